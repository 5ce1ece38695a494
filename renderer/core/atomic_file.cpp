#include "renderer/core/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
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

/// What an existing special file is, for messages; empty for a regular file or a path that does not exist.
std::string specialKind(const struct stat& st) {
  if (S_ISCHR(st.st_mode)) return "a character device";
  if (S_ISFIFO(st.st_mode)) return "a FIFO";
  if (S_ISBLK(st.st_mode)) return "a block device";
  if (S_ISSOCK(st.st_mode)) return "a socket";
  if (S_ISDIR(st.st_mode)) return "a folder";
  if (!S_ISREG(st.st_mode)) return "not a regular file";
  return {};
}

/// FIFOs opened by requireWritableFolder() before the work, kept open until written: closing one would send its
/// reader an end of file before the output comes.
std::mutex heldFifosMutex;
std::map<std::string, int> heldFifos;

/// Opens an existing FIFO for writing without waiting: a FIFO without a reader is refused rather than waited on.
int openFifo(const std::string& path) {
  int fd = ::open(path.c_str(), O_WRONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) {
    if (errno == ENXIO) throw FileWriteError(path + ": is a FIFO that no program reads; start the reader first");
    fail(path, "cannot open a FIFO for writing", errno);
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  return fd;
}

/// Writes into an existing character device or FIFO in place: no temporary, no rename, no truncation, no fsync
/// (devices refuse it).
void writeInPlace(const std::string& path, const struct stat& st, std::string_view bytes) {
  int fd = -1;
  if (S_ISFIFO(st.st_mode)) {
    std::lock_guard lock(heldFifosMutex);
    if (auto it = heldFifos.find(path); it != heldFifos.end()) {
      fd = it->second;
      heldFifos.erase(it);
    }
  }
  if (fd < 0) fd = S_ISFIFO(st.st_mode) ? openFifo(path) : ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd < 0) fail(path, "cannot open " + specialKind(st) + " for writing", errno);
  std::size_t done = 0;
  while (done < bytes.size()) {
    ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      int error = n < 0 ? errno : ENOSPC;
      ::close(fd);
      fail(path, "write failed after " + std::to_string(done) + " of " + std::to_string(bytes.size()) + " bytes",
           error);
    }
    done += static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0) fail(path, "close failed", errno);
}

/// Throws for an existing target that is neither a regular file, a character device nor a FIFO.
void refuseUnwritableKind(const std::string& path, const struct stat& st) {
  if (S_ISDIR(st.st_mode)) throw FileWriteError(path + ": is a folder");
  if (!S_ISREG(st.st_mode) && !S_ISCHR(st.st_mode) && !S_ISFIFO(st.st_mode))
    throw FileWriteError(path + ": is " + specialKind(st) +
                         "; vplab writes regular files, character devices (/dev/null) and FIFOs only");
}

}  // namespace

void writeFileAtomically(const std::string& path, std::string_view bytes) {
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    refuseUnwritableKind(path, st);
    if (!S_ISREG(st.st_mode)) return writeInPlace(path, st, bytes);
  }
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
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    refuseUnwritableKind(path, st);
    // A device or FIFO is written in place: what matters is the right to write it, not its folder (/dev). A FIFO is
    // opened now, so that one without a reader is refused before the work, and held open until it is written.
    if (!S_ISREG(st.st_mode)) {
      if (::access(path.c_str(), W_OK) != 0) fail(path, "cannot write " + specialKind(st), errno);
      if (S_ISFIFO(st.st_mode)) {
        std::lock_guard lock(heldFifosMutex);
        if (!heldFifos.count(path)) heldFifos[path] = openFifo(path);
      }
      return;
    }
  }
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

std::string describeBytes(std::uint64_t bytes) {
  char text[64];
  if (bytes >= (1ull << 30))
    std::snprintf(text, sizeof text, "%.3g GiB", static_cast<double>(bytes) / double(1ull << 30));
  else if (bytes >= (1ull << 20))
    std::snprintf(text, sizeof text, "%.3g MiB", static_cast<double>(bytes) / double(1ull << 20));
  else
    std::snprintf(text, sizeof text, "%llu bytes", static_cast<unsigned long long>(bytes));
  return text;
}

std::uint64_t requireInputFile(const std::string& path, std::uint64_t maxBytes, const std::string& what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) {
    int error = errno;
    if (error == ENOENT) throw FileReadError(path + ": no such file");
    throw FileReadError(path + ": cannot open: " + std::strerror(error));
  }
  if (S_ISDIR(st.st_mode)) throw FileReadError(path + ": is a folder, not " + what);
  // A FIFO would block until a writer comes (forever, often) and a device such as /dev/zero never ends.
  if (!S_ISREG(st.st_mode)) throw FileReadError(path + ": is " + specialKind(st) + ", not a regular file");
  auto size = static_cast<std::uint64_t>(st.st_size);
  if (size > maxBytes)
    throw FileReadError(path + ": " + describeBytes(size) + ", larger than the " + describeBytes(maxBytes) +
                        " that vplab reads as " + what);
  return size;
}

std::string readInputFile(const std::string& path, std::uint64_t maxBytes, const std::string& what) {
  requireInputFile(path, maxBytes, what);
  int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) throw FileReadError(path + ": cannot open: " + std::strerror(errno));
  struct stat st {};
  // The path may have changed between the two looks; the open file is what counts.
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw FileReadError(path + ": not a regular file");
  }
  std::string bytes;
  char buffer[1 << 16];
  for (;;) {
    ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      int error = errno;
      ::close(fd);
      throw FileReadError(path + ": read error: " + std::strerror(error));
    }
    if (n == 0) break;
    bytes.append(buffer, static_cast<std::size_t>(n));
    if (bytes.size() > maxBytes) {
      ::close(fd);
      throw FileReadError(path + ": grew past the " + describeBytes(maxBytes) + " that vplab reads as " + what);
    }
  }
  ::close(fd);
  return bytes;
}

}  // namespace vplab
