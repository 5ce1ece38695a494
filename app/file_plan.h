#pragma once
// The files a command reads and writes, checked before any work starts: a mistake in an output path must show before
// minutes of rendering, not after, and no command may write over one of its own inputs (a heatmap over the reference,
// a VPL file over the scene).

#include <string>
#include <vector>

#include "app/cli.h"
#include "renderer/image/image_io.h"
#include "renderer/offline/progressive.h"
#include "renderer/settings.h"

namespace vplab::cli {

enum class OutputKind {
  Image,        ///< .exr, .pfm or .png, decided by the extension
  LinearImage,  ///< .exr or .pfm
  Png,          ///< .png
  Text,         ///< any name (JSON, CSV)
};

class FilePlan {
 public:
  /// A file the command reads (checked by the command when it reads it).
  void input(const std::string& path);
  /// A file the command will write, named on the command line by `option` ("--out").
  void output(const std::string& option, const std::string& path, OutputKind kind);
  /// Throws CliError naming the option when an output has the wrong extension, names an input or another output, or
  /// lies in a folder that does not exist or does not take a new file.
  void check() const;

 private:
  struct Output {
    std::string option, path;
    OutputKind kind;
  };
  std::vector<std::string> inputs_;
  std::vector<Output> outputs_;
};

/// --out FILE (-o; .exr, .pfm or .png, by the extension) and --png FILE (an extra tonemapped copy).
std::vector<OptionSpec> imageOutputOptions();
/// The plan of a rendering command: its inputs (the positional scene, --settings, --ref when offered) and its
/// --out/--png outputs. Throws CliError when neither output is given.
FilePlan imageOutputPlan(const CommandLine& cl);

/// The output folder of a sweep (bench, stability), made and checked before the sweep starts: CliError when it is a
/// file, cannot be made, takes no new file, or is one of the inputs.
void requireOutputFolder(const std::string& folder, const std::vector<std::string>& inputs);

/// What a render writes with its linear image (image_io.h ImageInfo): components, method, spp and every setting.
ImageInfo renderInfo(const Settings& settings, const char* method, int samplesPerPixel);
/// renderInfo() of a finished offline render: its samples per pixel and the NaN/Inf samples it left out
/// ("nonFiniteSamples").
ImageInfo renderInfo(const Settings& settings, const char* method, const ProgressiveResult& result);
/// "4 spp, 0 NaN/Inf samples" for a command's summary; a warning on stderr when any sample was not finite.
std::string describeSamples(const char* command, const ProgressiveResult& result);

/// Throws CliError when a buffer of `bytes` (what: "the 16384x16384 reference image") exceeds the memory this process
/// may still use (MemAvailable, and the address-space limit when one is set), before the work that needs it starts.
void requireMemory(double bytes, const std::string& what);

}  // namespace vplab::cli
