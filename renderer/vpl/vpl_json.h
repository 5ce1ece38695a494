#pragma once
// A VplSet as JSON, for debugging and teaching: inspect the VPLs of a scene, plot them, or feed the same set to both
// renderers. Floats are written with full round-trip precision, so save + load gives back the same set.

#include "renderer/vpl/vpl.h"

#include <stdexcept>
#include <string>

namespace vplab {

struct VplJsonError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// {"stats": {...}, "vpls": [{"position": [x,y,z], ...}], "rejected": [...]}.
std::string vplSetToJson(const VplSet& set);
/// Parses what vplSetToJson() writes; throws VplJsonError naming the JSON path of the first problem.
VplSet vplSetFromJson(const std::string& text);

/// Writes to a file; throws VplJsonError (message starts with the file name) when it cannot be written.
void saveVplSet(const std::string& path, const VplSet& set);
/// Reads a file; throws VplJsonError (message starts with the file name) on I/O or format problems.
VplSet loadVplSet(const std::string& path);

}  // namespace vplab
