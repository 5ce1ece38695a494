#include "app/comparison.h"

#include <cstdio>

#include "app/cli.h"
#include "renderer/core/text.h"

namespace vplab::cli {

std::vector<std::string> infoMismatches(const ImageInfo& image, const ImageInfo& reference) {
  std::vector<std::string> lines;
  auto a = image.find("components"), b = reference.find("components");
  if (a != image.end() && b != reference.end() && a->second != b->second)
    lines.push_back("the image holds " + a->second + " light but the reference holds " + b->second +
                    " light (--components)");
  return lines;
}

Image readReference(const std::string& path, const Settings& settings, const ImageInfo& render, const char* command) {
  if (!isLinearFormat(imageFormatFromPath(path)))
    throw CliError("option --ref: " + path + " is a tonemapped PNG; compare against linear radiance (.exr or .pfm)");
  Image reference = readImage(path);
  if (reference.width != settings.width || reference.height != settings.height)
    throw CliError("option --ref: " + path + " is " + std::to_string(reference.width) + "x" +
                   std::to_string(reference.height) + ", the render is " + std::to_string(settings.width) + "x" +
                   std::to_string(settings.height));
  for (const std::string& line : infoMismatches(render, readImageInfo(path)))
    std::fprintf(stderr, "vplab %s: warning: %s\n", command, printable(line).c_str());
  return reference;
}

}  // namespace vplab::cli
