#include "output_directory.hpp"

#include <fcntl.h>

#include <cerrno>
#include <cstdio>
#include <system_error>

#include "output_directory_detail.hpp"

namespace cambio::app {

namespace fs = std::filesystem;
using namespace output_directory_detail;

void OutputDirectory::commit() {
  if (committed_) return;
  make_staging_directory();
  write_file_synced(staging_ / kManifestName, bytes_of(manifest_text(command_, true, staged_)));

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
  std::set<std::string> both = previous_;
  both.insert(staged_.begin(), staged_.end());
  const fs::path during_path = staging_ / ".manifest-during";
  write_file_synced(during_path, bytes_of(manifest_text(command_, false, both)));
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

}  // namespace cambio::app
