#include "renderer/scene/media_gltf.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "renderer/core/text.h"
#include "renderer/scene/density_grid.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/vdb_grid.h"

namespace vplab {

namespace {

/// Checks the medium's box (volume, a finite inverse, within the coordinate bound); what is wrong, or empty.
std::string boxProblem(const glm::mat4& world, const Medium& m) {
  // Every axis non-zero and the three not (nearly) in one plane, measured scale-free as |det| against the product of
  // the axis lengths.
  double lengths = 1.0;
  for (int i = 0; i < 3; ++i) lengths *= glm::length(glm::dvec3(glm::vec3(world[i])));
  const double det = glm::determinant(glm::dmat3(glm::mat3(world)));
  if (!(lengths > 0.0) || !std::isfinite(lengths) || !(std::abs(det) > kMinMediumBoxSquareness * lengths))
    return "singular transform for a medium box (a zero scale, or axes in one plane): the box has no volume";
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (!std::isfinite(m.boxFromWorld[i][j])) return "medium box too small to invert in float";
  for (const glm::vec3& corner : m.corners())
    if (!withinCoordinateBound(corner)) return "medium box reaches beyond +-" + numberText(kMaxCoordinate) + " m";
  return {};
}

}  // namespace

Medium readMediumExtension(const tinygltf::Value& ext, bool fillsSpace, const glm::mat4& worldFromNode,
                           const std::string& file, const std::string& baseDir, const std::string& at) {
  auto fail = [&](const std::string& where, const std::string& what) -> void {
    throw SceneError(file + ": " + where + ": " + what);
  };
  if (!ext.IsObject()) fail(at, "must be an object with sigmaA, sigmaS and optionally g and density");
  static const char* const known[] = {"sigmaA", "sigmaS", "g", "density", "extensions", "extras"};
  for (const std::string& key : ext.Keys())
    if (std::find_if(std::begin(known), std::end(known), [&](const char* k) { return key == k; }) == std::end(known))
      fail(at + "." + key, "unknown field '" + key + "' (known: sigmaA, sigmaS, g, density, extensions, extras)");
  auto coefficient = [&](const char* key) {
    std::string where = at + "." + key;
    if (!ext.Has(key)) fail(where, "required (RGB in 1/m, e.g. [0.1, 0.1, 0.1])");
    const tinygltf::Value& v = ext.Get(key);
    if (!v.IsArray() || v.ArrayLen() != 3) fail(where, "needs an array of 3 numbers (RGB, 1/m)");
    glm::vec3 out;
    for (int c = 0; c < 3; ++c) {
      const tinygltf::Value& x = v.Get(c);
      if (!x.IsNumber()) fail(where + "[" + std::to_string(c) + "]", "is not a number");
      double d = x.GetNumberAsDouble();
      if (!(d >= 0.0 && d <= kMaxMediumSigma))
        fail(where + "[" + std::to_string(c) + "]",
             "must lie in [0, " + numberText(kMaxMediumSigma) + "] 1/m (got " + numberText(d) + ")");
      out[c] = static_cast<float>(d);
    }
    return out;
  };
  Medium m;
  m.fillsSpace = fillsSpace;
  m.sigmaA = coefficient("sigmaA");
  m.sigmaS = coefficient("sigmaS");
  if (ext.Has("g")) {
    const tinygltf::Value& g = ext.Get("g");
    if (!g.IsNumber()) fail(at + ".g", "is not a number");
    double d = g.GetNumberAsDouble();
    // |g| = 1 is a delta phase function, which no sampler here can evaluate.
    if (!(std::abs(d) < 1.0)) fail(at + ".g", "must lie in (-1, 1) (got " + numberText(d) + ")");
    m.g = static_cast<float>(d);
  }
  if (!ext.Has("density")) {
    if (fillsSpace) return m;
    // The box is the node's own [-1, 1]^3.
    m.setBox(worldFromNode);
    if (std::string problem = boxProblem(worldFromNode, m); !problem.empty()) fail(at, problem);
    return m;
  }

  // A density grid: {"uri", "grid" = "density", "scale" = 1}.
  const std::string where = at + ".density";
  if (fillsSpace) fail(where, "a medium filling all space has no density grid; put the grid on a node");
  const tinygltf::Value& d = ext.Get("density");
  if (!d.IsObject()) fail(where, "must be an object {\"uri\": \"smoke.vdb\", \"grid\": \"density\", \"scale\": 1}");
  for (const std::string& key : d.Keys())
    if (key != "uri" && key != "grid" && key != "scale")
      fail(where + "." + key, "unknown field '" + key + "' (known: uri, grid, scale)");
  if (!d.Has("uri") || !d.Get("uri").IsString()) fail(where + ".uri", "required: the OpenVDB file, a relative path");
  const std::string uri = d.Get("uri").Get<std::string>();
  std::string gridName = "density";
  if (d.Has("grid")) {
    if (!d.Get("grid").IsString()) fail(where + ".grid", "must be a string (the grid's name in the file)");
    gridName = d.Get("grid").Get<std::string>();
  }
  if (d.Has("scale")) {
    const tinygltf::Value& s = d.Get("scale");
    if (!s.IsNumber()) fail(where + ".scale", "is not a number");
    const double v = s.GetNumberAsDouble();
    if (!(v >= 0.0 && v <= kMaxMediumSigma))
      fail(where + ".scale", "must lie in [0, " + numberText(kMaxMediumSigma) + "] (got " + numberText(v) + ")");
    m.densityScale = static_cast<float>(v);
  }
  if (uri.empty() || uri.find(':') != std::string::npos)
    fail(where + ".uri", "'" + uri + "' must be a relative path to a .vdb file");
  const std::string path = (std::filesystem::path(baseDir) / uri).string();
  try {
    m.setDensity(readVdbDensity(path, gridName), worldFromNode);
  } catch (const VdbError& e) {
    fail(where, e.what());
  }
  m.densityUri = uri;
  m.densityGridName = gridName;
  if (std::string problem = boxProblem(m.worldFromBox, m); !problem.empty())
    fail(where, "the grid under the node's transform: " + problem);
  if (std::string problem = mediumProblem(m); !problem.empty()) fail(where, problem);
  return m;
}

void checkMediaDisjoint(const std::vector<Medium>& media, const std::vector<std::string>& paths,
                        const std::string& file) {
  // A point lies in at most one medium (renderer/scene/medium.h): overlapping boxes, or a box inside a medium that
  // fills all space, would need a rule for mixing coefficients that the format does not have.
  for (std::size_t a = 0; a < media.size(); ++a)
    for (std::size_t b = a + 1; b < media.size(); ++b)
      if (boxesOverlap(media[a], media[b])) {
        const Medium& ma = media[a];
        const Medium& mb = media[b];
        std::string what = ma.fillsSpace || mb.fillsSpace
                               ? "a medium box cannot lie inside the medium that fills all space"
                               : "medium boxes overlap";
        throw SceneError(file + ": " + paths[b] + ": '" + mb.name + "' and '" + ma.name + "' (" + paths[a] +
                         "): " + what + "; media must be disjoint");
      }
}

void attachDensity(Medium& medium, const std::string& vdbPath, const std::string& gridName, float scale) {
  if (medium.fillsSpace)
    throw VdbError("medium '" + medium.name + "' fills all space; a density grid needs a box to place it in");
  std::shared_ptr<const DensityGrid> grid = readVdbDensity(vdbPath, gridName);
  // Fit the grid's box, in its own local frame, into the medium's current box (uniform scale, centred).
  const glm::mat4 localFromIndex(grid->localFromIndex);
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (int i = 0; i < 8; ++i) {
    const glm::vec3 c((i & 1) ? grid->boxUpper().x : grid->boxLower().x, (i & 2) ? grid->boxUpper().y : grid->boxLower().y,
                      (i & 4) ? grid->boxUpper().z : grid->boxLower().z);
    const glm::vec3 p = glm::vec3(localFromIndex * glm::vec4(c, 1.0f));
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const glm::vec3 half = 0.5f * (hi - lo);
  const float s = 1.0f / std::max({half.x, half.y, half.z, 1e-30f});
  glm::mat4 boxFromLocal(s);
  boxFromLocal[3] = glm::vec4(-s * 0.5f * (lo + hi), 1.0f);
  Medium m = medium;
  m.densityScale = scale;
  m.setDensity(std::move(grid), medium.worldFromBox * boxFromLocal);
  // Absolute: the sidecar that saves it lies elsewhere than the folder the editor was started in.
  m.densityUri = std::filesystem::absolute(vdbPath).string();
  m.densityGridName = gridName;
  if (std::string problem = mediumProblem(m); !problem.empty()) throw VdbError(problem);
  medium = std::move(m);
}

}  // namespace vplab
