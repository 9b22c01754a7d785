// End to end: `cambio check-config` exits 0 on the shipped rigs and 2 on bad input, printing
// each problem on its own line.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "../scoped_environment_variable.hpp"
#include "cambio/config/shipped_config.hpp"

namespace {

struct CommandRun {
  int exit_code = -1;
  std::string output;  ///< stdout and stderr together.
};

CommandRun run_cambio(const std::string& arguments) {
  const std::string command =
      std::string(CAMBIO_BINARY_DIR) + "/bin/cambio check-config " + arguments + " 2>&1";
  CommandRun run;
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) return run;
  std::array<char, 4096> buffer{};
  while (const std::size_t n = std::fread(buffer.data(), 1, buffer.size(), pipe)) {
    run.output.append(buffer.data(), n);
  }
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

std::string shipped(const std::string& name) {
  return cambio::config::find_shipped_config("rigs/" + name);
}

TEST(CheckConfigCli, ShippedRigsPassWithASummary) {
  const CommandRun cambio = run_cambio(shipped("cambio.yaml"));
  EXPECT_EQ(cambio.exit_code, 0) << cambio.output;
  EXPECT_NE(cambio.output.find("rig cambio"), std::string::npos) << cambio.output;
  EXPECT_NE(cambio.output.find("neck_pan"), std::string::npos) << cambio.output;
  EXPECT_NE(cambio.output.find("[-90.0, 90.0] deg"), std::string::npos) << cambio.output;
  EXPECT_NE(cambio.output.find("1000 Hz"), std::string::npos) << cambio.output;
  EXPECT_NE(cambio.output.find("640x480"), std::string::npos) << cambio.output;

  const CommandRun pan_tilt = run_cambio(shipped("pan_tilt.yaml"));
  EXPECT_EQ(pan_tilt.exit_code, 0) << pan_tilt.output;
}

TEST(CheckConfigCli, OverrideIsApplied) {
  const CommandRun run = run_cambio(shipped("pan_tilt.yaml") + " --set loops.joint.rate_hz=250");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("250 Hz"), std::string::npos) << run.output;
}

TEST(CheckConfigCli, PrintsEachBussLoadWithItsGroupsAndRates) {
  const CommandRun run =
      run_cambio(shipped("cambio.yaml") +
                 " --set groups.head.backend=socketcan --set groups.left_arm.backend=socketcan "
                 "--set groups.right_arm.backend=socketcan --set can_buses.can2.interface=nocan7");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  // rigs/cambio.yaml's comment works these out: 1205 bits per cycle for five drives.
  for (const std::string text :
       {"  can0: interface can0, 1000 kbit/s, load 48.5% (485250 bit/s)\n"
        "    head: 5 drives at 400 Hz, 1205 bits per cycle + heartbeats: 485250 bit/s\n",
        "  can2: interface nocan7, 1000 kbit/s, load 30.4% (304500 bit/s)\n"
        "    right_arm: 5 drives at 250 Hz, 1205 bits per cycle + heartbeats: 304500 bit/s\n"
        "    interface nocan7 not present here: bit rate not checked\n",
        "left_arm: backend socketcan, joint loop 250 Hz, CAN bus can1",
        "head: backend socketcan, joint loop 400 Hz (loops.joint), CAN bus can0"}) {
    EXPECT_NE(run.output.find(text), std::string::npos) << text << "\n" << run.output;
  }
  const CommandRun sim = run_cambio(shipped("pan_tilt.yaml"));
  EXPECT_NE(sim.output.find("  can0: interface can0, 1000 kbit/s, no socketcan groups\n"),
            std::string::npos)
      << sim.output;
}

TEST(CheckConfigCli, AnOverloadedBusNamesTheGroupToSlowDown) {
  const CommandRun run = run_cambio(shipped("pan_tilt.yaml") +
                                    " --set groups.pan_tilt.backend=socketcan"
                                    " --set can_buses.can0.bitrate_bit_s=500000");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("can_buses.can0.bitrate_bit_s: expected a bitrate that carries the "
                            "joint loops' CANopen traffic within 60% (pan_tilt 2 drives at 1000 "
                            "Hz: 516300 bit/s worst case)"),
            std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("set groups.pan_tilt.rate_hz to at most 580 Hz"), std::string::npos)
      << run.output;
}

TEST(CheckConfigCli, ABackendThisBuildDoesNotCarryIsRefusedWithTheNamesItDoes) {
  const CommandRun run = run_cambio(shipped("pan_tilt.yaml") +
                                    " --set groups.pan_tilt.backend=ethercat"
                                    " --set cameras.camera.backend=gige");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  for (const char* expected :
       {"groups.pan_tilt.backend: backend 'ethercat' is not a known backend (available: sim, "
        "socketcan, v4l2)",
        "cameras.camera.backend: backend 'gige' is not a known backend"}) {
    EXPECT_NE(run.output.find(expected), std::string::npos) << expected << "\n" << run.output;
  }
}

TEST(CheckConfigCli, BadFileExitsTwoWithEveryProblem) {
  const auto path = std::filesystem::temp_directory_path() / "cambio_check_config_bad.yaml";
  int bogus_line = 0;  // The line after the shipped file's last.
  {
    std::ifstream in(shipped("pan_tilt.yaml"));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string from = "max_velocity_rad_s: 3.0";
    text.replace(text.find(from), from.size(), "max_velocity_rad_s: fast");
    bogus_line = static_cast<int>(std::count(text.begin(), text.end(), '\n')) + 1;
    text += "bogus_key: 1\n";
    std::ofstream out(path);
    out << text;
  }
  const CommandRun run = run_cambio(path.string());
  std::filesystem::remove(path);
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find(path.string() + ":13:25: joints.pan.max_velocity_rad_s: expected a "
                                            "number > 0, found \"fast\"\n"),
            std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find(path.string() + ":" + std::to_string(bogus_line) +
                            ":1: bogus_key: unknown key"),
            std::string::npos)
      << run.output;
}

// The render device the sim would take: the rig's, or CAMBIO_EGL_DEVICE's, which must be one
// the loader would accept.
TEST(CheckConfigCli, SaysWhichRenderDeviceAndWhoChoseIt) {
  CommandRun run = run_cambio(shipped("pan_tilt.yaml") + " --set sim.render_device=surfaceless");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("sim physics 1000 Hz, render device surfaceless; "), std::string::npos)
      << run.output;
  {
    const cambio::testing::ScopedEnvironmentVariable variable("CAMBIO_EGL_DEVICE", "1");
    run = run_cambio(shipped("pan_tilt.yaml"));
  }
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("render device 1 (CAMBIO_EGL_DEVICE; the rig says auto)"),
            std::string::npos)
      << run.output;
  {
    const cambio::testing::ScopedEnvironmentVariable variable("CAMBIO_EGL_DEVICE", "first");
    run = run_cambio(shipped("pan_tilt.yaml"));
  }
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("environment: CAMBIO_EGL_DEVICE: expected auto, surfaceless or an "
                            "EGL device index (0, 1, ...), found \"first\""),
            std::string::npos)
      << run.output;
}

TEST(CheckConfigCli, BadOverrideExitsTwo) {
  const CommandRun bad_value =
      run_cambio(shipped("pan_tilt.yaml") + " --set loops.joint.rate_hz=0");
  EXPECT_EQ(bad_value.exit_code, 2) << bad_value.output;
  EXPECT_NE(bad_value.output.find("--set: loops.joint.rate_hz: expected a number"),
            std::string::npos)
      << bad_value.output;
  const CommandRun malformed = run_cambio(shipped("pan_tilt.yaml") + " --set loops.joint.rate_hz");
  EXPECT_EQ(malformed.exit_code, 2) << malformed.output;
  EXPECT_NE(malformed.output.find("(no '=')"), std::string::npos) << malformed.output;
}

TEST(CheckConfigCli, MissingFileExitsTwo) {
  const CommandRun run = run_cambio("/nonexistent/rig.yaml");
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("/nonexistent/rig.yaml: cannot read the file"), std::string::npos)
      << run.output;
}

TEST(CheckConfigCli, MissingArgumentAndHelp) {
  EXPECT_EQ(run_cambio("").exit_code, 2);
  const CommandRun help = run_cambio("--help");
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("--set"), std::string::npos) << help.output;
}

}  // namespace
