#pragma once
// Every file vplab writes goes through writeFileAtomically(): the bytes go to a temporary file in the target's own
// folder, every write, the flush to disk and the close are checked, and only then is the temporary renamed over the
// target. A full disk, a read-only folder or a crash therefore leaves either the old file or no file, never a cut one,
// and a command never reports "wrote" for a file that is not completely there.
//
// A target that exists and is not a regular file is never replaced: a rename over /dev/null (as root) or over a FIFO
// would destroy it. A character device (/dev/null, /dev/stdout's terminal) or a FIFO with a reader is written
// directly; a block device or a socket is refused.
//
// Inputs are read by readInputFile(): only a regular file, bounded in size before it is read, so that a FIFO cannot
// hang a command and /dev/zero cannot fill the memory; every message names the path.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace vplab {

/// A file that could not be written; the message starts with the path.
struct FileWriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// A file that could not be read; the message starts with the path.
struct FileReadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Replaces (or creates) `path` with exactly `bytes`; a character device or FIFO there is written directly, a block
/// device or socket refused. Throws FileWriteError naming the path and the reason
/// (strerror); the target is then unchanged and no temporary is left behind.
void writeFileAtomically(const std::string& path, std::string_view bytes);

/// Throws FileWriteError unless a file can be created in the folder of `path` (which must exist): the check a command
/// makes for each output before it starts minutes of work.
void requireWritableFolder(const std::string& path);

/// True when the two paths name the same file: the same existing file (hard links included), or the same path after
/// making both absolute and normal.
bool samePath(const std::string& a, const std::string& b);

/// Throws FileReadError naming the path unless it is an existing regular file of at most `maxBytes` bytes (what:
/// "a scene", "a settings file", for the message on a file too large). Returns its size.
std::uint64_t requireInputFile(const std::string& path, std::uint64_t maxBytes, const std::string& what);

/// The whole content of the regular file `path` after requireInputFile(); FileReadError naming the path on any error.
std::string readInputFile(const std::string& path, std::uint64_t maxBytes, const std::string& what);

/// "1.5 GiB", "12 MiB", "300 bytes": a size for messages.
std::string describeBytes(std::uint64_t bytes);

}  // namespace vplab
