#include "evaluation/csv_log.h"

#include <cassert>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "renderer/core/atomic_file.h"

namespace vplab {

std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::vector<std::string> splitCsvLine(const std::string& line) {
  std::vector<std::string> fields;
  std::string cur;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cur += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cur += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.push_back(cur);
      cur.clear();
    } else if (c != '\r') {
      cur += c;
    }
  }
  fields.push_back(cur);
  return fields;
}

std::vector<CsvRow> readCsv(const std::string& path, std::vector<std::string>* headerOut) {
  std::ifstream in(path);
  if (!in) throw CsvError(path + ": cannot open");
  std::string line;
  if (!std::getline(in, line)) throw CsvError(path + ": empty file, expected a header line");
  std::vector<std::string> header = splitCsvLine(line);
  std::vector<CsvRow> rows;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<std::string> f = splitCsvLine(line);
    if (f.size() != header.size()) continue;  // a row cut off by an interruption
    CsvRow row;
    for (std::size_t i = 0; i < f.size(); ++i) row[header[i]] = f[i];
    rows.push_back(std::move(row));
  }
  if (headerOut) *headerOut = header;
  return rows;
}

std::string CsvLog::join(const std::vector<std::string>& key) {
  std::string k;
  for (const std::string& f : key) k += csvField(f) + ",";
  return k;
}

CsvLog::CsvLog(std::string path, std::vector<std::string> header, std::size_t keyColumns)
    : path_(std::move(path)), header_(std::move(header)), keyColumns_(keyColumns) {
  assert(keyColumns_ <= header_.size());
  bool exists = std::filesystem::exists(path_) && std::filesystem::file_size(path_) > 0;
  if (exists) {
    std::vector<std::string> found;
    rows_ = readCsv(path_, &found);
    if (found != header_)
      throw CsvError(path_ + ": the header differs from this version's columns; use another --out or delete it");
    for (const CsvRow& r : rows_) {
      std::vector<std::string> key;
      for (std::size_t i = 0; i < keyColumns_; ++i) key.push_back(r.at(header_[i]));
      keys_.insert(join(key));
    }
  }
  save();
}

void CsvLog::save() const {
  std::string text;
  for (std::size_t i = 0; i < header_.size(); ++i) text += (i ? "," : "") + csvField(header_[i]);
  text += "\n";
  for (const CsvRow& r : rows_) {
    for (std::size_t i = 0; i < header_.size(); ++i) text += (i ? "," : "") + csvField(r.at(header_[i]));
    text += "\n";
  }
  try {
    writeFileAtomically(path_, text);
  } catch (const FileWriteError& e) {
    throw CsvError(e.what());
  }
}

std::size_t CsvLog::removeRows(const std::string& column, const std::string& value) {
  const std::size_t before = rows_.size();
  std::erase_if(rows_, [&](const CsvRow& r) {
    auto it = r.find(column);
    return it != r.end() && it->second == value;
  });
  const std::size_t removed = before - rows_.size();
  if (removed == 0) return 0;
  keys_.clear();
  for (const CsvRow& r : rows_) {
    std::vector<std::string> key;
    for (std::size_t i = 0; i < keyColumns_; ++i) key.push_back(r.at(header_[i]));
    keys_.insert(join(key));
  }
  save();
  return removed;
}

void CsvLog::append(const std::vector<std::string>& values, bool saveNow) {
  assert(values.size() == header_.size());
  CsvRow row;
  for (std::size_t i = 0; i < values.size(); ++i) row[header_[i]] = values[i];
  rows_.push_back(std::move(row));
  if (saveNow) save();
  keys_.insert(join(std::vector<std::string>(values.begin(), values.begin() + static_cast<long>(keyColumns_))));
}

}  // namespace vplab
