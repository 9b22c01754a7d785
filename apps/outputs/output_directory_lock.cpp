#include "output_directory.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>

#include "output_directory_detail.hpp"

namespace cambio::app::output_directory_detail {

int lock_directory(const fs::path& directory) {
  const fs::path lock_path = directory / OutputDirectory::kLockName;
  const int fd = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0)
    throw OutputError(in_quotes(directory) + ": cannot create its lock file: " + errno_text(errno));
  if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
    // The caller reads why in errno: close() must not overwrite it.
    const int error = errno;
    ::close(fd);
    errno = error;
    return -1;
  }
  return fd;
}

}  // namespace cambio::app::output_directory_detail
