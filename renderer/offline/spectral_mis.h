#pragma once
// Spectral MIS along a whole path through chromatic media (docs/theory.md §16), shared by the reference's camera
// paths and the light paths that make VPLs and VRLs.

#include <algorithm>
#include <glm/glm.hpp>

#include "renderer/offline/embree_scene.h"

namespace vplab {

/// Spectral MIS over the whole path (docs/theory.md §16; Wilkie et al. 2014, "Hero wavelength spectral sampling";
/// pbrt-v4's path-wide r_u). A path samples every free flight with one channel h picked once, uniformly; its weight is
/// f(path) / mean_k p_k(path), p_k the product over the segments of the density channel k's free-flight sampling
/// gives them (sigma_t,k T_k(t) for a scattering event, T_k(s) for passing to the surface). Per channel the ratio
/// f_c / p_c is the product of single-scattering albedos (<= 1), so the weight stays <= 3 x that: bounded. Dividing
/// each segment by its own channel mean instead (Segment::weight) is unbiased too, but along long paths in a
/// chromatic medium the per-segment factors (up to 3 each) multiply into fireflies: the chromatic furnace of
/// the reference test then missed L = 2 by 20 % at 18k paths and by 15 % at 600k.
struct PathSpectralMis {
  /// The channel every free flight of the path samples, fixed by the first medium crossing's draw; -1 before.
  int hero = -1;
  /// prod_segments p_k, divided by its channel mean after every segment (so that it neither under- nor overflows).
  glm::vec3 pdf{1.0f};

  /// The free-flight draw for the path, from the two numbers u traceSegment() asked for: the first crossing's u.x
  /// picks the hero channel, later crossings keep it (u.x is still drawn, so the random stream does not change).
  glm::vec2 draw(glm::vec2 u) {
    if (hero < 0) hero = std::min(2, static_cast<int>(u.x * 3.0f));
    u.x = (static_cast<float>(hero) + 0.5f) * (1.0f / 3.0f);
    return u;
  }

  /// Multiplies throughput by f(segment) / mean_k(pdf_k p_k(segment)) for a segment that crossed a medium.
  void apply(const Segment& segment, glm::vec3& throughput) {
    // The flight's path measure and the density of each channel's sampling (FreeFlight, media_tracking.h): T sigma_s
    // and T sigma_t at a scattering event, T and T for the surface or the end of the ray (homogeneous media).
    const glm::vec3 f = segment.spectralF;
    const glm::vec3 p = segment.spectralP;
    const glm::vec3 next = pdf * p;
    const float mean = (next.x + next.y + next.z) * (1.0f / 3.0f);
    if (!(mean > 0.0f)) {
      throughput = glm::vec3(0.0f);
      return;
    }
    throughput *= f / mean;
    pdf = next / mean;
  }
};

}  // namespace vplab
