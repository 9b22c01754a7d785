#pragma once

#include <cstdint>
#include <filesystem>
#include <set>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace cambio::app {

/// A problem with an --out directory or with writing into it; the message names the path and
/// the reason. Commands exit 2 on it (the user chose the destination).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The --out directory of one command run. Claimed before any work starts, so a bad destination
/// fails at once instead of after a 4-second run; filled by staging files; committed as a set.
///
/// Guarantees:
///  - never a file the program did not write: the directory must be empty or hold only what an
///    earlier cambio run wrote, as its manifest (`.cambio-manifest.json`) lists;
///  - one run at a time: an exclusive lock (flock on `.cambio-lock`) is held from claim to
///    destruction, and a second run into the same directory is refused at once;
///  - nothing half-written: staged files are written in full and fsynced in a staging
///    directory beside the target; commit() swaps the two directories atomically
///    (renameat2 RENAME_EXCHANGE), so readers see the previous run's set or the new one, never
///    a mix, and no file of the previous run stays behind. Where the file system cannot swap
///    directories, files are renamed one by one with the manifest marking the set incomplete
///    until the last rename;
///  - every write is checked (a full disk is an OutputError, never a 0-byte file and "wrote").
class OutputDirectory {
 public:
  /// Creates `path` (and its parents) if missing, checks it is a writable directory holding
  /// nothing cambio did not write, and takes the lock. Throws OutputError.
  OutputDirectory(const std::filesystem::path& path, std::string_view command);
  ~OutputDirectory();
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;

  /// Writes one file of the set (a plain name, no directories) to the staging area, fsynced.
  /// Throws OutputError.
  void stage(const std::string& name, std::span<const std::uint8_t> bytes);
  void stage(const std::string& name, std::string_view text);

  /// Makes the staged files the directory's contents, replacing the previous run's set. Throws
  /// OutputError; the previous set is then left as it was.
  void commit();

  const std::filesystem::path& path() const { return path_; }
  /// The files committed (or staged, before commit()).
  const std::set<std::string>& files() const { return staged_; }

  static constexpr const char* kManifestName = ".cambio-manifest.json";
  static constexpr const char* kLockName = ".cambio-lock";

 private:
  void make_staging_directory();
  void commit_by_renames();
  void remove_staging_directory() noexcept;

  std::filesystem::path path_;
  std::string command_;
  std::filesystem::path staging_;
  std::set<std::string> previous_;  // What the previous run's manifest lists.
  std::set<std::string> staged_;
  int lock_fd_ = -1;
  int staging_lock_fd_ = -1;
  bool committed_ = false;
};

}  // namespace cambio::app
