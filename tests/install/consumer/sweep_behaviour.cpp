// A user's behaviour, built outside Câmbio as a plugin against the installed headers only
// (cambio::behaviour): it sweeps the gaze left and right by a fixed angle, one saccade per period.
#include <cmath>
#include <numbers>
#include <string>

#include "cambio/behaviour/registry.hpp"

namespace {

class Sweep final : public cambio::behaviour::Behaviour {
 public:
  Sweep(double amplitude_rad, double period_s)
      : amplitude_rad_(amplitude_rad), period_s_(period_s) {}

  void step(const cambio::behaviour::Observation& observation,
            cambio::behaviour::Actions& actions) override {
    if (observation.run_time_s < next_s_) return;
    next_s_ += period_s_;
    // Alternate around where it started: +a, then -2a, +2a, ...
    const double pan_rad =
        saccades_ == 0 ? amplitude_rad_ : (saccades_ % 2 == 0 ? 2.0 : -2.0) * amplitude_rad_;
    if (actions.saccade_by_angles(pan_rad, 0.0).sent) ++saccades_;
    seen_maps_ = observation.feature_map_names.size();
  }
  std::string status() const override {
    return "sweep: " + std::to_string(saccades_) + " saccades, " + std::to_string(seen_maps_) +
           " feature maps seen";
  }

 private:
  double amplitude_rad_;
  double period_s_;
  double next_s_ = 0.0;
  int saccades_ = 0;
  std::size_t seen_maps_ = 0;
};

}  // namespace

CAMBIO_BEHAVIOUR_PLUGIN(registry) {
  registry.add("sweep", [](cambio::behaviour::BehaviourParams& params) {
    return std::make_unique<Sweep>(params.number("amplitude_deg", 5.0) * std::numbers::pi / 180.0,
                                   params.number("period_s", 0.3));
  });
}
