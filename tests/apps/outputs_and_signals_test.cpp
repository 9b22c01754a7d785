// Results are never lost or half-written, and an interrupted run says so: the --out directory
// is claimed before any work, replaced as a set, locked against a second run; every write and
// standard output are checked; SIGINT, SIGTERM and SIGHUP give 130/143 and a summary that
// records the stop.
#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "run_cambio.hpp"

namespace cambio {
namespace {

// GCC and clang say differently that AddressSanitizer is on.
#if defined(__SANITIZE_ADDRESS__)
constexpr bool kUnderAddressSanitizer = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kUnderAddressSanitizer = true;
#else
constexpr bool kUnderAddressSanitizer = false;
#endif
#else
constexpr bool kUnderAddressSanitizer = false;
#endif

namespace fs = std::filesystem;
using testing::run_cambio;

const std::string kQuickRun =
    "run tests/apps/data/sim_hold.yaml "
    "--set experiment.duration_s=0.2 ";

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

fs::path fresh_directory(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("cambio_outputs_test_" + name);
  fs::remove_all(dir);
  return dir;
}

std::set<std::string> names_in(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir)) names.insert(entry.path().filename());
  return names;
}

/// A shell command line run from the source tree, with $CAMBIO naming the built program;
/// stdout and stderr are captured unless the script redirects them.
testing::CommandResult run_in_shell(const std::string& script) {
  return testing::run_shell(std::string("cd '") + CAMBIO_SOURCE_DIR + "' && CAMBIO='" +
                            CAMBIO_BINARY_DIR + "/bin/cambio' && { " + script + "; } 2>&1");
}

nlohmann::json read_json(const fs::path& path) {
  std::ifstream file(path);
  return nlohmann::json::parse(file);
}

TEST(Outputs, ABadOutIsRefusedBeforeAnyWork) {
  const fs::path file = fresh_directory("a_file");
  std::ofstream(file) << "not a directory";
  const auto started = std::chrono::steady_clock::now();
  // A 60 s run: refused before it starts, or this test takes a minute.
  auto result = run_cambio(
      "run firmware_config/experiments/vergence_sphere.yaml --set experiment.duration_s=60 --out "
      "'" +
      file.string() + "'");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "is not a directory")) << result.output;
  EXPECT_LT(std::chrono::steady_clock::now() - started, std::chrono::seconds(20));

  result = run_cambio(kQuickRun + "--out ''");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "empty path")) << result.output;

  result = run_cambio(kQuickRun + "--out /proc/cambio_cannot_be_here");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "cannot create")) << result.output;
}

TEST(Outputs, ADirectoryHoldingFilesCambioDidNotWriteIsRefusedAndLeftAlone) {
  const fs::path dir = fresh_directory("foreign");
  fs::create_directories(dir);
  std::ofstream(dir / "thesis.tex") << "precious";
  const auto result = run_cambio(kQuickRun + "--out '" + dir.string() + "'");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "'thesis.tex', which no cambio run wrote")) << result.output;
  EXPECT_EQ(names_in(dir), (std::set<std::string>{"thesis.tex"})) << "nothing was added";
}

TEST(Outputs, ARunReplacesThePreviousRunsFilesAsASet) {
  const fs::path dir = fresh_directory("set");
  ASSERT_EQ(run_cambio(kQuickRun + "--out '" + dir.string() + "'").exit_code, 0);
  const std::set<std::string> first = names_in(dir);
  // A sim run with a stereo head also leaves its trace and plots (no key frames asked here).
  EXPECT_EQ(first, (std::set<std::string>{".cambio-lock", ".cambio-manifest.json", "left_eye.png",
                                          "right_eye.png", "summary.json", "trace.csv",
                                          "plot_gaze.png", "plot_joints.png"}));
  // Pretend the previous run also wrote a file this run will not: it must not stay behind.
  std::ofstream(dir / "overview.png") << "from an earlier run";
  nlohmann::json manifest = read_json(dir / ".cambio-manifest.json");
  manifest["files"].push_back("overview.png");
  std::ofstream(dir / ".cambio-manifest.json") << manifest.dump();

  const auto result =
      run_cambio(kQuickRun + "--set experiment.seed=7 --out '" + dir.string() + "'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(names_in(dir), first) << "the stale overview.png is gone, nothing else appeared";
  EXPECT_EQ(read_json(dir / "summary.json").at("seed"), 7) << "the new run's summary";
  EXPECT_EQ(read_json(dir / ".cambio-manifest.json").at("complete"), true);
  for (const auto& entry : fs::directory_iterator(dir.parent_path())) {
    EXPECT_FALSE(contains(entry.path().filename().string(), "cambio_outputs_test_set.cambio-"))
        << "a staging directory was left behind: " << entry.path();
  }
}

TEST(Outputs, ASecondRunIntoADirectoryAnotherRunHoldsIsRefusedAtOnce) {
  const fs::path dir = fresh_directory("locked");
  fs::create_directories(dir);
  const int fd = ::open((dir / ".cambio-lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);  // This test is "the other run".
  const auto result = run_cambio(kQuickRun + "--out '" + dir.string() + "'");
  ::close(fd);
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "being written by another cambio run")) << result.output;
  EXPECT_FALSE(fs::exists(dir / "summary.json"));
}

TEST(Outputs, AFullDiskIsAnErrorAndLeavesThePreviousSetIntact) {
  const fs::path dir = fresh_directory("full");
  ASSERT_EQ(run_cambio(kQuickRun + "--out '" + dir.string() + "'").exit_code, 0);
  const auto before = fs::file_size(dir / "left_eye.png");
  // Files larger than 64 KiB cannot be written (EFBIG, as on a full disk); SIGXFSZ ignored.
  const auto result = run_in_shell("trap '' XFSZ; ulimit -f 64; \"$CAMBIO\" " + kQuickRun +
                                   "--out '" + dir.string() + "'");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "write failed")) << result.output;
  EXPECT_FALSE(contains(result.output, "wrote ")) << result.output;
  EXPECT_EQ(fs::file_size(dir / "left_eye.png"), before) << "the previous set is untouched";
  EXPECT_EQ(read_json(dir / ".cambio-manifest.json").at("complete"), true);
}

TEST(Outputs, AFileSizeLimitIsAFailedWriteNotADeathBySigxfsz) {
  // ulimit -f 64: no file of the run may pass 64 KiB; trace.csv and the images do.
  const fs::path dir = fresh_directory("fsize");
  const auto result = run_in_shell(
      "ulimit -f 64; \"$CAMBIO\" run tests/apps/data/sim_hold.yaml "
      "--set experiment.duration_s=0.5 --out '" +
      dir.string() + "'");
  EXPECT_EQ(result.exit_code, 2) << "not 153 (SIGXFSZ): " << result.output;
  EXPECT_TRUE(contains(result.output, "File too large")) << result.output;
  EXPECT_FALSE(fs::exists(dir / "summary.json")) << "no partial set was put in place";
}

TEST(Outputs, RenderingUnderAnAddressSpaceLimitIsOutOfMemoryNotADeviceFault) {
  if (kUnderAddressSanitizer) {
    GTEST_SKIP() << "AddressSanitizer's shadow memory alone passes any such limit";
  }
  // ulimit -v 300000 (KiB: 307 MB): Mesa's software renderer, which maps about 1 GB, cannot start
  // although its packages are installed. Memory ran out: not a device's fault (3).
  const fs::path dir = fresh_directory("address_space");
  const auto result = run_in_shell(
      "ulimit -v 300000; \"$CAMBIO\" run tests/apps/data/sim_hold.yaml "
      "--set experiment.duration_s=0.2 --out '" +
      dir.string() + "'");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_TRUE(contains(result.output, "out of memory")) << result.output;
  EXPECT_TRUE(contains(result.output, "address-space limit (ulimit -v) is 307 MB"))
      << result.output;
  EXPECT_FALSE(fs::exists(dir / "summary.json")) << "nothing ran";
}

TEST(Outputs, AtEveryAddressSpaceLimitARunFinishesOrSaysItRanOutOfMemory) {
  if (kUnderAddressSanitizer) {
    GTEST_SKIP() << "AddressSanitizer's shadow memory alone passes any such limit";
  }
  // Between about 550 and 900 MB Mesa's software renderer fails in a different place from one run
  // to the next: MuJoCo's "could not allocate memory" (once a device fault, 3), an incomplete
  // framebuffer, or a segfault inside the driver (139). Whatever fails, a run either finishes or
  // says it ran out of memory (1), within a bounded time, and leaves nothing in the temporary
  // directory (the plotting process, which may be the one that dies, once left its own there).
  for (int limit_mb = 560; limit_mb <= 900; limit_mb += 20) {
    const fs::path dir = fresh_directory("address_space_" + std::to_string(limit_mb));
    const fs::path tmp = fresh_directory("address_space_tmp_" + std::to_string(limit_mb));
    fs::create_directories(tmp);
    const auto result = run_in_shell(
        "ulimit -v " + std::to_string(limit_mb * 1'000'000 / 1024) + "; TMPDIR='" + tmp.string() +
        "' timeout -s KILL 120 \"$CAMBIO\" run tests/apps/data/sim_hold.yaml "
        "--set experiment.duration_s=0.2 --out '" +
        dir.string() + "'");
    EXPECT_TRUE(fs::is_empty(tmp)) << limit_mb << " MB: " << fs::directory_iterator(tmp)->path();
    if (result.exit_code == 0) {
      EXPECT_TRUE(fs::exists(dir / "summary.json")) << limit_mb << " MB: " << result.output;
      continue;
    }
    EXPECT_EQ(result.exit_code, 1) << limit_mb << " MB: " << result.output;
    EXPECT_TRUE(contains(result.output, "out of memory")) << limit_mb << " MB: " << result.output;
  }
}

TEST(Outputs, AFailedWriteToStandardOutputIsAnError) {
  // stderr to the test, stdout to a device that is always full.
  auto result =
      run_in_shell("\"$CAMBIO\" check-config firmware_config/rigs/cambio.yaml 2>&1 >/dev/full");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_TRUE(contains(result.output, "cannot write to standard output")) << result.output;
  result =
      run_in_shell("\"$CAMBIO\" loop-bench --rate-hz 100 --duration-s 0.05 --json 2>&1 >/dev/full");
  EXPECT_EQ(result.exit_code, 2) << result.output;
}

TEST(Outputs, AReaderThatWentAwayIsAFailedWriteNotADeathBySigpipe) {
  // Standard output is a pipe whose read end is already closed: every write raises SIGPIPE.
  int fds[2];
  ASSERT_EQ(::pipe(fds), 0);
  ::close(fds[0]);
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    ::dup2(fds[1], STDOUT_FILENO);
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, STDERR_FILENO);
    const std::string cambio = std::string(CAMBIO_BINARY_DIR) + "/bin/cambio";
    const std::string rig = std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/rigs/cambio.yaml";
    ::execl(cambio.c_str(), cambio.c_str(), "check-config", rig.c_str(), nullptr);
    ::_exit(127);
  }
  ::close(fds[1]);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_FALSE(WIFSIGNALED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 2) << "status " << status;
}

/// Starts a long run, waits until it has started (its handlers are installed), sends `signal`.
testing::CommandResult interrupt_run(const std::string& signal, const fs::path& out) {
  const fs::path log = out.string() + ".log";
  // A log left by an earlier run would say "started" before this one has installed its handlers.
  fs::remove(log);
  return run_in_shell(
      "\"$CAMBIO\" run tests/apps/data/sim_hold.yaml "
      "--set experiment.duration_s=60 --out '" +
      out.string() + "' 2>'" + log.string() + "' & pid=$!; until grep -q 'executor' '" +
      log.string() + "' 2>/dev/null; do sleep 0.05; done; sleep 0.5; kill -" + signal +
      " $pid; wait $pid; status=$?; cat '" + log.string() + "'; exit $status");
}

TEST(Signals, AnInterruptedRunSaysSoInItsStatusItsSummaryAndItsProgress) {
  for (const auto& [signal, status, name] :
       {std::tuple{"INT", 130, "SIGINT"}, std::tuple{"TERM", 143, "SIGTERM"},
        std::tuple{"HUP", 143, "SIGHUP"}}) {
    const fs::path dir = fresh_directory(std::string("signal_") + signal);
    const auto result = interrupt_run(signal, dir);
    EXPECT_EQ(result.exit_code, status) << signal << ": " << result.output;
    EXPECT_TRUE(contains(result.output, std::string("interrupted by ") + name)) << result.output;
    EXPECT_FALSE(contains(result.output, "100%")) << "the progress claims a finished run";
    const nlohmann::json summary = read_json(dir / "summary.json");
    EXPECT_EQ(summary.at("outcome"), "interrupted");
    EXPECT_EQ(summary.at("stopped_by"), name);
    EXPECT_EQ(summary.at("exit_status"), status);
    EXPECT_LT(summary.at("simulated_s").get<double>(), 60.0);
    EXPECT_GT(summary.at("simulated_s").get<double>(), 0.0);
  }
}

TEST(Signals, ASecondSignalHurriesTheStopButNeverSkipsItNorTheResults) {
  // Two SIGTERMs at once, as `timeout` and impatient users send: before, the second ended the
  // program before the drives were disabled and before any file was written.
  const fs::path dir = fresh_directory("signal_twice");
  const fs::path log = dir.string() + ".log";
  fs::remove(log);
  const auto result = run_in_shell(
      "\"$CAMBIO\" run tests/apps/data/sim_hold.yaml --set experiment.duration_s=60 --out '" +
      dir.string() + "' 2>'" + log.string() + "' & pid=$!; until grep -q 'executor' '" +
      log.string() + "' 2>/dev/null; do sleep 0.05; done; sleep 0.5; kill -TERM $pid; " +
      "kill -TERM $pid; sleep 0.01; kill -TERM $pid; wait $pid; status=$?; cat '" + log.string() +
      "'; exit $status");
  EXPECT_EQ(result.exit_code, 143) << result.output;
  EXPECT_TRUE(contains(result.output, "interrupted by SIGTERM")) << result.output;
  const nlohmann::json summary = read_json(dir / "summary.json");
  EXPECT_EQ(summary.at("outcome"), "interrupted");
  EXPECT_EQ(summary.at("joint_loop").at("fault_latched_at_end"), false);
}

TEST(Signals, ASignalWhileTheRunIsBeingBuiltIsHeardAndSaysSo) {
  // The run claims --out, then builds (the world, the renderer; SDO on a CAN rig). Before, the
  // handlers came after the build: a signal then killed the program with no word.
  const fs::path dir = fresh_directory("signal_start");
  const auto result = run_in_shell(
      "\"$CAMBIO\" run tests/apps/data/sim_hold.yaml --set experiment.duration_s=60 --out '" +
      dir.string() + "' & pid=$!; until [ -e '" + dir.string() +
      "/.cambio-lock' ] || [ $((tries += 1)) -ge 2000 ]; do sleep 0.001; done; kill -INT $pid; "
      "wait $pid");
  EXPECT_EQ(result.exit_code, 130) << result.output;
  EXPECT_TRUE(contains(result.output, "interrupted by")) << result.output;
}

TEST(Signals, AConsoleAtATinyRealTimeFactorStopsAtOnce) {
  // --rtf 1e-6: each 10 ms slice of simulated time is 10,000 s of wall time. Before, SIGINT was
  // seen only when the slice's sleep ended.
  const fs::path log = fresh_directory("signal_console_rtf").string() + ".log";
  fs::remove(log);
  const auto started = std::chrono::steady_clock::now();
  const auto result = run_in_shell(
      "printf 'wait 1\\nstatus\\n' | \"$CAMBIO\" console "
      "firmware_config/experiments/vergence_sphere.yaml --rtf 1e-6 "
      ">'" +
      log.string() + "' 2>&1 & pid=$!; until grep -q 'executor' '" + log.string() +
      "' 2>/dev/null || [ $((tries += 1)) -ge 600 ]; do sleep 0.05; done; sleep 0.5; "
      "kill -INT $pid; wait $pid; status=$?; cat '" +
      log.string() + "'; exit $status");
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  EXPECT_EQ(result.exit_code, 130) << result.output;
  EXPECT_LT(wall_s, 20.0) << result.output;
}

TEST(Signals, AConsoleWaitingOnARealtimeRigStopsAtOnce) {
  // `wait 60` between two lines: the interrupt ends the wait and the run, not a minute later.
  const fs::path log = fresh_directory("signal_console").string() + ".log";
  fs::remove(log);
  const auto started = std::chrono::steady_clock::now();
  const auto result = run_in_shell(
      "printf 'wait 60\\nstatus\\n' | \"$CAMBIO\" console "
      "firmware_config/experiments/vergence_sphere.yaml "
      "--set experiment.executor=realtime >'" +
      log.string() + "' 2>&1 & pid=$!; until grep -q 'executor' '" + log.string() +
      "' 2>/dev/null || [ $((tries += 1)) -ge 600 ]; do sleep 0.05; done; sleep 0.5; "
      "kill -INT $pid; wait $pid; status=$?; "
      "cat '" +
      log.string() + "'; exit $status");
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  EXPECT_EQ(result.exit_code, 130) << result.output;
  EXPECT_LT(wall_s, 30.0) << result.output;
}

}  // namespace
}  // namespace cambio
