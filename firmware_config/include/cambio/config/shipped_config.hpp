#pragma once

#include <string>
#include <string_view>

namespace cambio::config {

/// Directory of the shipped YAML (rigs/, scenes/, experiments/, perception/): $CAMBIO_CONFIG_DIR
/// when set; else the install prefix's share/cambio/firmware_config when the running program is
/// installed under that prefix; else the source tree's firmware_config/.
std::string shipped_config_dir();

/// The shipped file at `relative_path` under shipped_config_dir() (e.g. "perception/ssm.yaml"),
/// or empty when there is none. The one place that knows where shipped config files live.
std::string find_shipped_config(std::string_view relative_path);

/// A config file as named on a command line: `argument` itself when it is an existing path,
/// else the shipped `<kind>/<argument>` (".yaml" appended when missing, so `--config pan_tilt`
/// and `--scene vergence` work), else `argument` unchanged for the loader to report as
/// unreadable under the name the user gave.
std::string resolve_config_argument(std::string_view kind, const std::string& argument);

}  // namespace cambio::config
