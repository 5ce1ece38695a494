#pragma once
// What two images must agree on before their difference means anything: the same size, both linear radiance (or both
// tonemapped), and the same radiance components. The recorded ImageInfo (image_io.h) says what each one holds.

#include <string>
#include <vector>

#include "renderer/image/image_io.h"
#include "renderer/settings.h"

namespace vplab::cli {

/// One line per recorded property that differs between the two (components, ...); empty when they agree or when
/// either image records nothing.
std::vector<std::string> infoMismatches(const ImageInfo& image, const ImageInfo& reference);

/// Reads the reference a render is compared against (--ref), before the render starts. CliError when it is not
/// settings.width x settings.height or is a tonemapped PNG (the render is linear); a warning on stderr, prefixed
/// with `command`, for each infoMismatches() line.
Image readReference(const std::string& path, const Settings& settings, const ImageInfo& render, const char* command);

}  // namespace vplab::cli
