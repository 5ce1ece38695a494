#include "app/cli.h"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <mutex>
#include <sstream>

namespace vplab::cli {

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ",") + n;
  return out;
}

CommandLine::CommandLine(std::string usage, std::vector<OptionSpec> options)
    : usage_(std::move(usage)), options_(std::move(options)) {}

void CommandLine::addOptions(const std::vector<OptionSpec>& options) {
  options_.insert(options_.end(), options.begin(), options.end());
}

const OptionSpec* CommandLine::find(const std::string& name) const {
  for (const OptionSpec& o : options_)
    if (o.name == name) return &o;
  return nullptr;
}

bool CommandLine::parse(const std::vector<std::string>& args) {
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--help" || a == "-h") return false;
    if (a.size() == 2 && a[0] == '-' && a[1] != '-') {
      const OptionSpec* spec = nullptr;
      for (const OptionSpec& o : options_)
        if (o.shortName == a[1]) spec = &o;
      if (!spec) throw CliError("unknown option " + a + " (see --help)");
      if (spec->valueName.empty()) {
        values_[spec->name] = "1";
      } else {
        if (i + 1 >= args.size()) throw CliError("option " + a + " needs a value <" + spec->valueName + ">");
        values_[spec->name] = args[++i];
      }
    } else if (a.size() > 2 && a.rfind("--", 0) == 0) {
      std::string name = a.substr(2), value;
      bool inlineValue = false;
      if (std::size_t eq = name.find('='); eq != std::string::npos) {
        value = name.substr(eq + 1);
        name = name.substr(0, eq);
        inlineValue = true;
      }
      const OptionSpec* spec = find(name);
      if (!spec) throw CliError("unknown option --" + name + suggestion(name) + " (see --help)");
      if (spec->switchWithValue) {
        values_[name] = inlineValue ? value : "true";
      } else if (spec->valueName.empty()) {
        if (inlineValue) throw CliError("option --" + name + " takes no value");
        values_[name] = "1";
      } else {
        if (!inlineValue) {
          if (i + 1 >= args.size()) throw CliError("option --" + name + " needs a value <" + spec->valueName + ">");
          value = args[++i];
        }
        values_[name] = value;
      }
    } else {
      positional_.push_back(a);
    }
  }
  return true;
}

// "; did you mean --clamp-bound?" for "--clamp": the options whose name contains the one typed.
std::string CommandLine::suggestion(const std::string& name) const {
  std::string list;
  for (const OptionSpec& o : options_)
    if (name.size() >= 3 && o.name.find(name) != std::string::npos) list += (list.empty() ? "--" : " or --") + o.name;
  return list.empty() ? "" : "; did you mean " + list + "?";
}

std::string CommandLine::help() const {
  std::ostringstream s;
  s << "usage: " << usage_ << "\n";
  if (!options_.empty()) s << "options:\n";
  for (const OptionSpec& o : options_) {
    std::string left = std::string(o.shortName ? "  -" + std::string(1, o.shortName) + ", " : "  ") + "--" + o.name;
    if (o.switchWithValue)
      left += "[=" + o.valueName + "]";
    else if (!o.valueName.empty())
      left += " <" + o.valueName + ">";
    s << left;
    for (std::size_t pad = left.size(); pad < 36; ++pad) s << ' ';
    s << " " << o.help << "\n";
  }
  return s.str();
}

bool CommandLine::has(const std::string& name) const { return values_.count(name) > 0; }

std::optional<std::string> CommandLine::value(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) return std::nullopt;
  return it->second;
}

std::string CommandLine::getString(const std::string& name, const std::string& fallback) const {
  return value(name).value_or(fallback);
}

int CommandLine::getInt(const std::string& name, int fallback) const {
  auto v = value(name);
  if (!v) return fallback;
  try {
    std::size_t used = 0;
    long long x = std::stoll(*v, &used);
    if (used != v->size() || x < -2147483648LL || x > 2147483647LL) throw std::invalid_argument("");
    return static_cast<int>(x);
  } catch (const std::exception&) {
    throw CliError("option --" + name + ": '" + *v + "' is not an integer");
  }
}

float CommandLine::getFloat(const std::string& name, float fallback) const {
  auto v = value(name);
  if (!v) return fallback;
  if (*v == "inf" || *v == "infinity") return INFINITY;
  try {
    std::size_t used = 0;
    float x = std::stof(*v, &used);
    if (used != v->size() || std::isnan(x)) throw std::invalid_argument("");
    return x;
  } catch (const std::exception&) {
    throw CliError("option --" + name + ": '" + *v + "' is not a number");
  }
}

void CommandLine::getSize(const std::string& name, int& width, int& height) const {
  auto v = value(name);
  if (!v) return;
  std::size_t x = v->find('x');
  try {
    if (x == std::string::npos) throw std::invalid_argument("");
    std::size_t u1 = 0, u2 = 0;
    std::string a = v->substr(0, x), b = v->substr(x + 1);
    int w = std::stoi(a, &u1), h = std::stoi(b, &u2);
    if (u1 != a.size() || u2 != b.size()) throw std::invalid_argument("");
    width = w;
    height = h;
  } catch (const std::exception&) {
    throw CliError("option --" + name + ": '" + *v + "' is not WxH (for example 256x256)");
  }
}

void CommandLine::requirePositional(std::size_t min, std::size_t max, const std::string& what) const {
  if (positional_.size() < min) throw CliError("missing " + what + " (see --help)");
  if (positional_.size() > max) throw CliError("unexpected argument '" + positional_[max] + "' (see --help)");
}

ProgressReporter::ProgressReporter(std::string label) : label_(std::move(label)), terminal_(isatty(2) != 0) {}

ProgressReporter::~ProgressReporter() { finish(); }

void ProgressReporter::update(float fraction) {
  static std::mutex mutex;
  std::lock_guard lock(mutex);
  if (finished_) return;
  int percent = static_cast<int>(std::floor(std::fmin(std::fmax(fraction, 0.0f), 1.0f) * 100.0f));
  if (terminal_) {
    if (percent == lastPercent_) return;
    int filled = percent * 30 / 100;
    std::fprintf(stderr, "\r%s [%s%s] %3d%%", label_.c_str(), std::string(filled, '#').c_str(),
                 std::string(30 - filled, '.').c_str(), percent);
  } else {
    // Plain lines every 10% keep CI logs readable.
    if (percent / 10 == lastPercent_ / 10 && lastPercent_ >= 0) return;
    std::fprintf(stderr, "%s: %d%%\n", label_.c_str(), percent);
  }
  lastPercent_ = percent;
  std::fflush(stderr);
}

void ProgressReporter::finish() {
  if (finished_) return;
  if (lastPercent_ >= 0 && lastPercent_ < 100) update(1.0f);
  if (terminal_ && lastPercent_ >= 0) std::fprintf(stderr, "\n");
  finished_ = true;
}

}  // namespace vplab::cli
