#include "cambio/perception/perception_config.hpp"

#include <algorithm>
#include <cmath>

#include "cambio/config/config_error.hpp"
#include "cambio/config/map_reader.hpp"
#include "cambio/config/shipped_config.hpp"
#include "cambio/perception/gaussian_kernels.hpp"
#include "cambio/perception/operator_bank.hpp"
#include "cambio/perception/retina.hpp"

namespace cambio::perception {

namespace {

/// Beyond this a retina level is no longer "small": the SSM's premise (paper Section 3; its
/// levels are 16 x 16). It also bounds the feature maps: 8 levels x 64 maps x 128 x 128 floats
/// are 32 MiB per eye and frame.
constexpr double kMaxLevelSide_px = 128;
/// The widest search, level-0 px: the widest camera (config::kMaxCameraSide_px).
constexpr double kMaxSearchRange_px = 4096;

std::string in_quotes(const std::string& text) {
  return '"' + text + '"';
}

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

/// Checks a feature-map name against the operator set's, with a "did you mean" (up to 3 edits:
/// map names are short and differ in their scale digits).
void check_map_name(config::MapReader& reader, std::string_view key, const std::string& name,
                    const std::vector<std::string>& map_names, std::size_t index, bool listed) {
  if (contains(map_names, name)) return;
  std::string message = "unknown feature map " + in_quotes(name);
  if (const auto suggestion = config::closest_name(name, map_names, 3)) {
    message += "; did you mean " + in_quotes(*suggestion) + "?";
  } else {
    message += "; the operator set makes e.g. " + in_quotes(map_names.back());
  }
  if (listed) {
    reader.error(key, index, std::move(message));
  } else {
    reader.error(key, std::move(message));
  }
}

RetinaConfig read_retina(config::MapReader reader) {
  RetinaConfig retina;
  retina.levels = static_cast<int>(
      reader.integer_or("levels", retina.levels, config::Range::closed(1, Retina::kMaxLevels)));
  retina.width_px = static_cast<int>(
      reader.integer_or("width_px", retina.width_px, config::Range::closed(4, kMaxLevelSide_px)));
  retina.height_px = static_cast<int>(
      reader.integer_or("height_px", retina.height_px, config::Range::closed(4, kMaxLevelSide_px)));
  retina.coarsest_covers_field = reader.boolean_or("coarsest_covers_field", false);
  reader.finish();
  return retina;
}

OperatorConfig read_operators(config::MapReader reader) {
  OperatorConfig ops;
  if (reader.has("sigmas_px")) {
    ops.sigmas_px = reader.numbers("sigmas_px", config::Range::closed(0.3, 32.0));
    if (ops.sigmas_px.empty()) reader.error("sigmas_px", "expected at least one sigma");
  }
  ops.half_width_sigmas =
      reader.number_or("half_width_sigmas", ops.half_width_sigmas, config::Range::closed(1.0, 6.0));
  ops.half_width_px =
      static_cast<int>(reader.integer_or("half_width_px", 0, config::Range::closed(0, 64)));
  ops.laplacian_of_gaussian = reader.boolean_or("laplacian_of_gaussian", true);
  ops.sobel = reader.boolean_or("sobel", true);
  ops.average_radius_px = static_cast<int>(
      reader.integer_or("average_radius_px", ops.average_radius_px, config::Range::closed(0, 32)));
  for (auto& entry : reader.map_list("masks")) {
    UserMask mask;
    mask.name = entry.text("name");
    mask.rows = static_cast<int>(entry.integer("rows", config::Range::closed(1, 63)));
    mask.cols = static_cast<int>(entry.integer("cols", config::Range::closed(1, 63)));
    mask.values = entry.numbers("values");
    if (mask.rows % 2 == 0 || mask.cols % 2 == 0) {
      entry.error("rows", "a mask needs odd rows and cols (it is centred on a pixel), found " +
                              std::to_string(mask.rows) + " x " + std::to_string(mask.cols));
    } else if (!mask.values.empty() &&
               mask.values.size() != static_cast<std::size_t>(mask.rows * mask.cols)) {
      entry.error("values", "expected rows * cols = " + std::to_string(mask.rows * mask.cols) +
                                " values, found " + std::to_string(mask.values.size()));
    }
    entry.finish();
    ops.masks.push_back(std::move(mask));
  }
  reader.finish();
  return ops;
}

}  // namespace

SsmConfig read_ssm_config(config::MapReader& root) {
  SsmConfig config;
  config.rate_hz = root.number_or("rate_hz", config.rate_hz, config::Range::closed(0.1, 10'000));
  if (auto retina = root.optional_map("retina")) config.retina = read_retina(*retina);
  if (auto ops = root.optional_map("operators")) config.operators = read_operators(*ops);
  const std::vector<MapSpec> specs = feature_map_specs(config.operators);
  if (static_cast<int>(specs.size()) > kMaxMaps) {
    root.error("operators", "the operator set makes " + std::to_string(specs.size()) +
                                " maps per level; at most 64 are supported");
  }
  std::vector<std::string> map_names;
  for (const auto& spec : specs) map_names.push_back(spec.name);
  for (std::size_t i = 0; i < specs.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (specs[i].name == specs[j].name) {
        root.error("operators", "two feature maps are named " + in_quotes(specs[i].name));
      }
    }
  }

  bool disparity_features_given = false;
  if (auto reader = root.optional_map("disparity")) {
    DisparityConfig& d = config.disparity;
    d.enabled = reader->boolean_or("enabled", true);
    disparity_features_given = reader->has("features");
    if (disparity_features_given) {
      d.features = reader->strings("features");
      if (d.features.empty()) reader->error("features", "expected at least one feature map");
      for (std::size_t i = 0; i < d.features.size(); ++i) {
        check_map_name(*reader, "features", d.features[i], map_names, i, true);
      }
    }
    d.search_range_px = reader->number_or("search_range_px", d.search_range_px,
                                          config::Range::closed(0, kMaxSearchRange_px));
    d.window_half_px = static_cast<int>(reader->integer_or(
        "window_half_px", d.window_half_px, config::Range::closed(0, kMaxLevelSide_px / 2)));
    if (2 * d.window_half_px + 1 > config.retina.width_px) {
      reader->error("window_half_px", "a window of " + std::to_string(2 * d.window_half_px + 1) +
                                          " px does not fit a retina " +
                                          std::to_string(config.retina.width_px) + " px wide");
    }
    d.refine_range_px = static_cast<int>(
        reader->integer_or("refine_range_px", d.refine_range_px, config::Range::closed(1, 64)));
    d.min_texture_rms =
        reader->number_or("min_texture_rms", d.min_texture_rms, config::Range::non_negative());
    d.scan_range_px = reader->number_or("scan_range_px", d.scan_range_px,
                                        config::Range::closed(0, kMaxSearchRange_px));
    d.scan_window_px = reader->number_or("scan_window_px", d.scan_window_px,
                                         config::Range::closed(1, kMaxSearchRange_px));
    reader->finish();
  }
  if (!disparity_features_given) {
    // The estimator is built whether or not disparity is enabled, so its default maps must exist
    // in this operator set even when a disparity section sets other keys only.
    for (const auto& name : config.disparity.features) {
      if (!contains(map_names, name)) {
        root.error("operators", "the default disparity feature " + in_quotes(name) +
                                    " is not made by this operator set; set disparity.features");
      }
    }
  }

  if (auto reader = root.optional_map("motion")) {
    MotionConfig& m = config.motion;
    m.enabled = reader->boolean_or("enabled", true);
    m.sigma_px = reader->number_or("sigma_px", m.sigma_px, config::Range::closed(0.3, 32.0));
    m.iterations = static_cast<int>(
        reader->integer_or("iterations", m.iterations, config::Range::closed(1, 50)));
    m.min_eigenvalue =
        reader->number_or("min_eigenvalue", m.min_eigenvalue, config::Range::non_negative());
    m.rekey_shift_px =
        reader->number_or("rekey_shift_px", m.rekey_shift_px, config::Range::closed(0.5, 64.0));
    m.rekey_frames = static_cast<int>(
        reader->integer_or("rekey_frames", m.rekey_frames, config::Range::closed(1, 1000)));
    reader->finish();
  }

  if (auto reader = root.optional_map("moments")) {
    MomentsConfig& m = config.moments;
    m.enabled = reader->boolean_or("enabled", true);
    m.map = reader->text_or("map", m.map);
    check_map_name(*reader, "map", m.map, map_names, 0, false);
    const std::string mode = reader->choice_or("mode", {"weighted", "above", "below"}, "above");
    m.mode = mode == "weighted" ? MomentsConfig::Mode::kWeighted
             : mode == "below"  ? MomentsConfig::Mode::kBelow
                                : MomentsConfig::Mode::kAbove;
    m.threshold = reader->number_or("threshold", m.threshold);
    reader->finish();
  }
  if (auto reader = root.optional_map("region")) {
    FixatedRegionConfig& r = config.region;
    r.enabled = reader->boolean_or("enabled", true);
    r.cell_px =
        static_cast<int>(reader->integer_or("cell_px", r.cell_px, config::Range::closed(2, 64)));
    r.cells = static_cast<int>(reader->integer_or("cells", r.cells, config::Range::closed(3, 128)));
    r.max_disparity_px = static_cast<int>(
        reader->integer_or("max_disparity_px", r.max_disparity_px, config::Range::closed(0, 16)));
    r.min_correlation =
        reader->number_or("min_correlation", r.min_correlation, config::Range::closed(-1.0, 1.0));
    r.min_texture_grey =
        reader->number_or("min_texture_grey", r.min_texture_grey, config::Range::non_negative());
    r.seed_radius_cells = static_cast<int>(
        reader->integer_or("seed_radius_cells", r.seed_radius_cells, config::Range::closed(0, 64)));
    r.min_cells = static_cast<int>(
        reader->integer_or("min_cells", r.min_cells, config::Range::closed(1, 16384)));
    reader->finish();
  }
  root.finish();
  return config;
}

SsmConfig load_ssm_config(const std::string& path,
                          const std::vector<config::ConfigOverride>& overrides) {
  config::ConfigDocument document = config::ConfigDocument::load_file(path, overrides);
  config::MapReader root = document.root();
  SsmConfig config = read_ssm_config(root);
  document.issues()->throw_if_any();
  return config;
}

std::string default_ssm_config_path() {
  const std::string path = config::find_shipped_config("perception/ssm.yaml");
  if (path.empty()) {
    // Running on built-in defaults without a word would hide a broken install or a wrong
    // CAMBIO_CONFIG_DIR.
    throw config::ConfigError({config::ConfigIssue{
        config::shipped_config_dir() + "/perception/ssm.yaml", 0, 0, "",
        "cannot read the shipped perception settings: it does not exist (give --config FILE, "
        "or set CAMBIO_CONFIG_DIR to a directory that has perception/ssm.yaml)"}});
  }
  return path;
}

}  // namespace cambio::perception
