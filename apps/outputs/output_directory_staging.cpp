#include "output_directory.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <system_error>
#include <vector>

#include "output_directory_detail.hpp"

namespace cambio::app::output_directory_detail {

namespace {

bool process_alive(long pid) {
  return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM);
}

/// Whether `directory` is the root of a file system of its own (a bind mount, a Docker volume):
/// it cannot be swapped with a sibling, and files cannot be renamed into it from beside it.
bool is_mount_point(const fs::path& directory) {
  struct statx self {};
  if (::statx(AT_FDCWD, directory.c_str(), 0, STATX_BASIC_STATS, &self) == 0 &&
      (self.stx_attributes_mask & STATX_ATTR_MOUNT_ROOT) != 0) {
    return (self.stx_attributes & STATX_ATTR_MOUNT_ROOT) != 0;
  }
  // Kernels before 5.8: a mount of another file system still shows as another device.
  struct stat own {
  }, parent{};
  if (::stat(directory.c_str(), &own) != 0 || ::stat(directory.parent_path().c_str(), &parent) != 0)
    return false;
  return own.st_dev != parent.st_dev;
}

/// The start of the names of staging directories beside `directory`; the writer's pid follows.
std::string staging_prefix(const fs::path& directory) {
  return "." + directory.filename().string() + kStagingMark;
}

}  // namespace

void remove_abandoned_staging(const fs::path& directory) noexcept {
  const std::string prefix = staging_prefix(directory);
  std::error_code error;
  for (fs::directory_iterator it(directory.parent_path(), error), end; !error && it != end;
       it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    char* parse_end = nullptr;
    const long pid = std::strtol(name.c_str() + prefix.size(), &parse_end, 10);
    if (parse_end == nullptr || *parse_end != '\0' || process_alive(pid)) continue;
    std::error_code ignored;
    fs::remove_all(it->path(), ignored);
  }
}

}  // namespace cambio::app::output_directory_detail

namespace cambio::app {

namespace fs = std::filesystem;
using namespace output_directory_detail;

void OutputDirectory::make_staging_directory() {
  if (!staging_.empty()) return;
  // Beside the target, so the two can be swapped in one rename; inside it where the parent
  // cannot be written (then files are renamed one by one).
  const fs::path beside =
      path_.parent_path() / (staging_prefix(path_) + std::to_string(::getpid()));
  const fs::path inside = path_ / (kStagingMark + std::to_string(::getpid()));
  std::vector<fs::path> candidates{beside, inside};
  if (is_mount_point(path_)) candidates.erase(candidates.begin());
  for (const fs::path& candidate : candidates) {
    std::error_code error;
    fs::remove_all(candidate, error);
    if (fs::create_directory(candidate, error)) {
      staging_ = candidate;
      break;
    }
  }
  if (staging_.empty()) {
    throw OutputError(in_quotes(path_) + ": cannot create a staging directory beside or inside it");
  }
  staging_lock_fd_ = lock_directory(staging_);
  if (staging_lock_fd_ < 0) {
    throw OutputError(in_quotes(staging_) + ": cannot lock: " + errno_text(errno));
  }
}

void OutputDirectory::remove_staging_directory() noexcept {
  if (staging_.empty()) return;
  std::error_code ignored;
  fs::remove_all(staging_, ignored);
  staging_.clear();
}

}  // namespace cambio::app
