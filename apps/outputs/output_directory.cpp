#include "output_directory.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <system_error>

#include <nlohmann/json.hpp>

namespace cambio::app {

namespace fs = std::filesystem;

namespace {

std::string in_quotes(const fs::path& path) {
  return "'" + path.string() + "'";
}

std::string errno_text(int error) {
  return std::strerror(error);
}

/// Writes all of `bytes` to `path` (created or truncated) and fsyncs it: every call checked,
/// EINTR retried, a short write continued.
void write_file_synced(const fs::path& path, std::span<const std::uint8_t> bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw OutputError(in_quotes(path) + ": cannot create: " + errno_text(errno));
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = n < 0 ? errno : EIO;
      ::close(fd);
      throw OutputError(in_quotes(path) + ": write failed after " + std::to_string(done) + " of " +
                        std::to_string(bytes.size()) + " bytes: " + errno_text(error));
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    const int error = errno;
    ::close(fd);
    throw OutputError(in_quotes(path) + ": cannot flush to disk: " + errno_text(error));
  }
  if (::close(fd) != 0) throw OutputError(in_quotes(path) + ": close failed: " + errno_text(errno));
}

void sync_directory(const fs::path& directory) noexcept {
  const int fd = ::open(directory.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  (void)::fsync(fd);  // Best effort: the renames are done either way.
  ::close(fd);
}

/// Opens (creating) `directory`/.cambio-lock and takes an exclusive lock without waiting.
/// Returns the descriptor, or -1 with errno EWOULDBLOCK when another process holds it.
int lock_directory(const fs::path& directory) {
  const fs::path lock_path = directory / OutputDirectory::kLockName;
  const int fd = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0)
    throw OutputError(in_quotes(directory) + ": cannot create its lock file: " + errno_text(errno));
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    ::close(fd);
    errno = error;
    return -1;
  }
  return fd;
}

/// Whether `name` is a plain file name a run may have written: no directory part, not `.` or
/// `..`, not one of the directory's own bookkeeping names. A name read from a file (a manifest)
/// is untrusted: anything else would let it reach outside the directory.
bool is_plain_output_name(const std::string& name) {
  return !name.empty() && name != "." && name != ".." && name.find('/') == std::string::npos &&
         name.find('\0') == std::string::npos && name != OutputDirectory::kLockName &&
         name != OutputDirectory::kManifestName && name.rfind(".cambio-staging-", 0) != 0;
}

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
    if (text.size() > max_bytes) {
      ::close(fd);
      throw OutputError(in_quotes(path) + ": larger than a manifest can be");
    }
  }
  ::close(fd);
  return text;
}

/// The files the manifest in `directory` lists (empty if there is none). Every name must be a
/// plain file name: a manifest naming `/etc/passwd` or `../x` is refused, never acted on.
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

/// Refuses a directory holding anything the manifest does not list.
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

bool process_alive(long pid) {
  return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM);
}

std::string staging_prefix(const fs::path& directory) {
  return "." + directory.filename().string() + ".cambio-staging-";
}

/// Removes staging directories that runs which no longer exist left beside `directory`.
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

}  // namespace

OutputDirectory::OutputDirectory(const fs::path& path, std::string_view command)
    : command_(command) {
  if (path.empty()) throw OutputError("--out '': an empty path names no directory");
  std::error_code error;
  path_ = fs::absolute(path, error).lexically_normal();
  if (error) throw OutputError(in_quotes(path) + ": " + error.message());
  if (path_.filename().empty()) path_ = path_.parent_path();  // "dir/" -> "dir"
  if (fs::exists(path_, error) && !fs::is_directory(path_, error)) {
    throw OutputError(in_quotes(path) + " exists and is not a directory");
  }
  fs::create_directories(path_, error);
  if (error) throw OutputError(in_quotes(path) + ": cannot create: " + error.message());
  // A symlink to a directory: work on the directory it names (swapping would replace the link).
  path_ = fs::canonical(path_, error);
  if (error) throw OutputError(in_quotes(path) + ": " + error.message());
  if (::access(path_.c_str(), W_OK | X_OK) != 0) {
    throw OutputError(in_quotes(path) + ": cannot write into it: " + errno_text(errno));
  }
  // Check before creating anything in it (the lock file), then again under the lock: another
  // run may have committed in between.
  check_only_cambio_files(path_, read_manifest(path_));
  lock_fd_ = lock_directory(path_);
  if (lock_fd_ < 0) {
    throw OutputError(in_quotes(path) +
                      " is being written by another cambio run; wait for it to "
                      "finish or choose another --out");
  }
  previous_ = read_manifest(path_);
  check_only_cambio_files(path_, previous_);
  remove_abandoned_staging(path_);
}

OutputDirectory::~OutputDirectory() {
  if (!committed_) remove_staging_directory();
  if (staging_lock_fd_ >= 0) ::close(staging_lock_fd_);
  if (lock_fd_ >= 0) ::close(lock_fd_);
}

void OutputDirectory::make_staging_directory() {
  if (!staging_.empty()) return;
  // Beside the target, so the two can be swapped in one rename; inside it where the parent
  // cannot be written (then files are renamed one by one).
  const fs::path beside =
      path_.parent_path() / (staging_prefix(path_) + std::to_string(::getpid()));
  const fs::path inside = path_ / (".cambio-staging-" + std::to_string(::getpid()));
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

void OutputDirectory::stage(const std::string& name, std::span<const std::uint8_t> bytes) {
  if (committed_) throw std::logic_error("output directory: stage() after commit()");
  if (!is_plain_output_name(name)) {
    throw OutputError("output file name " + in_quotes(name) + " is not a plain file name");
  }
  make_staging_directory();
  write_file_synced(staging_ / name, bytes);
  staged_.insert(name);
}

void OutputDirectory::stage(const std::string& name, std::string_view text) {
  stage(name, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

void OutputDirectory::commit() {
  if (committed_) return;
  make_staging_directory();
  nlohmann::json manifest;
  manifest["written_by"] = "cambio " + command_;
  manifest["complete"] = true;
  manifest["files"] = std::vector<std::string>(staged_.begin(), staged_.end());
  const std::string text = manifest.dump(2) + "\n";
  write_file_synced(staging_ / kManifestName,
                    std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));

  const bool beside = staging_.parent_path() == path_.parent_path();
  if (beside &&
      ::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, path_.c_str(), RENAME_EXCHANGE) == 0) {
    sync_directory(path_.parent_path());
    committed_ = true;
    // `staging_` now holds the previous run's files.
    remove_staging_directory();
    return;
  }
  // A mount point (a Docker volume as --out) cannot be swapped (EBUSY), nor a directory across
  // file systems (EXDEV): both are written file by file instead.
  if (beside && errno != EINVAL && errno != ENOSYS && errno != EOPNOTSUPP && errno != EBUSY &&
      errno != EXDEV) {
    throw OutputError(in_quotes(path_) +
                      ": cannot put the new files in place: " + errno_text(errno));
  }
  commit_by_renames();
}

void OutputDirectory::commit_by_renames() {
  // While files move one by one the manifest lists both sets and says the set is incomplete,
  // so an interruption leaves nothing unaccounted for and nothing that looks whole.
  nlohmann::json during;
  during["written_by"] = "cambio " + command_;
  during["complete"] = false;
  std::set<std::string> both = previous_;
  both.insert(staged_.begin(), staged_.end());
  during["files"] = std::vector<std::string>(both.begin(), both.end());
  const std::string during_text = during.dump(2) + "\n";
  const fs::path during_path = staging_ / ".manifest-during";
  write_file_synced(
      during_path,
      std::span(reinterpret_cast<const std::uint8_t*>(during_text.data()), during_text.size()));
  if (std::rename(during_path.c_str(), (path_ / kManifestName).c_str()) != 0) {
    throw OutputError(in_quotes(path_) + ": cannot write its manifest: " + errno_text(errno));
  }
  for (const auto& name : staged_) {
    if (std::rename((staging_ / name).c_str(), (path_ / name).c_str()) != 0) {
      throw OutputError(in_quotes(path_ / name) + ": cannot put in place: " + errno_text(errno));
    }
  }
  for (const auto& name : previous_) {
    if (staged_.count(name) != 0) continue;
    std::error_code ignored;
    fs::remove(path_ / name, ignored);
  }
  if (std::rename((staging_ / kManifestName).c_str(), (path_ / kManifestName).c_str()) != 0) {
    throw OutputError(in_quotes(path_) + ": cannot write its manifest: " + errno_text(errno));
  }
  sync_directory(path_);
  committed_ = true;
  remove_staging_directory();
}

void OutputDirectory::remove_staging_directory() noexcept {
  if (staging_.empty()) return;
  std::error_code ignored;
  fs::remove_all(staging_, ignored);
  staging_.clear();
}

}  // namespace cambio::app
