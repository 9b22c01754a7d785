#include "output_directory.hpp"

#include <unistd.h>

#include <cerrno>
#include <system_error>

#include "output_directory_detail.hpp"

namespace cambio::app {

namespace fs = std::filesystem;
using namespace output_directory_detail;

namespace {

/// `path` made absolute and created if missing, as the directory it names (a symlink resolved);
/// refused unless this process may write into it. Messages name `path` as the user gave it.
fs::path writable_directory(const fs::path& path) {
  std::error_code error;
  fs::path directory = fs::absolute(path, error).lexically_normal();
  if (error) throw OutputError(in_quotes(path) + ": " + error.message());
  if (directory.filename().empty()) directory = directory.parent_path();  // "dir/" -> "dir"
  if (fs::exists(directory, error) && !fs::is_directory(directory, error)) {
    throw OutputError(in_quotes(path) + " exists and is not a directory");
  }
  fs::create_directories(directory, error);
  if (error) throw OutputError(in_quotes(path) + ": cannot create: " + error.message());
  // A symlink to a directory: work on the directory it names (swapping would replace the link).
  directory = fs::canonical(directory, error);
  if (error) throw OutputError(in_quotes(path) + ": " + error.message());
  if (::access(directory.c_str(), W_OK | X_OK) != 0) {
    throw OutputError(in_quotes(path) + ": cannot write into it: " + errno_text(errno));
  }
  return directory;
}

}  // namespace

OutputDirectory::OutputDirectory(const fs::path& path, std::string_view command)
    : command_(command) {
  if (path.empty()) throw OutputError("--out '': an empty path names no directory");
  path_ = writable_directory(path);
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
  stage(name, bytes_of(text));
}

}  // namespace cambio::app
