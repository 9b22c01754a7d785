#pragma once

// What the -bench commands share to turn wall time into figures: elapsed seconds and medians, so
// a burst of load from another process skews one sample, not the figure.

#include <chrono>
#include <functional>
#include <vector>

namespace cambio::app {

/// Wall time since `start`, s (steady clock).
double seconds_since(std::chrono::steady_clock::time_point start);

/// The median of `values`: the mean of the middle two for an even count; 0 for none.
double median_of(std::vector<double> values);

/// The median wall time of `run`, us, over `repeats` timed runs after a few untimed ones;
/// `before` runs untimed before each timed run. For an even `repeats`, the upper middle sample.
double median_us(
    int repeats, const std::function<void()>& run, const std::function<void()>& before = [] {});

}  // namespace cambio::app
