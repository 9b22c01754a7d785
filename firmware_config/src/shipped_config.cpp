#include "cambio/config/shipped_config.hpp"

#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "cambio/config/config_error.hpp"
#include "cambio/config/echoed_text.hpp"

namespace cambio::config {

namespace fs = std::filesystem;

std::string shipped_config_dir() {
  if (const char* from_env = std::getenv("CAMBIO_CONFIG_DIR"); from_env && *from_env) {
    // The user named where the configuration is: a directory that is not there is their mistake
    // to hear about, never a reason to run on other files or on built-in defaults.
    std::error_code error;
    if (!fs::is_directory(from_env, error)) {
      const bool exists = fs::exists(from_env, error);
      throw ConfigError({ConfigIssue{
          "environment", 0, 0, "CAMBIO_CONFIG_DIR",
          "expected the directory of Câmbio's configuration (rigs/, scenes/, experiments/, "
          "perception/), found " +
              in_quotes(from_env) + (exists ? ": not a directory" : ": it does not exist")}});
    }
    return from_env;
  }
  const fs::path install_dir = CAMBIO_INSTALL_CONFIG_DIR;
  std::error_code error;
  if (fs::is_directory(install_dir, error)) {
    // <prefix>/share/cambio/firmware_config: the program is installed when it runs from under
    // <prefix>; a build tree's program uses the source tree even if an older install exists.
    const fs::path prefix = install_dir.parent_path().parent_path().parent_path();
    const fs::path program = fs::read_symlink("/proc/self/exe", error);
    if (!error) {
      const auto relative = program.lexically_relative(prefix);
      if (!relative.empty() && *relative.begin() != "..") return install_dir.string();
    }
  }
  return CAMBIO_SOURCE_CONFIG_DIR;
}

std::string find_shipped_config(std::string_view relative_path) {
  const fs::path path = fs::path(shipped_config_dir()) / relative_path;
  std::error_code error;
  return fs::exists(path, error) ? path.string() : std::string();
}

std::string resolve_config_argument(std::string_view kind, const std::string& argument) {
  std::error_code error;
  if (fs::exists(argument, error)) return argument;
  fs::path relative = fs::path(kind) / argument;
  if (relative.extension() != ".yaml") relative += ".yaml";
  const std::string shipped = find_shipped_config(relative.string());
  return shipped.empty() ? argument : shipped;
}

}  // namespace cambio::config
