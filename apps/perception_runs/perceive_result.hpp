#pragma once

// perceive's result.json: what the SSM saw on one image pair, for people and programs.

#include "cambio/perception/sensory_servo.hpp"
#include "json_output.hpp"
#include "perceive_run.hpp"

namespace cambio::app {

/// The document: the inputs, the disparity at the fovea (null when not valid), the retina, each
/// level's footprint, disparity and moments, the maps' names and the timings. Measured values
/// keep six significant digits.
Json perceive_result_json(const PerceiveInputs& inputs, const perception::SensoryServo& servo,
                          const perception::SsmSummary& summary);

}  // namespace cambio::app
