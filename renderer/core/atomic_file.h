#pragma once
// Every file vplab writes goes through writeFileAtomically(): the bytes go to a temporary file in the target's own
// folder, every write, the flush to disk and the close are checked, and only then is the temporary renamed over the
// target. A full disk, a read-only folder or a crash therefore leaves either the old file or no file, never a cut one,
// and a command never reports "wrote" for a file that is not completely there.

#include <stdexcept>
#include <string>
#include <string_view>

namespace vplab {

/// A file that could not be written; the message starts with the path.
struct FileWriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Replaces (or creates) `path` with exactly `bytes`. Throws FileWriteError naming the path and the reason
/// (strerror); the target is then unchanged and no temporary is left behind.
void writeFileAtomically(const std::string& path, std::string_view bytes);

/// Throws FileWriteError unless a file can be created in the folder of `path` (which must exist): the check a command
/// makes for each output before it starts minutes of work.
void requireWritableFolder(const std::string& path);

/// True when the two paths name the same file: the same existing file (hard links included), or the same path after
/// making both absolute and normal.
bool samePath(const std::string& a, const std::string& b);

}  // namespace vplab
