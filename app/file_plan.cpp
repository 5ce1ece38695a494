#include "app/file_plan.h"

#include <sys/resource.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/cli.h"
#include "renderer/core/atomic_file.h"
#include "renderer/settings_json.h"

namespace vplab::cli {

void FilePlan::input(const std::string& path) {
  inputs_.push_back(path);
}

void FilePlan::output(const std::string& option, const std::string& path, OutputKind kind) {
  outputs_.push_back({option, path, kind});
  // A PFM's information goes to a sidecar, which is written too.
  if (kind != OutputKind::Text && kind != OutputKind::Png) {
    try {
      if (imageFormatFromPath(path) == ImageFormat::Pfm)
        outputs_.push_back({option + " (its sidecar)", pfmSidecarPath(path), OutputKind::Text});
    } catch (const ImageIoError&) {
      // reported by check()
    }
  }
}

void FilePlan::check() const {
  for (std::size_t i = 0; i < outputs_.size(); ++i) {
    const Output& o = outputs_[i];
    const std::string where = "option " + o.option + ": ";
    if (o.kind != OutputKind::Text) {
      ImageFormat format;
      try {
        format = imageFormatFromPath(o.path);
      } catch (const ImageIoError& e) {
        throw CliError(where + e.what());
      }
      if (o.kind == OutputKind::Png && format != ImageFormat::Png)
        throw CliError(where + "'" + o.path + "' is not .png");
      if (o.kind == OutputKind::LinearImage && !isLinearFormat(format))
        throw CliError(where + "'" + o.path + "' is not .exr or .pfm");
    }
    for (const std::string& in : inputs_)
      if (samePath(o.path, in))
        throw CliError(where + "'" + o.path + "' is an input of this command; refusing to write over it");
    for (std::size_t j = 0; j < i; ++j)
      if (samePath(o.path, outputs_[j].path))
        throw CliError(where + "'" + o.path + "' is also the file of " + outputs_[j].option);
    try {
      requireWritableFolder(o.path);
    } catch (const FileWriteError& e) {
      throw CliError(where + e.what());
    }
  }
}

std::vector<OptionSpec> imageOutputOptions() {
  OptionSpec out{"out", "FILE", "output image: .exr or .pfm (linear radiance) or .png (tonemapped, uses --exposure)"};
  out.shortName = 'o';
  return {out, {"png", "FILE", "also write a tonemapped PNG (uses --exposure)"}};
}

FilePlan imageOutputPlan(const CommandLine& cl) {
  FilePlan plan;
  for (const std::string& p : cl.positional()) plan.input(p);
  if (auto settings = cl.value("settings")) plan.input(*settings);
  if (auto ref = cl.value("ref")) plan.input(*ref);
  auto out = cl.value("out");
  auto png = cl.value("png");
  if (!out && !png) throw CliError("nothing to write: give -o/--out FILE (and/or --png FILE)");
  if (out) plan.output("--out", *out, OutputKind::Image);
  if (png) plan.output("--png", *png, OutputKind::Png);
  return plan;
}

void requireOutputFolder(const std::string& folder, const std::vector<std::string>& inputs) {
  std::error_code ec;
  for (const std::string& in : inputs)
    if (samePath(folder, in)) throw CliError("option --out: '" + folder + "' is an input of this command");
  if (std::filesystem::exists(folder, ec) && !std::filesystem::is_directory(folder, ec))
    throw CliError("option --out: '" + folder + "' is a file, not a folder");
  std::filesystem::create_directories(folder, ec);
  if (ec) throw CliError("option --out: cannot make the folder '" + folder + "': " + ec.message());
  try {
    requireWritableFolder(folder + "/probe");
  } catch (const FileWriteError& e) {
    throw CliError("option --out: " + std::string(e.what()));
  }
}

ImageInfo renderInfo(const Settings& settings, const char* method, int samplesPerPixel) {
  return {{"components", toString(settings.components)},
          {"method", method},
          {"spp", std::to_string(samplesPerPixel)},
          {"settings", settingsToJson(settings)}};
}

ImageInfo renderInfo(const Settings& settings, const char* method, const ProgressiveResult& result) {
  ImageInfo info = renderInfo(settings, method, result.samplesPerPixel);
  info["nonFiniteSamples"] = std::to_string(result.nonFiniteSamples);
  return info;
}

std::string describeSamples(const char* command, const ProgressiveResult& result) {
  const auto bad = static_cast<unsigned long long>(result.nonFiniteSamples);
  if (bad > 0)
    std::fprintf(stderr,
                 "vplab %s: warning: %llu samples were NaN or infinite and are left out of their pixels' means (a "
                 "defect of the estimator, not of the scene)\n",
                 command, bad);
  return std::to_string(result.samplesPerPixel) + " spp, " + std::to_string(bad) + " NaN/Inf samples";
}

namespace {

/// MemAvailable from /proc/meminfo in bytes; 0 when unknown.
double availableMemory() {
  std::ifstream in("/proc/meminfo");
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string key;
    double kib = 0.0;
    if (s >> key >> kib && key == "MemAvailable:") return kib * 1024.0;
  }
  return 0.0;
}

std::string gib(double bytes) {
  std::ostringstream s;
  s.precision(3);
  s << bytes / (1024.0 * 1024.0 * 1024.0) << " GiB";
  return s.str();
}

}  // namespace

void requireMemory(double bytes, const std::string& what) {
  double limit = availableMemory();
  const char* source = "available memory";
  rlimit rl{};
  if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY &&
      (limit == 0.0 || static_cast<double>(rl.rlim_cur) < limit)) {
    limit = static_cast<double>(rl.rlim_cur);
    source = "the address-space limit (ulimit -v)";
  }
  if (limit > 0.0 && bytes > limit)
    throw CliError(what + " needs about " + gib(bytes) + ", more than " + source + " (" + gib(limit) +
                   "); use a smaller --size");
}

}  // namespace vplab::cli
