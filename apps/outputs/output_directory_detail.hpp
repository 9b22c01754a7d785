#pragma once

// What OutputDirectory's source files share (output_directory.cpp: claiming the directory and
// staging files; output_directory_lock.cpp: the flock; output_directory_manifest.cpp: reading,
// checking and writing the manifest; output_directory_staging.cpp: the staging directory;
// output_directory_writes.cpp: checked, fsynced writes; output_directory_commit.cpp: putting the
// set in place). Not installed.

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <set>
#include <span>
#include <string>
#include <string_view>

namespace cambio::app::output_directory_detail {

namespace fs = std::filesystem;

/// What every staging directory's name holds, beside the target (after its name) or inside it.
inline constexpr const char* kStagingMark = ".cambio-staging-";

inline std::string in_quotes(const fs::path& path) {
  return "'" + path.string() + "'";
}

inline std::string errno_text(int error) {
  return std::strerror(error);
}

inline std::span<const std::uint8_t> bytes_of(std::string_view text) {
  return std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

/// Writes all of `bytes` to `path` (created or truncated) and fsyncs it: every call checked,
/// EINTR retried, a short write continued. Throws OutputError.
void write_file_synced(const fs::path& path, std::span<const std::uint8_t> bytes);

/// Flushes `directory`'s entries (the renames into it) to disk; best effort, never fails.
void sync_directory(const fs::path& directory) noexcept;

/// Opens (creating) `directory`/.cambio-lock and takes an exclusive lock without waiting.
/// Returns the descriptor, or -1 with errno EWOULDBLOCK when another process holds it. Throws
/// OutputError when the lock file cannot be created.
int lock_directory(const fs::path& directory);

/// Whether `name` is a plain file name a run may have written: no directory part, not `.` or
/// `..`, not one of the directory's own bookkeeping names. A name read from a file (a manifest)
/// is untrusted: anything else would let it reach outside the directory.
bool is_plain_output_name(const std::string& name);

/// The files the manifest in `directory` lists (empty if there is none). Every name must be a
/// plain file name: a manifest naming `/etc/passwd` or `../x` is refused, never acted on.
std::set<std::string> read_manifest(const fs::path& directory);

/// Refuses a directory holding anything the manifest does not list.
void check_only_cambio_files(const fs::path& directory, const std::set<std::string>& listed);

/// The manifest of a set of `files` written by `cambio <command>`, as its file holds it;
/// `complete` false while the set is being put in place file by file.
std::string manifest_text(const std::string& command, bool complete,
                          const std::set<std::string>& files);

/// Removes staging directories that runs which no longer exist left beside `directory`.
void remove_abandoned_staging(const fs::path& directory) noexcept;

}  // namespace cambio::app::output_directory_detail
