#include "renderer/core/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <vector>

namespace vplab {

namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what, int error) {
  throw FileWriteError(path + ": " + what + ": " + std::strerror(error));
}

std::string folderOf(const std::string& path) {
  std::filesystem::path parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? "." : parent.string();
}

/// A new empty file "<path>.tmp-XXXXXX" beside the target; returns its descriptor and fills tempPath.
int createTemporary(const std::string& path, std::string& tempPath) {
  std::string pattern = path + ".tmp-XXXXXX";
  std::vector<char> name(pattern.begin(), pattern.end());
  name.push_back('\0');
  int fd = mkstemp(name.data());
  if (fd < 0) fail(path, "cannot create a file in " + folderOf(path), errno);
  tempPath = name.data();
  return fd;
}

/// The absolute, normal form of a path whose folders exist (symbolic links resolved), lexical otherwise.
std::filesystem::path normalPath(const std::string& path) {
  std::error_code ec;
  std::filesystem::path p = std::filesystem::weakly_canonical(path, ec);
  if (ec) p = std::filesystem::absolute(path, ec).lexically_normal();
  return p;
}

}  // namespace

void writeFileAtomically(const std::string& path, std::string_view bytes) {
  if (std::filesystem::is_directory(path)) throw FileWriteError(path + ": is a folder");
  std::string temp;
  int fd = createTemporary(path, temp);
  auto abandon = [&](const std::string& what, int error) {
    ::close(fd);
    ::unlink(temp.c_str());
    fail(path, what, error);
  };
  // mkstemp makes the file private (0600); an output is an ordinary file (0644 less the umask is not readable
  // without changing the process umask, so 0644).
  if (::fchmod(fd, 0644) != 0) abandon("cannot set permissions", errno);
  std::size_t done = 0;
  while (done < bytes.size()) {
    ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      abandon("write failed after " + std::to_string(done) + " of " + std::to_string(bytes.size()) + " bytes",
              n < 0 ? errno : ENOSPC);
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) abandon("flush to disk failed", errno);
  if (::close(fd) != 0) {
    int error = errno;
    ::unlink(temp.c_str());
    fail(path, "close failed", error);
  }
  if (::rename(temp.c_str(), path.c_str()) != 0) {
    int error = errno;
    ::unlink(temp.c_str());
    fail(path, "cannot rename the finished file into place", error);
  }
}

void requireWritableFolder(const std::string& path) {
  std::string folder = folderOf(path);
  std::error_code ec;
  if (!std::filesystem::is_directory(folder, ec)) throw FileWriteError(path + ": folder " + folder + " does not exist");
  if (std::filesystem::is_directory(path, ec)) throw FileWriteError(path + ": is a folder");
  std::string temp;
  int fd = createTemporary(path, temp);
  ::close(fd);
  ::unlink(temp.c_str());
}

bool samePath(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (std::filesystem::exists(a, ec) && std::filesystem::exists(b, ec) && std::filesystem::equivalent(a, b, ec))
    return true;
  return normalPath(a) == normalPath(b);
}

}  // namespace vplab
