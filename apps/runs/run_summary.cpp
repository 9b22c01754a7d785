#include "run_summary.hpp"

#include <cmath>
#include <string>

#include "peak_rss.hpp"
#include "renderer_report.hpp"
#include "run_trace.hpp"

namespace cambio::app {

namespace {

Json joint_loop_json(const MainJobResult& result) {
  return {{"fault_recoveries", result.fault_recoveries},
          {"startup_hold_cycles", result.startup_hold_cycles},
          {"watchdog_hold_cycles", result.watchdog_cycles},
          {"fault_hold_cycles", result.fault_hold_cycles},
          {"fault_latched_at_end", result.fault_latched_at_end}};
}

/// Each controller's tracking of its joints: how long it froze while they held, its restarts
/// from the measured pose, the largest lead of its command (and the joint's limit), a fault.
Json tracking_json(const MainJobResult& result) {
  Json controllers = Json::object();
  for (const auto& report : result.tracking) {
    controllers[report.controller] = {
        {"frozen_cycles", report.frozen_cycles},
        {"restarts", report.restarts},
        {"peak_error_rad", report.peak_error_rad},
        {"peak_joint", report.peak_joint.empty() ? Json(nullptr) : Json(report.peak_joint)},
        {"peak_joint_limit_rad", std::isfinite(report.peak_joint_limit_rad)
                                     ? Json(report.peak_joint_limit_rad)
                                     : Json(nullptr)},
        {"fault", report.faulted ? Json(report.fault) : Json(nullptr)}};
  }
  return controllers;
}

Json perception_json(const perception::SsmSummary& perception) {
  const auto& d = perception.disparity;
  return {{"frames", perception.sequence},
          {"disparity_valid", d.valid},
          {"disparity_px", d.disparity_px},
          {"confidence", d.confidence}};
}

Json gaze_json(const MainJobResult& result) {
  const control::GazeStatus& gaze = *result.gaze;
  return {{"commands_applied", gaze.commands_applied},
          {"commands_rejected", result.gaze_rejected_commands},
          {"last_refusal", std::string(control::to_string(gaze.last_refusal))},
          {"disparity_measurements", result.gaze_measurements},
          {"vergence_corrections", result.gaze_corrections},
          // Measurements not followed, by why: a sudden depth jump awaiting a second reading; a
          // jump while the dominant fovea held still (something in front of the verging eye);
          // returns to the vergence last verged on when it was measured again; anchors moved
          // to a surface at another depth held for GazeLoop::kReanchorAfter_s; and anchors
          // forgotten as false matches (a confirmed jump with neither fovea changed). A reading
          // leaving the anchor with far less confidence than the anchor's is a doubtful one.
          {"vergence_rejected",
           {{"jump_awaiting_confirmation", result.gaze_held_jumps},
            {"occlusion_of_the_verging_eye", result.gaze_occlusion_rejections},
            {"doubtful_departure_from_the_anchor", result.gaze_doubtful_departures}}},
          {"vergence_anchor_returns", result.gaze_anchor_returns},
          {"vergence_reanchors", result.gaze_reanchors},
          {"vergence_false_anchors", result.gaze_false_anchors},
          // Corrections on readings too faint to count, followed because GazeLoop::kFaintAgreements
          // of them in a row agreed before anything was verged on.
          {"vergence_faint_steps", result.gaze_faint_steps},
          // Pursuit frames whose fovea saw the target's motion one way only (stripes along it),
          // placed across it by the centre of the fixated object's zero-disparity region.
          {"pursuit_region_frames", result.gaze_pursuit_region_frames},
          {"final_action", gaze_action_name(gaze.action)},
          {"final_vergence_rad", gaze.vergence_rad}};
}

Json behaviour_json(const BehaviourReport& behaviour) {
  return {{"name", behaviour.name},
          {"plugins", behaviour.plugins},
          {"steps", behaviour.steps},
          {"status", behaviour.status},
          {"failed", behaviour.failed},
          {"error", behaviour.failed ? Json(behaviour.error) : Json(nullptr)}};
}

/// Each present arm's last reach; times in s from the script's start, null when not reached.
Json arms_json(const MainJobResult& result) {
  const control::ArmStatus& arms = *result.arms;
  Json sides = Json::object();
  for (std::size_t side = 0; side < 2; ++side) {
    if (!result.arm_present[side]) continue;
    const control::ArmStatus::Arm& arm = arms.arms[side];
    const auto seconds = [&](std::int64_t ns) {
      return ns == 0 ? Json(nullptr)
                     : Json(static_cast<double>(ns - result.script_start_ns) * 1e-9);
    };
    sides[side == 0 ? "left" : "right"] = {{"phase", reach_phase_name(arm.phase)},
                                           {"gripper_closed", arm.gripper_closed},
                                           {"command_s", seconds(arm.command_ns)},
                                           {"touch_s", seconds(arm.touch_ns)},
                                           {"target_m", arm.target_W_m},
                                           {"gripper_m", arm.gripper_W_m},
                                           {"distance_to_target_m", arm.distance_to_target_m}};
  }
  return {{"commands_applied", arms.commands_applied},
          {"refusal", arms.refusal().empty() ? Json(nullptr) : Json(std::string(arms.refusal()))},
          {"arms", sides}};
}

/// The visits (when the trace followed objects), the final joints and the trace's own figures.
void add_trace_fields(Json& json, const Trace& trace, const config::ExperimentConfig& experiment) {
  if (!trace.visit_objects.empty()) {
    json["visits"] = visits_json(trace, experiment.evaluation.visit_dwell_s);
  }
  json["final_joints"] = final_joints_json(trace);
  json["trace"] = {
      {"rows", trace.rows.size()}, {"truncated", trace.truncated}, {"problems", trace.problems}};
}

Json can_group_json(const canopen::CanGroupCounters& c) {
  return {{"syncs_sent", c.syncs_sent},
          {"tpdos_received", c.tpdos_received},
          {"missed_sync_answers", c.missed_sync_answers},
          {"late_tpdos", c.late_tpdos},
          {"malformed_frames", c.malformed_frames},
          {"unexpected_frames", c.unexpected_frames},
          {"tx_queue_full", c.tx_queue_full},
          {"emergencies", c.emergencies},
          {"error_frames", c.error_frames},
          {"boot_ups", c.boot_ups},
          {"receive_cap_reached", c.receive_cap_reached},
          {"frames_sent", c.frames_sent},
          {"frames_received", c.frames_received},
          {"bus_bits_worst_case", c.bus_bits},
          {"reconfigurations", c.reconfigurations},
          {"reconfiguration_failures", c.reconfiguration_failures},
          {"homings_on_request", c.homings},
          {"homing_failures", c.homing_failures}};
}

/// The names of the loops that allocated in update() without declaring it.
Json loops_that_allocated(const MainJobResult& result) {
  Json over_budget = Json::array();
  for (const auto& loop : result.loops) {
    if (!runtime::passes_allocation_gate(loop)) over_budget.push_back(loop.name);
  }
  return over_budget;
}

/// The loops, devices and process: statistics, CAN counters, renderer, time shares, memory.
void add_execution_fields(Json& json, const MainJobResult& result) {
  json["loops"] = Json::array();
  for (const auto& loop : result.loops) json["loops"].push_back(runtime::statistics_json(loop));
  for (const auto& report : result.can_groups) {
    json["can_groups"][report.group] = can_group_json(report.counters);
    // Each joint that homed at activate, and each homing on request in order: how long it took,
    // the statuswords it went through.
    Json homing = Json::object();
    Json on_request = Json::array();
    for (const auto& homed : report.homing) {
      Json entry = {{"node_id", homed.node_id},
                    {"method", homed.method},
                    {"duration_s", homed.duration_s},
                    {"statuswords", homed.statuswords}};
      if (homed.on_request) {
        entry["joint"] = homed.joint;
        on_request.push_back(std::move(entry));
      } else {
        homing[homed.joint] = std::move(entry);
      }
    }
    Json& group = json["can_groups"][report.group];
    group["homing"] = std::move(homing);
    group["homed_on_request"] = std::move(on_request);
    if (!report.last_homing_error.empty()) {
      group["last_homing_error"] = report.last_homing_error;
    }
  }
  if (result.ros2) {
    const ros2::BridgeCounts& c = *result.ros2;
    json["ros2"] = {{"joint_states", c.joint_states},
                    {"tf", c.tf},
                    {"clock", c.clock},
                    {"images", c.images},
                    {"camera_infos", c.camera_infos},
                    {"diagnostics", c.diagnostics},
                    {"gaze", c.gaze},
                    {"commands_received", c.commands_received},
                    {"commands_refused", c.commands_refused},
                    {"write_errors", c.write_errors}};
  }
  if (result.perception_link) {
    const ros2::RobotPerceptionLinkCounts& c = *result.perception_link;
    Json outages = Json::array();
    for (const ros2::LinkOutage& outage : c.outages) {
      // back_s null: the link was still down when the run ended.
      outages.push_back({{"lost_s", outage.lost_s},
                         {"back_s", outage.back_s >= 0.0 ? Json(outage.back_s) : Json(nullptr)}});
    }
    json["perception_link"] = {{"pairs_sent", c.pairs_sent},
                               {"requests_sent", c.requests_sent},
                               {"results_received", c.results_received},
                               {"results_used", c.results_used},
                               {"results_stale", c.results_stale},
                               {"results_malformed", c.results_malformed},
                               {"last_malformed", c.last_malformed},
                               {"write_errors", c.write_errors},
                               {"latency_median_ms", c.latency_median_ms},
                               {"latency_max_ms", c.latency_max_ms},
                               {"outages", std::move(outages)}};
  }
  if (result.renderer) {
    add_renderer_fields(json["renderer"], *result.renderer);
  } else {
    json["renderer"] = nullptr;
  }
  json["wall_time_shares"] = runtime::wall_time_shares_json(
      runtime::wall_time_shares(result.loops.data(), result.loops.size(), result.wall_s),
      result.wall_s, !result.realtime);
  json["peak_rss_kib"] = peak_rss_kib();
  const Json over_budget = loops_that_allocated(result);
  json["allocation_gate"] = {{"passed", over_budget.empty()},
                             {"loops_that_allocated", over_budget}};
}

}  // namespace

Json summary_json(const config::ExperimentConfig& experiment, const MainJobResult& result,
                  const RunOutcome& outcome, const Trace* trace,
                  const std::optional<RunEvaluation>& evaluation) {
  Json json;
  json["experiment"] = experiment.name;
  json["outcome"] = outcome.name;
  json["exit_status"] = outcome.exit_status;
  json["stopped_by"] = outcome.signal_name.empty() ? Json(nullptr) : Json(outcome.signal_name);
  json["duration_s"] = experiment.duration_s;
  json["rig"] = experiment.rig.name;
  json["executor"] = result.realtime ? "realtime" : "lockstep";
  json["seed"] = experiment.seed;
  json["simulated_s"] = result.simulated_s;
  json["wall_s"] = result.wall_s;
  json["stopped_by_signal"] = result.stopped_by_signal;
  json["camera_frames"] = result.camera_frames;
  json["stereo_pairs"] = result.stereo_pairs;
  json["mismatched_stereo_pairs"] = result.mismatched_stereo_pairs;
  json["joint_loop"] = joint_loop_json(result);
  json["tracking"] = tracking_json(result);
  if (result.perception) json["perception"] = perception_json(*result.perception);
  if (result.gaze) json["gaze"] = gaze_json(result);
  if (result.behaviour) json["behaviour"] = behaviour_json(*result.behaviour);
  if (result.arms) json["arms"] = arms_json(result);
  if (evaluation) {
    json["metrics"] = metrics_json(evaluation->metrics);
    json["goals"] = goals_json(evaluation->goals);
    json["passed"] = all_passed(evaluation->goals);
  }
  if (trace != nullptr) add_trace_fields(json, *trace, experiment);
  add_execution_fields(json, result);
  return json;
}

}  // namespace cambio::app
