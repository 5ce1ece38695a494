#pragma once
// The command-line spelling of Settings, shared by every subcommand that renders.

#include "app/cli.h"
#include "renderer/settings.h"

namespace vplab::cli {

/// Image, seed, thread and staging options (--settings, --size, --seed, --threads, --exposure, --stage).
std::vector<OptionSpec> imageOptions();
/// Reference options (--spp, --max-depth, --components).
std::vector<OptionSpec> referenceOptions();
/// Many-light options (--vpls, --bounces, --clamp, --vsl-radius, --reject, --epsilon, ...; GL ones included).
std::vector<OptionSpec> manyLightOptions();

/// Loads --settings first, then copies every other option that is present into settings (so they override the
/// file), then validates; throws CliError naming the bad option or key.
void applySettingsOptions(const CommandLine& cl, Settings& settings);

/// The offline renderers' outputs: --out FILE (.exr, .pfm or .png) and/or --png FILE. Throws CliError when neither is
/// given or an extension is wrong, so that a mistake shows before minutes of rendering.
void checkImageOutputs(const CommandLine& cl);

}  // namespace vplab::cli
