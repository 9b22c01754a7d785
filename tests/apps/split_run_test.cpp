#include <dds/dds.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <future>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "diagnostic_msgs/msg/DiagnosticArray.h"
#include "run_cambio.hpp"

// The stack split across two processes and across two network namespaces: `cambio run` with
// ros2.split: perception_remote on the "robot", `cambio node perception` on the "perception
// host", Cyclone DDS between them. Judged by the run's goals (the sim's ground truth) and its
// trace, not by the link's own counts alone.

namespace cambio {
namespace {

namespace fs = std::filesystem;
using testing::run_shell;

const std::string kCambio = std::string(CAMBIO_BINARY_DIR) + "/bin/cambio";
const std::string kExperiment =
    std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/experiments/vergence_sphere.yaml";

std::string read_text(const fs::path& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

nlohmann::json read_json(const fs::path& path) {
  std::ifstream file(path);
  return nlohmann::json::parse(file, nullptr, false);
}

// The trace's columns by name, one vector per column.
std::map<std::string, std::vector<double>> read_trace(const fs::path& path) {
  std::ifstream file(path);
  std::string line;
  std::getline(file, line);
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string name; std::getline(header, name, ',');) names.push_back(name);
  std::map<std::string, std::vector<double>> columns;
  while (std::getline(file, line)) {
    std::stringstream row(line);
    std::string cell;
    for (std::size_t k = 0; k < names.size() && std::getline(row, cell, ','); ++k) {
      char* end = nullptr;
      const double value = std::strtod(cell.c_str(), &end);
      columns[names[k]].push_back(end != cell.c_str() ? value : NAN);
    }
  }
  return columns;
}

std::string split_overrides(int domain, double duration_s) {
  return " --set experiment.executor=realtime --set experiment.duration_s=" +
         std::to_string(duration_s) +
         " --set 'experiment.ros2={domain_id: " + std::to_string(domain) +
         ", split: perception_remote, images_hz: 0}'";
}

class SplitRun : public ::testing::Test {
 protected:
  void SetUp() override {
    out_ = fs::temp_directory_path() / ("cambio_split_" + std::to_string(getpid()));
    fs::remove_all(out_);
    fs::create_directories(out_);
    domain_ = 1 + (getpid() + 57) % 200;
  }
  void TearDown() override { fs::remove_all(out_); }

  // Starts `command` in the background (its output in `log`); returns its process id.
  std::string start_background(const std::string& command, const fs::path& log) {
    const testing::CommandResult started =
        run_shell("(" + command + ") > '" + log.string() + "' 2>&1 & echo $!");
    EXPECT_EQ(started.exit_code, 0);
    std::string pid = started.output;
    while (!pid.empty() && (pid.back() == '\n' || pid.back() == ' ')) pid.pop_back();
    return pid;
  }

  fs::path out_;
  int domain_ = 0;
};

// The link's state as /diagnostics says it, read by a ROS 2 peer (this process) while it runs.
struct LinkDiagnostics {
  bool seen = false;
  std::uint8_t level = 255;
  std::map<std::string, std::string> values;
};

LinkDiagnostics read_link_diagnostics(int domain, const std::atomic<bool>& done) {
  LinkDiagnostics found;
  const dds_entity_t participant =
      dds_create_participant(static_cast<dds_domainid_t>(domain), nullptr, nullptr);
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 10);
  const dds_entity_t topic = dds_create_topic(
      participant, &diagnostic_msgs_msg_dds__DiagnosticArray__desc, "rt/diagnostics", qos, nullptr);
  const dds_entity_t reader = dds_create_reader(participant, topic, qos, nullptr);
  dds_delete_qos(qos);
  while (!done.load()) {
    void* samples[1] = {};
    dds_sample_info_t info;
    while (dds_take(reader, samples, &info, 1, 1) > 0) {
      const auto& array =
          *static_cast<const diagnostic_msgs_msg_dds__DiagnosticArray_*>(samples[0]);
      for (std::uint32_t k = 0; info.valid_data && k < array.status._length; ++k) {
        const diagnostic_msgs_msg_dds__DiagnosticStatus_& status = array.status._buffer[k];
        if (std::string(status.name) != "cambio: perception link") continue;
        found.seen = true;
        found.level = status.level;
        for (std::uint32_t v = 0; v < status.values._length; ++v) {
          found.values[status.values._buffer[v].key] = status.values._buffer[v].value;
        }
      }
      dds_return_loan(reader, samples, 1);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  dds_delete(participant);
  return found;
}

TEST_F(SplitRun, VergesWithTheSsmInAnotherProcess) {
  // The run, the node and this process's reader on loopback.
  const std::string localhost =
      std::string("file://") + CAMBIO_SOURCE_DIR + "/firmware_config/ros2/cyclonedds_localhost.xml";
  setenv("CYCLONEDDS_URI", localhost.c_str(), 1);
  const std::string uri = "CYCLONEDDS_URI=" + localhost + " ";
  const std::string node_pid =
      start_background(uri + "exec '" + kCambio + "' node perception '" + kExperiment +
                           "' --domain " + std::to_string(domain_),
                       out_ / "node.log");
  std::atomic<bool> run_done{false};
  auto diagnostics =
      std::async(std::launch::async, [&] { return read_link_diagnostics(domain_, run_done); });
  const testing::CommandResult run = run_shell(
      uri + "'" + kCambio + "' run '" + kExperiment + "'" + split_overrides(domain_, 2.0) +
      " --set experiment.ros2.diagnostics_hz=4 --out '" + (out_ / "run").string() + "' 2>&1");
  run_done = true;
  const LinkDiagnostics link_state = diagnostics.get();
  run_shell("kill -TERM " + node_pid + "; while kill -0 " + node_pid +
            " 2>/dev/null; do sleep 0.05; done");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  ASSERT_TRUE(link_state.seen) << "no 'cambio: perception link' status on /diagnostics";
  EXPECT_EQ(link_state.level, 0) << "the link was not OK while results came";
  EXPECT_GT(std::stoi(link_state.values.at("results_used")), 0);

  // The goals are the shipped experiment's, scored against the sim's truth.
  const nlohmann::json summary = read_json(out_ / "run" / "summary.json");
  ASSERT_TRUE(summary.is_object());
  EXPECT_TRUE(summary["passed"].get<bool>());
  EXPECT_LE(summary["metrics"]["true_gaze_error_deg"].get<double>(), 0.1);
  const nlohmann::json& link = summary["perception_link"];
  ASSERT_TRUE(link.is_object()) << summary.dump(2);
  // Most pairs came back as results the gaze used (a pair superseded in transit is not an error).
  EXPECT_GE(link["results_used"].get<double>(), 0.6 * link["pairs_sent"].get<double>());
  EXPECT_EQ(link["results_malformed"], 0);
  EXPECT_TRUE(link["outages"].empty()) << link.dump();
  EXPECT_LT(link["latency_median_ms"].get<double>(), 100.0);
  // Nothing ran the SSM on the robot: the node's counts are the run's results.
  const std::string node_log = read_text(out_ / "node.log");
  EXPECT_NE(node_log.find("stopped by SIGTERM"), std::string::npos) << node_log;
  EXPECT_NE(node_log.find("images (0 refused)"), std::string::npos) << node_log;
}

TEST_F(SplitRun, WhatCannotSplitIsRefusedAndASilentHostIsADeviceFault) {
  const std::string experiments = std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/experiments/";
  struct Case {
    std::string arguments;
    std::string expected;
  };
  const std::string split = " --set 'experiment.ros2={split: perception_remote}'";
  for (const Case& c : std::vector<Case>{
           {"run '" + kExperiment + "'" + split, "needs executor: realtime"},
           {"run '" + experiments + "attention_scan.yaml' --set experiment.executor=realtime" +
                split,
            "cannot host a behaviour"},
           {"run '" + experiments + "pan_tilt_hold.yaml'" + split, "needs task gaze"},
           {"run '" + kExperiment + "' --set 'experiment.ros2={split: perception_far}'",
            "perception_remote"},
           {"node perception '" + experiments + "pan_tilt_hold.yaml'", "has no stereo pair"},
           {"node perception '" + kExperiment + "' --domain 233", "--domain"},
           {"node behaviour '" + kExperiment + "'", "the node kinds are: perception"},
       }) {
    const testing::CommandResult result = testing::run_cambio(c.arguments);
    EXPECT_EQ(result.exit_code, 2) << c.arguments << "\n" << result.output;
    EXPECT_NE(result.output.find(c.expected), std::string::npos) << result.output;
  }
  // Nobody serves the domain: the run says so before anything moves, as a device fault.
  const testing::CommandResult alone = run_shell(
      "CYCLONEDDS_URI=file://" + std::string(CAMBIO_SOURCE_DIR) +
      "/firmware_config/ros2/cyclonedds_localhost.xml '" + kCambio + "' run '" + kExperiment + "'" +
      split_overrides(domain_, 1.0) + " --set experiment.ros2.host_wait_s=0.5 --out '" +
      (out_ / "alone").string() + "' 2>&1");
  EXPECT_EQ(alone.exit_code, 3) << alone.output;
  EXPECT_NE(alone.output.find("no perception host answered on ROS 2 domain " +
                              std::to_string(domain_) + " within 0.5"),
            std::string::npos)
      << alone.output;
  EXPECT_NE(alone.output.find("cambio node perception"), std::string::npos) << alone.output;
}

bool have_network_namespaces() {
  return geteuid() == 0 && run_shell("ip netns list > /dev/null 2>&1").exit_code == 0;
}

// Two network namespaces joined by a veth pair, created here and removed when done.
class TwoHosts {
 public:
  explicit TwoHosts(int tag) : tag_(std::to_string(tag)) {
    robot_ = "cambio_robot_" + tag_;
    host_ = "cambio_host_" + tag_;
    robot_if_ = "cr" + tag_;
    host_if_ = "ch" + tag_;
    const std::string commands =
        "ip netns add " + robot_ + " && ip netns add " + host_ + " && ip link add " + robot_if_ +
        " type veth peer name " + host_if_ + " && ip link set " + robot_if_ + " netns " + robot_ +
        " && ip link set " + host_if_ + " netns " + host_ + " && ip -n " + robot_ +
        " addr add 10.231.7.1/24 dev " + robot_if_ + " && ip -n " + host_ +
        " addr add 10.231.7.2/24 dev " + host_if_ + " && ip -n " + robot_ + " link set " +
        robot_if_ + " up && ip -n " + host_ + " link set " + host_if_ + " up && ip -n " + robot_ +
        " link set lo up && ip -n " + host_ + " link set lo up";
    made_ = run_shell(commands + " 2>&1").exit_code == 0;
  }
  ~TwoHosts() {
    run_shell("ip netns del " + robot_ + " 2>/dev/null; ip netns del " + host_ + " 2>/dev/null");
  }
  bool made() const { return made_; }
  // A command's prefix to run in either: Cyclone on the veth alone, the other end its one peer,
  // through the shipped configuration for two hosts.
  std::string in_robot() const { return in(robot_, robot_if_, "10.231.7.2"); }
  std::string in_host() const { return in(host_, host_if_, "10.231.7.1"); }
  bool set_link(bool up) const {
    return run_shell("ip -n " + robot_ + " link set " + robot_if_ + (up ? " up" : " down"))
               .exit_code == 0;
  }

 private:
  static std::string in(const std::string& space, const std::string& interface,
                        const std::string& peer) {
    return "ip netns exec " + space + " env CYCLONEDDS_URI=file://" + CAMBIO_SOURCE_DIR +
           "/firmware_config/ros2/cyclonedds_peer.xml CAMBIO_DDS_INTERFACE=" + interface +
           " CAMBIO_DDS_PEER=" + peer + " ";
  }
  std::string tag_, robot_, host_, robot_if_, host_if_;
  bool made_ = false;
};

TEST_F(SplitRun, AcrossTwoNetworkNamespacesTheRobotHoldsWhileTheLinkIsCutAndResumes) {
  if (!have_network_namespaces()) {
    GTEST_SKIP() << "needs root and iproute2's `ip netns` (a second host made of a namespace)";
  }
  const TwoHosts hosts(getpid() % 100000);
  ASSERT_TRUE(hosts.made()) << "could not make the namespaces and their veth pair";
  const std::string node_pid =
      start_background(hosts.in_host() + "'" + kCambio + "' node perception '" + kExperiment +
                           "' --domain " + std::to_string(domain_),
                       out_ / "node.log");
  const fs::path run_log = out_ / "run.log";
  auto run = std::async(std::launch::async, [&] {
    return run_shell(hosts.in_robot() + "'" + kCambio + "' run '" + kExperiment + "'" +
                     split_overrides(domain_, 4.0) +
                     " --set 'experiment.ros2.link_timeout_s=0.3' --out '" +
                     (out_ / "run").string() + "' > '" + run_log.string() + "' 2>&1");
  });
  // Once the run is 0.8 s in (its progress decile 20%; verged by then: it settles in about
  // 0.3 s), the cable is pulled for a second.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (read_text(run_log).find("run:  20%") == std::string::npos &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(hosts.set_link(false));
  std::this_thread::sleep_for(std::chrono::milliseconds(1000));
  ASSERT_TRUE(hosts.set_link(true));
  const testing::CommandResult result = run.get();
  run_shell("kill -TERM " + node_pid + " 2>/dev/null");
  const std::string log = read_text(run_log);
  ASSERT_EQ(result.exit_code, 0) << log << read_text(out_ / "node.log");

  // Reported: one outage, lost within the timeout of the cut, back after it.
  const nlohmann::json summary = read_json(out_ / "run" / "summary.json");
  const nlohmann::json& outages = summary["perception_link"]["outages"];
  ASSERT_EQ(outages.size(), 1u) << summary["perception_link"].dump();
  const double lost_s = outages[0]["lost_s"].get<double>();
  ASSERT_TRUE(outages[0]["back_s"].is_number()) << "the link never came back";
  const double back_s = outages[0]["back_s"].get<double>();
  EXPECT_GT(back_s - lost_s, 0.4);
  EXPECT_LT(back_s - lost_s, 2.5);
  EXPECT_NE(log.find("perception link lost"), std::string::npos);
  EXPECT_NE(log.find("perception link back"), std::string::npos);
  EXPECT_TRUE(summary["passed"].get<bool>()) << summary["goals"].dump();

  // Held: while no result came, no measurement reached the gaze (the newest disparity it had
  // stayed the one from before the cut) and both eyes stayed on the target by the sim's truth
  // (the verging one included: held, not drifting). Resumed: new measurements after the link
  // came back.
  const auto trace = read_trace(out_ / "run" / "trace.csv");
  const std::vector<double>& t = trace.at("time_s");
  const std::vector<double>& verging_error = trace.at("verging_gaze_error_deg");
  const std::vector<double>& error = trace.at("true_gaze_error_deg");
  const std::vector<double>& disparity = trace.at("disparity_px");
  double worst_error_deg = 0.0;
  double worst_verging_error_deg = 0.0;
  std::set<double> disparities_during;
  std::set<double> disparities_after;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k] > lost_s + 0.05 && t[k] < back_s) {
      worst_error_deg = std::max(worst_error_deg, error[k]);
      worst_verging_error_deg = std::max(worst_verging_error_deg, verging_error[k]);
      disparities_during.insert(disparity[k]);
    }
    if (t[k] > back_s + 0.05) disparities_after.insert(disparity[k]);
  }
  EXPECT_EQ(disparities_during.size(), 1u) << "measurements arrived while the link was down";
  EXPECT_LT(worst_error_deg, 0.1);
  EXPECT_LT(worst_verging_error_deg, 0.1);
  EXPECT_GE(disparities_after.size(), 3u) << "no new measurements after the link came back";
}

}  // namespace
}  // namespace cambio
