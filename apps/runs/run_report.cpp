#include "run_report.hpp"

#include <iostream>
#include <string>

namespace cambio::app {

namespace {

void print_device_counts(const MainJobResult& result) {
  std::cout << "camera frames grabbed: " << result.camera_frames << " (" << result.stereo_pairs
            << " stereo pairs, " << result.mismatched_stereo_pairs
            << " refused for mismatched stamps)"
            << ", joint-loop holds: " << result.startup_hold_cycles
            << " cycles before the first targets, watchdog " << result.watchdog_cycles
            << " cycles, fault/stale holds: " << result.fault_hold_cycles << " cycles"
            << (result.fault_recoveries > 0
                    ? ", fault recoveries: " + std::to_string(result.fault_recoveries)
                    : "")
            << "\n";
  for (const auto& report : result.can_groups) {
    const auto& c = report.counters;
    std::cout << "CAN group " << report.group << ": " << c.syncs_sent << " SYNCs, "
              << c.tpdos_received << " TPDOs, " << c.missed_sync_answers << " missed answers, "
              << c.late_tpdos << " late TPDOs, " << c.emergencies << " EMCY, " << c.error_frames
              << " error frames, " << c.tx_queue_full << " frames refused by a full queue, "
              << c.malformed_frames + c.unexpected_frames << " malformed/unexpected frames\n";
    for (const auto& homed : report.homing) {
      std::cout << "  homing" << (homed.on_request ? " (on request)" : "") << ": joint "
                << homed.joint << " (node " << homed.node_id << ", method " << homed.method
                << ") homed in " << homed.duration_s << " s\n";
    }
    if (c.homing_failures > 0) {
      std::cout << "  homing on request failed " << c.homing_failures
                << " time(s), last: " << report.last_homing_error << "\n";
    }
  }
  if (result.ros2) {
    const ros2::BridgeCounts& c = *result.ros2;
    std::cout << "ROS 2: " << c.joint_states << " joint states, " << c.images << " images, "
              << c.diagnostics << " diagnostics; commands: " << c.commands_received << " taken, "
              << c.commands_refused << " refused" << (c.write_errors > 0 ? ", WRITE ERRORS: " : "")
              << (c.write_errors > 0 ? std::to_string(c.write_errors) : "") << "\n";
  }
  if (result.perception_link) {
    const ros2::RobotPerceptionLinkCounts& c = *result.perception_link;
    std::cout << "perception link: " << c.pairs_sent << " pairs sent, " << c.results_used
              << " results used of " << c.results_received << " (" << c.results_stale << " stale, "
              << c.results_malformed << " malformed), exposure to result " << c.latency_median_ms
              << " ms median, " << c.latency_max_ms << " ms at most, " << c.outages.size()
              << " outage(s)\n";
    for (const ros2::LinkOutage& outage : c.outages) {
      std::cout << "  outage: no results from " << outage.lost_s << " s"
                << (outage.back_s >= 0.0 ? " to " + std::to_string(outage.back_s) + " s"
                                         : " to the end of the run")
                << "\n";
    }
  }
  if (result.fault_latched_at_end) {
    std::cout << "joint loop: a drive fault is latched; the joints hold until a fault reset\n";
  }
  for (const auto& report : result.tracking) {
    std::cout << "tracking (" << report.controller << "): largest command lead "
              << report.peak_error_rad << " rad"
              << (report.peak_joint.empty() ? "" : " (" + report.peak_joint + ")") << ", frozen "
              << report.frozen_cycles << " cycles, " << report.restarts
              << " restart(s) from the measured pose"
              << (report.faulted ? "; FAULT: " + report.fault : "") << "\n";
  }
}

void print_task_results(const MainJobResult& result) {
  if (result.perception) {
    const auto& d = result.perception->disparity;
    std::cout << "perception: " << result.perception->sequence << " stereo frames; disparity at "
              << "the fovea " << (d.valid ? std::to_string(d.disparity_px) + " px" : "invalid")
              << " (confidence " << d.confidence << ")\n";
  }
  if (result.behaviour) {
    const BehaviourReport& behaviour = *result.behaviour;
    std::cout << "behaviour " << behaviour.name << ": " << behaviour.steps << " steps; "
              << behaviour.status << "\n";
    if (behaviour.failed) std::cerr << "cambio run: behaviour stopped: " << behaviour.error << "\n";
  }
}

}  // namespace

void print_run_report(const MainJobResult& result) {
  std::cout << runtime::format_statistics_table(result.loops.data(), result.loops.size());
  std::cout << runtime::format_wall_time_shares(
      runtime::wall_time_shares(result.loops.data(), result.loops.size(), result.wall_s),
      result.wall_s, !result.realtime);
  print_device_counts(result);
  print_task_results(result);
}

void warn_allocating_loops(const MainJobResult& result) {
  for (const auto& loop : result.loops) {
    if (runtime::passes_allocation_gate(loop)) continue;
    std::cerr << "cambio run: warning: loop '" << loop.name << "' allocated " << loop.allocations
              << " times in update() without declaring it\n";
  }
}

}  // namespace cambio::app
