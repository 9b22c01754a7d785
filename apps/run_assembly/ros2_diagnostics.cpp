#include "ros2_diagnostics.hpp"

#include <cstdio>
#include <memory>
#include <numbers>

#include "run_trace.hpp"

namespace cambio::app {
namespace {

using Entry = ros2::DiagnosticEntry;
using Level = Entry::Level;

std::string number(double value, const char* format = "%.6g") {
  char text[48];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

std::string count(std::uint64_t value) {
  return std::to_string(value);
}

/// The status bits' names, "" when none.
std::string bit_names(std::uint32_t bits) {
  static constexpr std::pair<std::uint32_t, const char*> kNames[] = {
      {hal::kJointCommandClamped, "clamped"},
      {hal::kJointAtLimit, "at_limit"},
      {hal::kJointFault, "fault"},
      {hal::kJointStale, "stale"},
      {hal::kJointNotEnabled, "not_enabled"},
      {hal::kJointCommLost, "comm_lost"},
      {hal::kJointHoming, "homing"}};
  std::string names;
  for (const auto& [bit, name] : kNames) {
    if ((bits & bit) == 0) continue;
    if (!names.empty()) names += ' ';
    names += name;
  }
  return names;
}

Entry drive_entry(const std::string& joint, const std::string& group,
                  const hal::JointState& state) {
  Entry entry;
  entry.name = "cambio: drive " + joint;
  entry.hardware_id = group;
  const std::uint32_t bits = state.status_bits;
  if ((bits & hal::kJointLatchingBits) != 0) {
    entry.level = Level::kError;
  } else if ((bits & (hal::kJointStale | hal::kJointNotEnabled | hal::kJointHoming)) != 0) {
    entry.level = Level::kWarn;
  }
  const std::string names = bit_names(bits);
  entry.message = std::string(hal::to_string(state.drive_state)) +
                  (names.empty() ? std::string() : " (" + names + ")");
  char code[8];
  std::snprintf(code, sizeof code, "0x%04X", static_cast<unsigned>(state.error_code));
  entry.values = {{"drive_state", std::string(hal::to_string(state.drive_state))},
                  {"error_code", code},
                  {"status_bits", names},
                  {"position_rad", number(state.position_rad)},
                  {"velocity_rad_s", number(state.velocity_rad_s)},
                  {"effort_nm", number(state.effort_nm)}};
  return entry;
}

/// `load`: the bus's worst-case load over the last window (negative: not measured yet).
Entry can_group_entry(const canopen::CanJointGroup& group, const canopen::CanGroupCounters& c,
                      double load) {
  Entry entry;
  entry.name = "cambio: CAN group " + group.info().name;
  entry.hardware_id = "CAN group " + group.info().name;
  const std::uint64_t errors = c.error_frames + c.bus_faults + c.malformed_frames +
                               c.tx_queue_full + c.reconfiguration_failures + c.homing_failures;
  entry.level = c.bus_faults > 0 ? Level::kError : errors > 0 ? Level::kWarn : Level::kOk;
  entry.message = errors == 0 ? "no errors" : count(errors) + " error(s) since start";
  entry.values = {
      {"rate_hz", number(group.rate_hz())},
      {"bus_load", load < 0.0 ? std::string("not measured yet") : number(load, "%.3f")},
      {"bus_bitrate_bit_s", count(static_cast<std::uint64_t>(group.bus_bitrate_bit_s()))},
      {"frames_sent", count(c.frames_sent)},
      {"frames_received", count(c.frames_received)},
      {"syncs_sent", count(c.syncs_sent)},
      {"tpdos_received", count(c.tpdos_received)},
      {"missed_sync_answers", count(c.missed_sync_answers)},
      {"late_tpdos", count(c.late_tpdos)},
      {"malformed_frames", count(c.malformed_frames)},
      {"unexpected_frames", count(c.unexpected_frames)},
      {"tx_queue_full", count(c.tx_queue_full)},
      {"emergencies", count(c.emergencies)},
      {"error_frames", count(c.error_frames)},
      {"boot_ups", count(c.boot_ups)},
      {"bus_faults", count(c.bus_faults)},
      {"reconfigurations", count(c.reconfigurations)},
      {"homings_on_request", count(c.homings)},
      {"homing_failures", count(c.homing_failures)}};
  const canopen::HomingError homing = group.last_homing_error();
  if (homing.node_id != 0) entry.values.emplace_back("last_homing_error", homing.text.data());
  return entry;
}

/// A loop's rate (`achieved_hz`, cycles per second of run time over the last window; negative:
/// not measured yet) and its worst wake-up latency and update time since the last sample.
Entry loop_entry(const runtime::LiveLoopSample& sample, double achieved_hz) {
  Entry entry;
  entry.name = "cambio: loop " + sample.name;
  entry.hardware_id = "cambio";
  // Below 90% of the schedule over a whole window: the loop cannot keep up.
  entry.level =
      achieved_hz >= 0.0 && achieved_hz < 0.9 * sample.rate_hz ? Level::kWarn : Level::kOk;
  entry.message = achieved_hz < 0.0 ? "rate not measured yet"
                                    : number(achieved_hz, "%.1f") + " Hz of " +
                                          number(sample.rate_hz, "%.1f") + " scheduled";
  entry.values = {{"rate_hz", number(achieved_hz, "%.2f")},
                  {"scheduled_rate_hz", number(sample.rate_hz)},
                  {"cycles", count(sample.cycles)},
                  {"overruns", count(sample.overruns)},
                  {"max_wakeup_latency_us", number(sample.max_wakeup_latency_ns * 1e-3, "%.1f")},
                  {"max_update_us", number(sample.max_execution_ns * 1e-3, "%.1f")}};
  return entry;
}

Entry joint_loop_entry(const control::JointLoop& loop, const control::JointStateFrame& frame) {
  Entry entry;
  entry.name = "cambio: joint loop " + loop.name() + " holds";
  entry.hardware_id = "cambio";
  entry.level = frame.fault_latched ? Level::kError : frame.holding ? Level::kWarn : Level::kOk;
  entry.message = frame.fault_latched ? "holding: a fault is latched until a reset"
                  : frame.holding     ? "holding"
                                      : "driving";
  entry.values = {{"fault_latched", frame.fault_latched ? "true" : "false"},
                  {"holding", frame.holding ? "true" : "false"},
                  {"fault_hold_cycles", count(loop.fault_hold_cycles())},
                  {"stale_target_cycles", count(loop.stale_cycles())},
                  {"stale_feedback_cycles", count(loop.feedback_stale_cycles())},
                  {"fault_recoveries", count(loop.fault_recoveries())},
                  {"homes_refused", count(loop.homes_refused())}};
  return entry;
}

Entry perception_link_entry(const ros2::RobotPerceptionLink& link) {
  const ros2::RobotPerceptionLinkCounts c = link.counts();
  const bool lost = !c.outages.empty() && c.outages.back().back_s < 0.0;
  Entry entry;
  entry.name = "cambio: perception link";
  entry.hardware_id = "cambio";
  entry.level = lost ? Level::kError : Level::kOk;
  entry.message = lost ? "lost at " + number(c.outages.back().lost_s, "%.2f") +
                             " s: no results from the perception host; the gaze holds"
                       : number(c.latency_median_ms, "%.1f") + " ms from exposure to result";
  entry.values = {{"pairs_sent", count(c.pairs_sent)},
                  {"results_used", count(c.results_used)},
                  {"results_stale", count(c.results_stale)},
                  {"results_malformed", count(c.results_malformed)},
                  {"outages", count(c.outages.size())},
                  {"latency_median_ms", number(c.latency_median_ms, "%.2f")},
                  {"latency_max_ms", number(c.latency_max_ms, "%.2f")}};
  return entry;
}

}  // namespace

ros2::DiagnosticsSampler make_diagnostics_sampler(DiagnosticsInputs inputs) {
  // Each loop's cycles at the start of the rate window, and its last measured rate: the
  // diagnostics thread's own. A window is at least 0.2 s of run time, so one cycle more or less
  // moves a rate by at most 5 Hz.
  struct State {
    DiagnosticsInputs inputs;
    std::vector<std::uint64_t> window_cycles;
    std::vector<double> rate_hz;
    std::vector<std::uint64_t> window_bus_bits;  // Per CAN group.
    std::vector<double> bus_load;
    std::int64_t window_start_ns = -1;
  };
  constexpr std::int64_t kMinWindowNs = 200'000'000;
  auto state = std::make_shared<State>();
  state->inputs = std::move(inputs);
  return [state](std::int64_t& stamp_ns, std::vector<Entry>& entries) {
    const DiagnosticsInputs& in = state->inputs;
    stamp_ns = in.executor->clock().now_ns();
    const std::vector<runtime::LiveLoopSample> loops = in.executor->live_statistics();
    state->window_cycles.resize(loops.size(), 0);
    state->rate_hz.resize(loops.size(), -1.0);
    const std::int64_t window_ns = stamp_ns - state->window_start_ns;
    const bool window_ends = state->window_start_ns < 0 || window_ns >= kMinWindowNs;
    for (std::size_t i = 0; i < loops.size(); ++i) {
      if (window_ends && state->window_start_ns >= 0) {
        state->rate_hz[i] = static_cast<double>(loops[i].cycles - state->window_cycles[i]) /
                            (static_cast<double>(window_ns) * 1e-9);
      }
      if (window_ends) state->window_cycles[i] = loops[i].cycles;
      entries.push_back(loop_entry(loops[i], state->rate_hz[i]));
    }
    std::vector<Entry> can_entries;
    state->window_bus_bits.resize(in.can_groups.size(), 0);
    state->bus_load.resize(in.can_groups.size(), -1.0);
    for (std::size_t g = 0; g < in.can_groups.size(); ++g) {
      const canopen::CanJointGroup& group = *in.can_groups[g];
      const canopen::CanGroupCounters counters = group.counters();
      if (window_ends && state->window_start_ns >= 0 && group.bus_bitrate_bit_s() > 0) {
        state->bus_load[g] = static_cast<double>(counters.bus_bits - state->window_bus_bits[g]) /
                             (static_cast<double>(window_ns) * 1e-9) /
                             static_cast<double>(group.bus_bitrate_bit_s());
      }
      if (window_ends) state->window_bus_bits[g] = counters.bus_bits;
      can_entries.push_back(can_group_entry(group, counters, state->bus_load[g]));
    }
    if (window_ends) state->window_start_ns = stamp_ns;
    control::JointStateFrame frame;
    for (const DiagnosticsInputs::JointLoopView& view : in.joint_loops) {
      if (view.states->version() == 0 || !view.states->read(frame)) continue;
      entries.push_back(joint_loop_entry(*view.loop, frame));
      const auto n = std::min(view.rig_indices.size(), static_cast<std::size_t>(frame.count));
      for (std::size_t j = 0; j < n; ++j) {
        const auto rig = static_cast<std::size_t>(view.rig_indices[j]);
        entries.push_back(drive_entry(in.joint_names[rig], in.joint_groups[rig], frame.states[j]));
      }
    }
    for (Entry& entry : can_entries) entries.push_back(std::move(entry));
    if (in.perception_link != nullptr)
      entries.push_back(perception_link_entry(*in.perception_link));
    return true;
  };
}

ros2::GazeSampler make_gaze_sampler(const control::GazeLoop& gaze_loop) {
  return [&gaze_loop](ros2::GazeSample& sample) {
    control::GazeStatus status;
    if (gaze_loop.status().version() == 0 || !gaze_loop.status().read(status)) return false;
    sample.stamp_ns = status.stamp_ns;
    sample.fixation_valid = status.believed_fixation_valid;
    sample.fixation_base_m = status.believed_fixation_W_m;
    Entry& entry = sample.status;
    entry.name = "cambio: gaze";
    entry.hardware_id = "head";
    entry.level = status.tracking_fault ? Level::kError
                  : status.joints_held  ? Level::kWarn
                                        : Level::kOk;
    entry.message = std::string(gaze_action_name(status.action)) +
                    (status.saccade_active ? " (saccade under way)" : "") +
                    (status.joints_held ? " (frozen: the joints hold)" : "");
    constexpr double kDegPerRad = 180.0 / std::numbers::pi;
    entry.values = {{"action", gaze_action_name(status.action)},
                    {"disparity_valid", status.disparity_valid ? "true" : "false"},
                    {"disparity_px", number(status.disparity_px, "%.2f")},
                    {"disparity_confidence", number(status.disparity_confidence, "%.3f")},
                    {"vergence_deg", number(status.vergence_rad * kDegPerRad, "%.3f")},
                    {"feature_error_px", number(status.feature_error_px, "%.2f")},
                    {"saccade_active", status.saccade_active ? "true" : "false"},
                    {"joints_held", status.joints_held ? "true" : "false"},
                    {"commands_applied", count(status.commands_applied)},
                    {"commands_refused", count(status.commands_refused)},
                    {"last_refusal", std::string(control::to_string(status.last_refusal))}};
    return true;
  };
}

}  // namespace cambio::app
