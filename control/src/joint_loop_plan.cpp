#include "cambio/control/joint_loop_plan.hpp"

#include <cmath>
#include <stdexcept>

namespace cambio::control {

std::vector<JointLoopPlan> plan_joint_loops(const std::vector<hal::JointGroupInfo>& groups,
                                            double joint_rate_hz) {
  if (!(joint_rate_hz > 0.0) || !std::isfinite(joint_rate_hz)) {
    throw std::invalid_argument("joint loop plan: the rig-wide joint rate must be > 0 Hz");
  }
  std::vector<JointLoopPlan> plans{{"joint", joint_rate_hz, {}}};
  for (std::size_t g = 0; g < groups.size(); ++g) {
    const double rate_hz = groups[g].rate_hz == 0.0 ? joint_rate_hz : groups[g].rate_hz;
    if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) {
      throw std::invalid_argument("joint loop plan: group '" + groups[g].name +
                                  "' has a rate that is not > 0 Hz");
    }
    JointLoopPlan* plan = nullptr;
    for (auto& candidate : plans) {
      if (candidate.rate_hz == rate_hz) plan = &candidate;
    }
    if (plan == nullptr) {
      plans.push_back({"joint." + groups[g].name, rate_hz, {}});
      plan = &plans.back();
    } else if (plan != &plans.front()) {
      plan->name += "+" + groups[g].name;
    }
    plan->groups.push_back(g);
  }
  if (plans.front().groups.empty() && plans.size() > 1) plans.erase(plans.begin());
  return plans;
}

}  // namespace cambio::control
