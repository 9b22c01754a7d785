#pragma once

// The bodies of the fuzz targets (README.md): plain functions, so that libFuzzer's entry point
// (fuzz_entry.cpp) and the unit test that replays found inputs (fuzz_regression_test.cpp) run
// the same code.
//
// Each takes one input and returns 0. A config::ConfigError is the expected answer to bad
// input; any other exception escapes (libFuzzer reports it as a crash), and a config that loads
// but breaks a bound its loader promises aborts with the bound's name.

#include <cstddef>
#include <cstdint>

namespace cambio::fuzz {

/// A rig file's text (rigs/*.yaml), then hal's description of the loaded rig.
int rig(const std::uint8_t* data, std::size_t size);
/// A scene file's text (scenes/*.yaml).
int scene(const std::uint8_t* data, std::size_t size);
/// An experiment file's text (experiments/*.yaml), read as if it were in the shipped
/// experiments/ folder, so that its relative rig, scene and perception paths find shipped files.
int experiment(const std::uint8_t* data, std::size_t size);
/// A perception (SSM) config's text (perception/*.yaml), then the Sensory Servo Module it
/// configures, built for the largest camera with one frame: the allocations the config sizes.
int perception(const std::uint8_t* data, std::size_t size);
/// `--set` arguments separated by NUL bytes (as `xargs -0` takes them, so a value may hold a
/// line break), parsed and applied to the shipped rigs/cambio.yaml.
int set_override(const std::uint8_t* data, std::size_t size);

}  // namespace cambio::fuzz
