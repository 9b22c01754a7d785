// Pairing two free-running cameras by their stamps (drivers/v4l2/src/frame_pairing.cpp).

#include "cambio/v4l2/frame_pairing.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace cambio::v4l2 {
namespace {

constexpr std::int64_t kPeriod = 33'333'333;  // 30 Hz
constexpr std::int64_t kHalf = kPeriod / 2;

TEST(V4l2FramePairing, TheNewestPairWithinHalfAPeriod) {
  // Right runs 10 ms behind left: left 0, P; right 10 ms, P + 10 ms.
  const std::vector<std::int64_t> left = {0, kPeriod};
  const std::vector<std::int64_t> right = {10'000'000, kPeriod + 10'000'000};
  const auto pair = choose_pair(left, right, kHalf);
  ASSERT_TRUE(pair);
  EXPECT_EQ(pair->left, 1u);
  EXPECT_EQ(pair->right, 1u);
  EXPECT_EQ(pair->skew_ns, 10'000'000);
}

TEST(V4l2FramePairing, APhaseOverHalfAPeriodPairsWithTheOtherNeighbour) {
  // Right 25 ms after left's frames: its newest (P + 25) is nearer left's next frame than this
  // one, but that has not come yet; right's P + 25 - P = 25 ms is over the bound, so the pair
  // is left P with right's frame 8.3 ms before it.
  const std::vector<std::int64_t> left = {0, kPeriod};
  const std::vector<std::int64_t> right = {25'000'000, kPeriod + 25'000'000};
  const auto pair = choose_pair(left, right, kHalf);
  ASSERT_TRUE(pair);
  EXPECT_EQ(pair->left, 1u);
  EXPECT_EQ(pair->right, 0u);
  EXPECT_EQ(pair->skew_ns, kPeriod - 25'000'000);
}

TEST(V4l2FramePairing, NoPairWhenEveryCombinationIsTooFarApart) {
  const std::vector<std::int64_t> left = {0};
  const std::vector<std::int64_t> right = {kHalf + 1};
  EXPECT_FALSE(choose_pair(left, right, kHalf));
  EXPECT_FALSE(choose_pair(left, {}, kHalf));
}

TEST(V4l2FramePairing, TheBoundIsInclusive) {
  const std::vector<std::int64_t> left = {0};
  const std::vector<std::int64_t> right = {kHalf};
  const auto pair = choose_pair(left, right, kHalf);
  ASSERT_TRUE(pair);
  EXPECT_EQ(pair->skew_ns, kHalf);
}

TEST(V4l2FramePairing, AmongPairsAsNewTheClosest) {
  // Both pairs' older frame is left's 100; right's 101 is closer than 110.
  const std::vector<std::int64_t> left = {100};
  const std::vector<std::int64_t> right = {101, 110};
  const auto pair = choose_pair(left, right, kHalf);
  ASSERT_TRUE(pair);
  EXPECT_EQ(pair->right, 0u);
}

}  // namespace
}  // namespace cambio::v4l2
