#version 450 core
// Pass 2, direct light T Le (docs/methods.md "Direct light in the preview"): K samples on the area lights give the
// unshadowed light, one shadow map per emitter or punctual light its visibility (common/light_shadow.glsl).
//  - area-light sample y_k (one-sided):  f(x1) cos1 max(0, n_y.(-w)) / d^2 * Le / (K p_A(y_k)) * V   (weight = Le/(K p_A))
//  - punctual light:                      f(x1) cos1 I(-w) / d^2 * V   (KHR_lights_punctual spot falloff)
// The area estimator is unbiased per sample, so the image converges to the exact direct light as K grows.
// Interleaved like the VPL gather (gather.frag.glsl, same deinterleaved block layout): pixel subset s uses lights
// s, s + k^2, ... with weight k^2, and the geometry-aware merge recombines the subsets.
#include "common/brdf.glsl"
#include "common/fullscreen.glsl"
#include "common/interleaved.glsl"
#include "common/math.glsl"
#include "common/units.glsl"
#include "common/light_shadow.glsl"

struct DirectLight {
  vec4 position;  // xyz, w: 0 area sample, 1 point, 2 spot, 3 directional (xyz unused)
  vec4 axis;      // emitter normal (area), spot axis or a directional light's direction of travel; w: cos(outer cone)
  vec4 weight;    // rgb: Le / (K p_A) (area), intensity in candela, or irradiance in lux (directional); w: cos(inner)
  vec4 shadow;    // x: the light's cube shadow map (its orthographic map for a directional light), y: radius of its
                  // emitter (0: punctual)
  vec4 centre;    // xyz: where that shadow map was rendered from (the emitter's centre, or the punctual light)
};
// A uniform block of at most DIRECT_UBO_LIGHTS lights (set by the renderer), bound from light uUboBase on: llvmpipe
// reads a UBO faster than a storage buffer; a longer list is drawn in ranges.
layout(std140, binding = BINDING_DIRECT_LIGHTS) uniform DirectLights { DirectLight lights[DIRECT_UBO_LIGHTS]; };

layout(location = 0) out vec4 outColor;

void main() {
  InterleavedSurface s;
  if (!interleavedSurface(s)) {
    outColor = vec4(0.0);
    return;
  }
  vec3 x1 = s.x1, n1 = s.n1, ng = s.ng, wo = s.wo;
  BrdfParams p = s.brdf;
  vec3 sum = vec3(0.0);
  int k2 = uInterleave * uInterleave;
  // The samples of one emitter share its shadow map: the visibility is filtered once per emitter and pixel.
  int cachedCube = -1;
  float cachedVisibility = 0.0;
  // Filter rotation per pixel (interleaved gradient noise, Jimenez 2014): deterministic, and the de-interleave blurs it.
  float rotation = 6.2831853 * fract(52.9829189 * fract(dot(vec2(s.px), vec2(0.06711056, 0.00583715))));
  // This subset's lights inside the range [uLightBegin, uLightEnd).
  for (int i = uLightBegin + uSubsetOffset; i < uLightEnd; i += k2) {
    DirectLight l = lights[i - uUboBase];
    bool directional = l.position.w == 3.0;
    vec3 d = l.position.xyz - x1;
    // A directional light arrives from -direction with its irradiance, no falloff with distance.
    float dist2 = directional ? 1.0 : dot(d, d);
    if (!(dist2 > 0.0)) continue;
    vec3 w = directional ? -l.axis.xyz : d * inversesqrt(dist2);
    // One-sided receiver: the light must be on the side the geometric normal faces.
    if (dot(ng, w) <= 0.0) continue;
    float cos1 = dot(n1, w);
    if (cos1 <= 0.0) continue;
    vec3 radiantTerm;
    if (l.position.w == 0.0) {
      // Area sample: one-sided emitter, cosine at the light.
      float cosY = -dot(l.axis.xyz, w);
      if (cosY <= 0.0) continue;
      radiantTerm = l.weight.rgb * cosY;
    } else if (l.position.w == 1.0 || directional) {
      radiantTerm = l.weight.rgb;
    } else {
      float cd = -dot(l.axis.xyz, w);
      float t = clamp((cd - l.axis.w) / max(0.001, l.weight.w - l.axis.w), 0.0, 1.0);
      radiantTerm = l.weight.rgb * (t * t);
    }
    int cube = int(l.shadow.x);
    float v;
    if (directional) {
      v = directionalVisibility(cube, l.axis.xyz, x1, ng, rotation);
    } else {
      if (cube != cachedCube) {
        cachedVisibility = lightVisibility(cube, l.centre.xyz, l.shadow.y, x1, ng, rotation);
        cachedCube = cube;
      }
      v = cachedVisibility;
    }
    if (v <= 0.0) continue;
    sum += evaluateBrdf(p, n1, wo, w) * cos1 / dist2 * radiantTerm * v;
  }
  outColor = interleavedOutput(s, sum * float(k2));
}
