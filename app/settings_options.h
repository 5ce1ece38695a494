#pragma once
// The command-line spelling of Settings, shared by every subcommand that renders. Every flag comes from the settings
// table (renderer/settings.h): its name is the setting's key in kebab case, its help and range are the table's, and
// the default shown is the one the command really uses.

#include "app/cli.h"
#include "renderer/settings.h"

#include <string>
#include <vector>

namespace vplab::cli {

/// --settings F.json, --size WxH (when the command renders an image), and one option per setting that acts on the
/// passes in `use` (SettingUse bits), each help line ending with its value in `defaults`.
std::vector<OptionSpec> settingOptions(const Settings& defaults, unsigned use);

/// Loads --settings first, then copies every option of settingOptions(use) that is present into settings (so they
/// override the file), then validates; throws CliError naming the flag (or the file's key) that is wrong.
void applySettingsOptions(const CommandLine& cl, Settings& settings, unsigned use);

/// The options of the settings named by `keys` (table keys, e.g. "stage") alone, for the commands whose other
/// options are their own (bench, stability).
std::vector<OptionSpec> settingOptions(const Settings& defaults, const std::vector<std::string>& keys);
/// Copies those of them that are present into settings, then validates; throws CliError naming the flag.
void applySettingsOptions(const CommandLine& cl, Settings& settings, const std::vector<std::string>& keys);

}  // namespace vplab::cli
