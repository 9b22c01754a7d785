#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "../../apps/run_cambio.hpp"

// `cambio export urdf` read back by urdfdom's own parser (check_urdf, Debian's liburdfdom-tools),
// the one RViz and robot_state_publisher use.

namespace cambio {
namespace {

struct ParsedUrdf {
  int exit_code = -1;
  std::string output;
};

ParsedUrdf export_and_parse(const std::string& rig) {
  const std::string path = std::filesystem::temp_directory_path() /
                           ("cambio_urdf_" + rig + "_" + std::to_string(getpid()) + ".urdf");
  const testing::CommandResult exported =
      testing::run_cambio("export urdf " + rig + " > '" + path + "'", testing::Capture::kStdout);
  EXPECT_EQ(exported.exit_code, 0) << exported.output;
  const testing::CommandResult parsed = testing::run_shell("check_urdf '" + path + "' 2>&1");
  std::filesystem::remove(path);
  return {parsed.exit_code, parsed.output};
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(UrdfExport, TheShippedRobotParsesWithItsTreeAsTheRigDescribesIt) {
  const ParsedUrdf urdf = export_and_parse("cambio");
  ASSERT_EQ(urdf.exit_code, 0) << urdf.output;
  EXPECT_NE(urdf.output.find("robot name is: cambio"), std::string::npos) << urdf.output;
  // base's children: the two shoulders and the neck; 15 joints and 2 optical frames below it.
  EXPECT_NE(urdf.output.find("root Link: base has 3 child(ren)"), std::string::npos);
  EXPECT_EQ(count(urdf.output, "):  "), 17u) << urdf.output;  // One "child(k):  name" each.
  EXPECT_NE(urdf.output.find("child(1):  left_eye_optical_frame"), std::string::npos);
}

TEST(UrdfExport, ThePanTiltParsesToo) {
  const ParsedUrdf urdf = export_and_parse("pan_tilt");
  ASSERT_EQ(urdf.exit_code, 0) << urdf.output;
  EXPECT_NE(urdf.output.find("root Link: base"), std::string::npos) << urdf.output;
}

TEST(UrdfExport, ARigThatDoesNotLoadIsBadInput) {
  const testing::CommandResult result = testing::run_cambio("export urdf /nonexistent/rig.yaml");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("rig.yaml"), std::string::npos) << result.output;
  EXPECT_EQ(testing::run_cambio("export sdf cambio").exit_code, 2);
}

}  // namespace
}  // namespace cambio
