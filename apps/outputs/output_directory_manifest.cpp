#include "output_directory.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "output_directory_detail.hpp"

namespace cambio::app::output_directory_detail {

namespace {

/// A manifest is a few kilobytes; anything far larger was not written by a run.
constexpr std::size_t kManifestMaxBytes = 1 << 20;

/// Reads `path` if it is a regular file of at most `max_bytes`, without following a symlink and
/// without blocking on a FIFO or device. Throws OutputError naming what it is instead.
std::string read_regular_file(const fs::path& path, std::size_t max_bytes) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw OutputError(in_quotes(path) + ": cannot open: " + errno_text(errno));
  struct stat info {};
  if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode) ||
      static_cast<std::size_t>(info.st_size) > max_bytes) {
    const bool regular = S_ISREG(info.st_mode);
    ::close(fd);
    throw OutputError(in_quotes(path) + (regular ? ": larger than a manifest can be (" +
                                                       std::to_string(max_bytes) + " bytes)"
                                                 : std::string(": not a regular file")));
  }
  std::string text;
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int error = errno;
      ::close(fd);
      throw OutputError(in_quotes(path) + ": cannot read: " + errno_text(error));
    }
    if (n == 0) break;
    text.append(buffer, static_cast<std::size_t>(n));
    // The file may have grown since fstat.
    if (text.size() > max_bytes) {
      ::close(fd);
      throw OutputError(in_quotes(path) + ": larger than a manifest can be");
    }
  }
  ::close(fd);
  return text;
}

}  // namespace

bool is_plain_output_name(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos &&
         name.find('\0') == std::string::npos && name != OutputDirectory::kLockName &&
         name != OutputDirectory::kManifestName && name.rfind(kStagingMark, 0) != 0;
}

std::set<std::string> read_manifest(const fs::path& directory) {
  const fs::path manifest = directory / OutputDirectory::kManifestName;
  struct stat link_info {};
  if (::lstat(manifest.c_str(), &link_info) != 0) {
    if (errno == ENOENT) return {};
    throw OutputError(in_quotes(manifest) + ": cannot read: " + errno_text(errno));
  }
  const auto unreadable = [&](const std::string& why) {
    return OutputError(in_quotes(directory) + ": its " + OutputDirectory::kManifestName + " " +
                       why +
                       ", so what it holds cannot be told from files cambio did not "
                       "write; remove the directory or choose another --out");
  };
  std::string text;
  try {
    text = read_regular_file(manifest, kManifestMaxBytes);
  } catch (const OutputError& error) {
    throw unreadable(std::string("is unusable (") + error.what() + ")");
  }
  const nlohmann::json json = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded() || !json.is_object() || !json.contains("files") ||
      !json["files"].is_array()) {
    throw unreadable("is unreadable");
  }
  std::set<std::string> files;
  for (const auto& name : json["files"]) {
    if (!name.is_string() || !is_plain_output_name(name.get<std::string>())) {
      throw unreadable("lists " + name.dump() + ", which is not a plain file name a run writes");
    }
    files.insert(name.get<std::string>());
  }
  return files;
}

void check_only_cambio_files(const fs::path& directory, const std::set<std::string>& listed) {
  std::error_code error;
  for (fs::directory_iterator it(directory, error), end; !error && it != end; it.increment(error)) {
    const std::string name = it->path().filename().string();
    if (name == OutputDirectory::kLockName || name == OutputDirectory::kManifestName) continue;
    if (listed.count(name) != 0) {
      // A run writes regular files only; a listed name that is a directory (or a symlink to
      // one) would make replacing the set remove what cambio never wrote.
      std::error_code status_error;
      if (!it->is_symlink(status_error) && it->is_regular_file(status_error)) continue;
      throw OutputError(in_quotes(directory) + " holds " + in_quotes(name) +
                        ", which its manifest lists but which is not a regular file a run "
                        "writes; remove it or choose another --out");
    }
    throw OutputError(in_quotes(directory) + " holds " + in_quotes(name) +
                      ", which no cambio run wrote (" +
                      (listed.empty() ? std::string("the directory has no manifest")
                                      : std::string("its manifest does not list it")) +
                      "); choose an empty or new directory for --out, or remove what is there");
  }
  if (error) throw OutputError(in_quotes(directory) + ": cannot list: " + error.message());
}

std::string manifest_text(const std::string& command, bool complete,
                          const std::set<std::string>& files) {
  nlohmann::json manifest;
  manifest["written_by"] = "cambio " + command;
  manifest["complete"] = complete;
  manifest["files"] = std::vector<std::string>(files.begin(), files.end());
  return manifest.dump(2) + "\n";
}

}  // namespace cambio::app::output_directory_detail
