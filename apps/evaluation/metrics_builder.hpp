#pragma once

// Internal to cambio_evaluation: how compute_metrics (run_metrics.cpp) and its metric families
// (metric_families.hpp) collect the metrics present and the reasons for the others.

#include <map>
#include <string>
#include <string_view>
#include <utility>

#include "run_metrics.hpp"

namespace cambio::app::detail {

class MetricsBuilder {
 public:
  void set(std::string_view name, double value) { values_[std::string(name)] = value; }
  void absent(std::string_view name, std::string reason) {
    absent_[std::string(name)] = std::move(reason);
  }

  /// In kMetricNames order; a name neither set nor absent is "not measured in this run".
  RunMetrics build() const {
    RunMetrics metrics;
    for (const std::string_view name : kMetricNames) {
      const std::string key(name);
      if (const auto it = values_.find(key); it != values_.end()) {
        metrics.values.emplace_back(key, it->second);
      } else if (const auto why = absent_.find(key); why != absent_.end()) {
        metrics.absent.emplace_back(key, why->second);
      } else {
        metrics.absent.emplace_back(key, "not measured in this run");
      }
    }
    return metrics;
  }

 private:
  std::map<std::string, double> values_;
  std::map<std::string, std::string> absent_;
};

}  // namespace cambio::app::detail
