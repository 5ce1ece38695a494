// Mirror of renderer/scene/medium.h phaseHG() / samplePhaseHG(): the Henyey-Greenstein phase function
// (docs/theory.md §16), g in (-1, 1), g > 0 scatters forward, normalised over the sphere:
//   f_p(cos t) = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos t)^(3/2)),
// t the angle between the direction light travelled before and after scattering. As for a BRDF, wo and wi both point
// away from the scattering point (wo toward the viewer, wi toward the light), so cos t = -dot(wi, wo). Same constants
// as the C++ (the 1e-30 floor under the square root, isotropic sampling below |g| < 1e-3).
#include "common/math.glsl"

float phaseHG(float cosTheta, float g) {
  // 1 + g^2 - 2 g cos as two non-negative terms (no cancellation at the peak), as in the C++.
  float denom = g >= 0.0 ? (1.0 - g) * (1.0 - g) + 2.0 * g * (1.0 - cosTheta)
                         : (1.0 + g) * (1.0 + g) - 2.0 * g * (1.0 + cosTheta);
  return (1.0 - g * g) / (4.0 * kPi * denom * sqrt(max(denom, 1e-30)));
}

float phaseHG(vec3 wo, vec3 wi, float g) { return phaseHG(-dot(wi, wo), g); }

// Draws wi (unit, away from the scattering point) with density phaseHG(wo, wi, g) from two uniform numbers: the HG
// cdf inverted in cos t, the direction light travelled before scattering built around wo, wi its opposite.
vec3 samplePhaseHG(vec3 wo, float g, vec2 u) {
  float cosTheta;
  if (abs(g) < 1e-3) {
    cosTheta = 1.0 - 2.0 * u.x;
  } else {
    float s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u.x);
    cosTheta = (1.0 + g * g - s * s) / (2.0 * g);
  }
  cosTheta = clamp(cosTheta, -1.0, 1.0);
  float sinTheta = sqrt(max(0.0, 1.0 - cosTheta * cosTheta));
  float phi = 2.0 * kPi * u.y;
  vec3 s, t;
  orthonormalFrame(wo, s, t);
  vec3 dIn = s * (sinTheta * cos(phi)) + t * (sinTheta * sin(phi)) + wo * cosTheta;
  return -dIn;
}
