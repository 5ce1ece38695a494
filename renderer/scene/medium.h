#pragma once
// Participating media (docs/theory.md §16, §22): RGB absorption and scattering coefficients, a Henyey-Greenstein
// phase function, and a region that is either all space or an oriented box. A box may carry a density grid (smoke):
// its coefficients are then per unit density, sigma(x) = densityScale d(x) sigma, and the box is where the grid's
// density can be non-zero. A scene holds any number of boxes that do
// not overlap, or a single medium filling all space (the loader refuses anything else), so a point lies in at most
// one medium and a ray crosses the media as disjoint intervals. Surfaces are not interfaces: light crosses them only
// where it is not blocked, nothing refracts.

#include <cstdint>
#include <glm/glm.hpp>
#include <memory>
#include <string>
#include <vector>

namespace vplab {

struct DensityGrid;

/// Largest absorption or scattering coefficient accepted, 1/m: a mean free path of 0.1 um. Anything denser is a unit
/// mistake, and keeping sigma_t * length finite in float over scenes up to kMaxCoordinate needs a bound anyway.
inline constexpr double kMaxMediumSigma = 1e7;
/// A medium box whose axes span less than this fraction of the volume their lengths allow (|det| over the product
/// of the column lengths, the box's "squareness") is treated as flat: its inverse would not be trustworthy in float.
inline constexpr double kMinMediumBoxSquareness = 1e-6;

struct Medium {
  std::string name;              ///< the glTF node's name (or "scene" for a medium that fills all space)
  glm::vec3 sigmaA{0.0f};        ///< absorption coefficient per channel, 1/m (scene units), >= 0
  glm::vec3 sigmaS{0.0f};        ///< scattering coefficient per channel, 1/m, >= 0
  float g = 0.0f;                ///< Henyey-Greenstein asymmetry in (-1, 1); > 0 scatters forward
  bool fillsSpace = false;       ///< true: the medium is everywhere; false: inside the box below
  glm::mat4 worldFromBox{1.0f};  ///< maps the cube [-1, 1]^3 onto the medium's box (the node's world transform)
  glm::mat4 boxFromWorld{1.0f};  ///< its inverse
  /// A heterogeneous medium's density (null: the coefficients hold everywhere in the box). Shared, never edited: an
  /// edit that changes the grid loads a new one.
  std::shared_ptr<const DensityGrid> density;
  float densityScale = 1.0f;    ///< multiplies the grid's values, >= 0
  std::string densityUri;       ///< the .vdb file as the scene names it (relative to the scene file)
  std::string densityGridName;  ///< the grid read from it
  /// Maps the box's [-1, 1]^3 onto the grid's index coordinates: fixed by the grid, so that moving or scaling the box
  /// moves and scales the smoke with it.
  glm::mat4 indexFromBox{1.0f};
  glm::mat4 indexFromWorld{1.0f};  ///< indexFromBox * boxFromWorld (setBox keeps it in step)

  /// sigma_t per unit density (the coefficients as the scene gives them).
  glm::vec3 sigmaT() const { return sigmaA + sigmaS; }
  bool heterogeneous() const { return density != nullptr; }
  /// What the coefficients are multiplied by at a world point: densityScale d(x) for a grid, 1 otherwise (the caller
  /// knows the point lies in the medium's region).
  float densityAt(const glm::vec3& world) const;
  glm::vec3 sigmaSAt(const glm::vec3& world) const { return sigmaS * densityAt(world); }
  glm::vec3 sigmaTAt(const glm::vec3& world) const { return sigmaT() * densityAt(world); }
  /// The largest sigma_t anywhere in the medium (sigmaT() for a homogeneous one).
  glm::vec3 sigmaTMax() const;
  /// Single-scattering albedo sigma_s / sigma_t per channel (0 where sigma_t is 0).
  glm::vec3 albedo() const;
  /// True when the medium neither absorbs nor scatters in any channel (a ray crosses it unchanged).
  bool isVacuum() const;
  /// World-space corners of the box (fillsSpace: none).
  std::vector<glm::vec3> corners() const;
  /// Per channel 1 / sigma_t: the mean distance light travels before it is absorbed or scattered (inf where the
  /// channel does not interact).
  glm::vec3 meanFreePath() const;
  /// The box's centre and half sizes along its own axes (the cube [-1, 1]^3 under worldFromBox).
  glm::vec3 centre() const { return glm::vec3(worldFromBox[3]); }
  glm::vec3 halfSizes() const;
  /// Sets worldFromBox, its inverse and indexFromWorld.
  void setBox(const glm::mat4& world);
  /// Gives the medium a density grid placed by worldFromLocal (the node's world transform) and the grid's own
  /// index-to-local map: the box becomes the grid's box.
  void setDensity(std::shared_ptr<const DensityGrid> grid, const glm::mat4& worldFromLocal);
};

/// What is wrong with one medium, as the loader judges it (coefficients finite in [0, kMaxMediumSigma], |g| < 1, a
/// box with volume and a finite inverse), or empty. Names the medium.
std::string mediumProblem(const Medium& medium);
/// mediumProblem of each medium, then whether two of them share points (media must be disjoint: boxes that do not
/// overlap, or one medium filling all space alone), or empty.
std::string mediaProblem(const std::vector<Medium>& media);

/// The part [t0, t1) of a ray that lies inside media[medium].
struct MediumInterval {
  float t0 = 0.0f;
  float t1 = 0.0f;
  uint32_t medium = 0;
};

/// Appends to `out` (cleared first) the intervals of origin + t * direction, t in [0, tMax), that lie inside media,
/// sorted by t0; tMax may be infinite (a medium filling all space then gives [0, inf)). direction need not be unit:
/// t is the ray parameter. Media that neither absorb nor scatter are left out.
void mediumIntervals(const std::vector<Medium>& media, const glm::vec3& origin, const glm::vec3& direction, float tMax,
                     std::vector<MediumInterval>& out);

/// Index of the medium containing p, or -1.
int mediumAt(const std::vector<Medium>& media, const glm::vec3& p);

/// True when the two boxes share interior points (separating-axis test for oriented boxes).
bool boxesOverlap(const Medium& a, const Medium& b);

/// Transmittance exp(-sum sigma_t length) over the intervals, clipped to [0, tMax).
glm::vec3 transmittanceOver(const std::vector<Medium>& media, const std::vector<MediumInterval>& intervals, float tMax);

/// Henyey-Greenstein phase function (docs/theory.md §16), normalised over the sphere:
///   f_p(cos t) = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos t)^(3/2)),
/// t the angle between the direction light travelled before and after scattering. In the interface below both wo and
/// wi point away from the scattering point, as for a BRDF (wo toward the viewer, wi toward the light): light arrives
/// travelling along -wi and leaves along wo, so cos t = -dot(wi, wo).
float phaseHG(float cosTheta, float g);
inline float phaseHG(const glm::vec3& wo, const glm::vec3& wi, float g) {
  return phaseHG(-glm::dot(wi, wo), g);
}

struct PhaseSample {
  glm::vec3 wi{0.0f};  ///< unit, away from the scattering point (toward where the light comes from)
  float pdf = 0.0f;    ///< solid-angle pdf, equal to the phase function's value (sampled exactly)
};
/// Draws wi with density phaseHG(wo, wi, g) from two uniform numbers.
PhaseSample samplePhaseHG(const glm::vec3& wo, float g, glm::vec2 u);

}  // namespace vplab
