// Tests of `--set key.path=value` overrides (firmware_config/src/config_document.cpp).
#include <gtest/gtest.h>

#include <numbers>

#include "cambio/config/rig_loader.hpp"
#include "rig_test_support.hpp"

namespace cambio::config {
namespace {

using test::describe;
using test::issues_of;
using test::small_rig;

std::vector<ConfigOverride> sets(std::initializer_list<std::string_view> texts) {
  std::vector<ConfigOverride> overrides;
  for (const auto text : texts) overrides.push_back(parse_override(text));
  return overrides;
}

std::vector<ConfigIssue> parse_issues(std::string_view text) {
  try {
    parse_override(text);
  } catch (const ConfigError& error) {
    return error.issues();
  }
  ADD_FAILURE() << "expected " << text << " to be refused";
  return {};
}

TEST(ParseOverride, SplitsAtTheFirstEquals) {
  const ConfigOverride o = parse_override("rig.name=a=b");
  EXPECT_EQ(o.key_path, "rig.name");
  EXPECT_EQ(o.value, "a=b");
}

TEST(ParseOverride, RefusesMalformedText) {
  const auto no_equals = parse_issues("loops.joint.rate_hz");
  ASSERT_EQ(no_equals.size(), 1u);
  EXPECT_EQ(no_equals[0].to_string(),
            "--set: expected key.path=value, found \"loops.joint.rate_hz\" (no '=')");
  const auto empty_path = parse_issues("=5");
  ASSERT_EQ(empty_path.size(), 1u);
  EXPECT_EQ(empty_path[0].to_string(),
            "--set: expected key.path=value, found \"=5\" (empty key path)");
  const auto empty_name = parse_issues("loops..rate_hz=5");
  ASSERT_EQ(empty_name.size(), 1u);
  EXPECT_EQ(empty_name[0].file, "--set");
  EXPECT_NE(empty_name[0].message.find("an empty name"), std::string::npos);
  EXPECT_EQ(parse_issues("loops.=5").size(), 1u);
}

TEST(Override, ChangesAValue) {
  const RigConfig rig =
      load_rig_from_string(small_rig(), "test.yaml", sets({"joints.pan.max_velocity_rad_s=3.5"}));
  EXPECT_EQ(rig.find_joint("pan")->max_velocity_rad_s, 3.5);
}

TEST(Override, ParsesTheValueAsYaml) {
  const RigConfig rig = load_rig(
      test::shipped_rig_path("cambio.yaml"),
      sets({"cameras.left_eye.origin_xyz_m=[0.03,0,0]", "joints.neck_pan.max_position_deg=60"}));
  EXPECT_EQ(rig.find_camera("left_eye")->mount.xyz_m, (std::array<double, 3>{0.03, 0.0, 0.0}));
  EXPECT_DOUBLE_EQ(rig.find_joint("neck_pan")->max_position_rad, std::numbers::pi / 3);
}

TEST(Override, CreatesMissingMaps) {
  // pan_tilt.yaml has no loops.
  const RigConfig rig = load_rig(test::shipped_rig_path("pan_tilt.yaml"),
                                 sets({"loops.joint.rate_hz=500", "sim.physics_rate_hz=2000"}));
  EXPECT_EQ(rig.find_loop("joint")->rate_hz, 500.0);
  EXPECT_EQ(rig.sim.physics_rate_hz, 2000.0);
}

TEST(Override, IndexesAList) {
  const RigConfig rig = load_rig(test::shipped_rig_path("cambio.yaml"),
                                 sets({"cameras.right_eye.principal_point_px.0=300"}));
  EXPECT_EQ(rig.find_camera("right_eye")->principal_x_px, 300.0);
}

TEST(Override, AStarSetsTheKeyUnderEveryEntryTheFileHas) {
  // Both eyes at 320x240 with the same field of view: four --sets instead of eight. The last one
  // changes the right eye's list alone: each eye got a copy of the value, not a shared node.
  const RigConfig rig =
      load_rig(test::shipped_rig_path("cambio.yaml"),
               sets({"cameras.*.width_px=320", "cameras.*.height_px=240",
                     "cameras.*.focal_px=277.128", "cameras.*.principal_point_px=[159.5,119.5]",
                     "cameras.right_eye.principal_point_px.0=160"}));
  for (const char* name : {"left_eye", "right_eye"}) {
    const auto* camera = rig.find_camera(name);
    ASSERT_NE(camera, nullptr) << name;
    EXPECT_EQ(camera->width_px, 320) << name;
    EXPECT_EQ(camera->height_px, 240) << name;
    EXPECT_EQ(camera->focal_x_px, 277.128) << name;
    EXPECT_EQ(camera->principal_y_px, 119.5) << name;
  }
  EXPECT_EQ(rig.find_camera("left_eye")->principal_x_px, 159.5);
  EXPECT_EQ(rig.find_camera("right_eye")->principal_x_px, 160.0);
}

TEST(Override, EachKeyAStarReachesIsCheckedAndNamedOnItsOwn) {
  const auto issues = issues_of(small_rig(), sets({"joints.*.max_velocity_rad_s=fast"}));
  ASSERT_EQ(issues.size(), 2u) << describe(issues);
  EXPECT_EQ(issues[0].to_string(),
            "--set: joints.pan.max_velocity_rad_s: expected a number > 0, found \"fast\"");
  EXPECT_EQ(issues[1].to_string(),
            "--set: joints.tilt.max_velocity_rad_s: expected a number > 0, found \"fast\"");
}

TEST(Override, AStarThatMatchesNothingIsRefusedSayingWhere) {
  const auto missing = issues_of(small_rig(), sets({"arms.*.reach_m=1"}));
  ASSERT_EQ(missing.size(), 1u) << describe(missing);
  EXPECT_EQ(missing[0].to_string(),
            "--set: arms.*.reach_m: '*' matches nothing: the document has no arms");
  const auto scalar = issues_of(small_rig(), sets({"rig.name.*=x"}));
  ASSERT_EQ(scalar.size(), 1u) << describe(scalar);
  EXPECT_EQ(scalar[0].key_path, "rig.name.*");
  EXPECT_NE(scalar[0].message.find("'*' matches nothing: rig.name is "), std::string::npos)
      << scalar[0].message;
}

TEST(Override, InvalidValueIsReportedAgainstSet) {
  const auto issues = issues_of(small_rig(), sets({"joints.pan.max_velocity_rad_s=fast"}));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].to_string(),
            "--set: joints.pan.max_velocity_rad_s: expected a number > 0, found \"fast\"");
}

TEST(Override, UnknownKeyIsReportedAgainstSetWithASuggestion) {
  const auto issues = issues_of(small_rig(), sets({"joints.pan.max_velocty_rad_s=3"}));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].file, "--set");
  EXPECT_EQ(issues[0].key_path, "joints.pan.max_velocty_rad_s");
  EXPECT_NE(issues[0].message.find("did you mean \"max_velocity_rad_s\"?"), std::string::npos);
}

TEST(Override, ANewMapIsCheckedLikeTheFile) {
  const auto issues = issues_of(small_rig(), sets({"cameras.eye.bogus={a: 1}"}));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].to_string(),
            "--set: cameras.eye.bogus: unknown key \"bogus\"; expected one of "
            "backend, buffer_count, controls, device, distortion, focal_px, focal_x_px, "
            "focal_y_px, format, frame_rate_hz, height_px, image_noise_std, origin_rpy_deg, "
            "origin_rpy_rad, origin_xyz_m, parent, pixel_format, principal_point_px, "
            "sim_foveation, width_px");
}

TEST(Override, ThroughAScalarIsRefused) {
  const auto issues = issues_of(small_rig(), sets({"rig.name.first=x"}));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].to_string(),
            "--set: rig.name.first: cannot set first under rig.name: rig.name is the value "
            "\"test\", not a map");
}

TEST(Override, UnparsableValueIsRefused) {
  const auto issues = issues_of(small_rig(), sets({"joints.pan.axis=[0, 0"}));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].file, "--set");
  EXPECT_EQ(issues[0].key_path, "joints.pan.axis");
  EXPECT_NE(issues[0].message.find("expected a YAML value"), std::string::npos);
}

TEST(Override, FileAndOverrideProblemsComeTogether) {
  const auto issues =
      issues_of(test::small_rig_with(31, "    focal_px: 0"), sets({"loops.joint.rate_hz=0"}));
  ASSERT_EQ(issues.size(), 2u) << describe(issues);
  EXPECT_EQ(issues[0].file, "--set");
  EXPECT_EQ(issues[0].key_path, "loops.joint.rate_hz");
  EXPECT_EQ(issues[1].to_string(),
            "test.yaml:31:15: cameras.eye.focal_px: expected a number > 0, found 0");
}

TEST(Override, ConsistencyChecksSeeTheOverriddenValue) {
  // The override moves the lower limit above the file's upper limit.
  const auto issues = issues_of(small_rig(), sets({"joints.pan.min_position_deg=120"}));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].file, "--set");
  EXPECT_EQ(issues[0].key_path, "joints.pan.min_position_deg");
}

// ---------------------------------------------------------------------------------------------
// Overrides that used to mislead

TEST(Override, ATypoInAnEntrysNameIsOneIssueWithASuggestion) {
  // It used to make up joint "tlit" and report each key it lacks, with no "did you mean".
  const auto issues = issues_of(small_rig(), sets({"joints.tlit.max_velocity_rad_s=3"}));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].to_string(),
            "--set: joints.tlit: --set made up \"tlit\", which the file does not have, and it "
            "lacks group, axis, min_position_deg, max_position_deg, max_acceleration_rad_s2; "
            "did you mean \"tilt\"?");
  // With no close name, the names the file has.
  const auto far = issues_of(small_rig(), sets({"joints.elbow.max_velocity_rad_s=3"}));
  ASSERT_EQ(far.size(), 1u) << describe(far);
  EXPECT_NE(far[0].message.find("; the file has pan, tilt"), std::string::npos)
      << far[0].to_string();
}

TEST(Override, AMapItMakesUpThatIsCompleteIsKept) {
  // The small rig has no loops section: --set may add one.
  const RigConfig rig =
      load_rig_from_string(small_rig(), "test.yaml", sets({"loops.joint.rate_hz=250"}));
  EXPECT_EQ(rig.find_loop("joint")->rate_hz, 250.0);
  // And its own problems are reported as such, against --set.
  const auto issues = issues_of(small_rig(), sets({"loops.joint.rate_hz=0"}));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].file, "--set");
  EXPECT_NE(issues[0].message.find("expected a number in [0.1, 100000]"), std::string::npos);
}

TEST(Override, AValueOfSeveralDocumentsIsRefused) {
  // YAML::Load read the first document only: rate_hz became 500, silently.
  const auto issues = issues_of(small_rig(), sets({"loops.joint.rate_hz=500\n---\n100"}));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].to_string(),
            "--set: loops.joint.rate_hz: expected a YAML value, found \"500\\n---\\n100\" "
            "(expected one YAML document, found a second (a line '---' starts it))");
}

TEST(Override, AHugeListIndexIsRefusedAsOutOfRange) {
  // std::stoul threw std::out_of_range, past every ConfigError handler.
  const auto issues =
      issues_of(small_rig(), sets({"groups.head.joints.99999999999999999999999=pan"}));
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].to_string(),
            "--set: groups.head.joints.99999999999999999999999: cannot set item "
            "99999999999999999999999 of groups.head.joints: the list has 2 items");
}

TEST(Override, AValueIsBoundedInSize) {
  const std::string value(kMaxOverrideValueBytes + 1, '1');
  const auto issues = issues_of(small_rig(), {ConfigOverride{"rig.name", value}});
  ASSERT_EQ(issues.size(), 1u) << describe(issues);
  EXPECT_EQ(issues[0].to_string(),
            "--set: rig.name: expected a value of at most 65536 bytes (a number, a list, a map of "
            "a few keys), found 65537 bytes");
}

}  // namespace
}  // namespace cambio::config
