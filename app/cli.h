#pragma once
// A small declarative command-line parser: each subcommand lists its options, unknown options are errors,
// and --help prints the list. Errors are one line (CliError) and make the command exit with status 2.

#include <functional>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace vplab::cli {

struct CliError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct OptionSpec {
  std::string name;       ///< without the leading "--"
  std::string valueName;  ///< empty for a flag
  std::string help;
  /// A switch that may also be given a value inline: "--rejection" means "--rejection=true"; "--rejection=false".
  bool switchWithValue = false;
  char shortName = 0;  ///< "-o FILE" for "--out FILE"; 0 = none
};

/// "a,b,c": the names of a list, for help texts and error messages.
std::string joined(const std::vector<std::string>& names);

class CommandLine {
 public:
  CommandLine(std::string usage, std::vector<OptionSpec> options);

  void addOptions(const std::vector<OptionSpec>& options);
  /// Parses args (without the program and command names). Returns false when --help was asked for.
  bool parse(const std::vector<std::string>& args);
  std::string help() const;

  bool has(const std::string& name) const;
  std::optional<std::string> value(const std::string& name) const;
  std::string getString(const std::string& name, const std::string& fallback) const;
  int getInt(const std::string& name, int fallback) const;
  float getFloat(const std::string& name, float fallback) const;  ///< accepts "inf"
  /// Parses "WxH".
  void getSize(const std::string& name, int& width, int& height) const;

  const std::vector<std::string>& positional() const { return positional_; }
  /// Throws unless the number of positional arguments is in [min, max].
  void requirePositional(std::size_t min, std::size_t max, const std::string& what) const;

 private:
  const OptionSpec* find(const std::string& name) const;
  std::string suggestion(const std::string& name) const;
  std::string usage_;
  std::vector<OptionSpec> options_;
  std::map<std::string, std::string> values_;
  std::vector<std::string> positional_;
};

struct Command {
  std::string name;
  std::string summary;
  std::function<int(const std::vector<std::string>& args)> run;
};

/// Reports progress on stderr: a redrawn bar on a terminal, plain "label: NN%" lines otherwise.
class ProgressReporter {
 public:
  explicit ProgressReporter(std::string label);
  ~ProgressReporter();
  void update(float fraction);
  void finish();

 private:
  std::string label_;
  bool terminal_;
  int lastPercent_ = -1;
  bool finished_ = false;
};

}  // namespace vplab::cli
