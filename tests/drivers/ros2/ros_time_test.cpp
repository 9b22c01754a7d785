#include "cambio/ros2/ros_time.hpp"

#include <gtest/gtest.h>

namespace cambio::ros2 {
namespace {

TEST(RosTime, SplitsNanosecondsIntoSecondsAndTheRest) {
  const RosTime t = to_ros_time(2'000'000'001);
  EXPECT_EQ(t.sec, 2);
  EXPECT_EQ(t.nanosec, 1u);
  const RosTime shifted = to_ros_time(999'999'999, 1);
  EXPECT_EQ(shifted.sec, 1);
  EXPECT_EQ(shifted.nanosec, 0u);
}

TEST(RosTime, ClampsWhatInt32SecondsCannotSay) {
  const RosTime before_epoch = to_ros_time(-5, 0);
  EXPECT_EQ(before_epoch.sec, 0);
  EXPECT_EQ(before_epoch.nanosec, 0u);
  const RosTime after_2038 = to_ros_time(INT64_MAX, INT64_MAX);
  EXPECT_EQ(after_2038.sec, INT32_MAX);
  EXPECT_EQ(after_2038.nanosec, 999'999'999u);
}

}  // namespace
}  // namespace cambio::ros2
