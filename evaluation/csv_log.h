#pragma once
// An append-only CSV log for long measurement sweeps: the file is rewritten (atomically, renderer/core/atomic_file.h)
// as soon as each row is measured, so an interrupted sweep keeps what it measured and the file is never cut; reopening
// the same file with the same header loads the rows already there so the sweep can skip them (restart where it
// stopped).

#include <cstddef>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace vplab {

struct CsvError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Quotes a field when it holds a comma, quote or line break (RFC 4180).
std::string csvField(const std::string& text);
/// Splits one line (no embedded line breaks) into fields, undoing csvField's quoting.
std::vector<std::string> splitCsvLine(const std::string& line);

/// One row as column name -> text.
using CsvRow = std::map<std::string, std::string>;

class CsvLog {
 public:
  /// Opens (creating when missing) `path` for appending. An existing file must start with exactly this header,
  /// otherwise CsvError names the file (a sweep must not mix two layouts); a last line cut off by an interruption
  /// (fewer fields than the header) is dropped. keyColumns (a prefix of the header's names) identify a run.
  CsvLog(std::string path, std::vector<std::string> header, std::size_t keyColumns);

  /// True when a row with these key fields (the first keyColumns values, in header order) is already logged.
  bool contains(const std::vector<std::string>& key) const { return keys_.count(join(key)) > 0; }
  /// Appends one row (values in header order; the count must match the header) and, with saveNow, rewrites the file.
  void append(const std::vector<std::string>& values, bool saveNow = true);
  /// Drops every row whose `column` holds `value` and rewrites the file; returns how many were dropped.
  std::size_t removeRows(const std::string& column, const std::string& value);
  /// Rewrites the file with every row (after appends without saving).
  void save() const;

  const std::vector<std::string>& header() const { return header_; }
  /// Every row in the file, loaded and appended, in order.
  const std::vector<CsvRow>& rows() const { return rows_; }
  const std::string& path() const { return path_; }

 private:
  static std::string join(const std::vector<std::string>& key);
  std::string path_;
  std::vector<std::string> header_;
  std::size_t keyColumns_;
  std::set<std::string> keys_;
  std::vector<CsvRow> rows_;
};

/// Reads a whole CSV file with a header line into rows (throws CsvError naming the file when it cannot be read).
std::vector<CsvRow> readCsv(const std::string& path, std::vector<std::string>* header = nullptr);

}  // namespace vplab
