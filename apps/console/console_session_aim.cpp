#include "console_session.hpp"

#include <algorithm>

#include "cambio/config/echoed_text.hpp"
#include "cambio/config/map_reader.hpp"
#include "console_session_detail.hpp"

namespace cambio::app {
namespace {

using console::detail::degrees;
using console::detail::format;

// Why `object NAME` names nothing: the nearest scene object, or all of them.
std::string no_such_object(const std::string& name, const std::vector<std::string>& scene_objects) {
  std::string why = "refused: no scene object " + config::in_quotes(name);
  if (const auto near = config::closest_name(name, scene_objects)) {
    why += "; did you mean " + config::in_quotes(*near) + "?";
  } else if (!scene_objects.empty()) {
    why += " (objects:";
    for (const auto& object : scene_objects) why += " " + object;
    why += ")";
  }
  return why;
}

}  // namespace

bool ConsoleSession::aim(const console::Target& target, bool saccade) {
  const auto& v = target.values;
  switch (target.kind) {
    case console::TargetKind::kPixel:
      report(saccade ? actions_.saccade_to_pixel(v[0], v[1]) : actions_.look_at_pixel(v[0], v[1]),
             format("%s pixel (%.1f, %.1f)", saccade ? "saccade to" : "fixating", v[0], v[1]));
      return true;
    case console::TargetKind::kPoint: {
      const Eigen::Vector3d p(v[0], v[1], v[2]);
      report(saccade ? actions_.saccade_to_point(p) : actions_.look_at_point(p),
             format("%s point (%.3f, %.3f, %.3f) m", saccade ? "saccade to" : "fixating", v[0],
                    v[1], v[2]));
      return true;
    }
    case console::TargetKind::kAngles:
      // The gaze loop takes angular displacements as saccades; fixating them is the same jump.
      report(actions_.saccade_by_angles(v[0], v[1]),
             format("saccade by pan %.2f deg, tilt %.2f deg", degrees(v[0]), degrees(v[1])));
      return true;
    case console::TargetKind::kObject: {
      sim::GroundTruth* truth = job_.ground_truth();
      if (std::find(scene_objects_.begin(), scene_objects_.end(), target.object) ==
              scene_objects_.end() ||
          truth == nullptr) {
        ++lines_refused_;
        out_ << no_such_object(target.object, scene_objects_) << "\n";
        return false;
      }
      // A convenience of the simulator: the object's true centre, given as a point.
      const Eigen::Vector3d p = truth->X_WO(target.object).translation();
      report(saccade ? actions_.saccade_to_point(p) : actions_.look_at_point(p),
             format("%s %s at (%.3f, %.3f, %.3f) m", saccade ? "saccade to" : "fixating",
                    target.object.c_str(), p.x(), p.y(), p.z()));
      return true;
    }
  }
  return false;
}

}  // namespace cambio::app
