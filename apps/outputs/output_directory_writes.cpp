#include "output_directory.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>

#include "output_directory_detail.hpp"

namespace cambio::app::output_directory_detail {

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

}  // namespace cambio::app::output_directory_detail
