#version 450 core
// Pass 2, direct light T Le (docs/methods.md "Direct light in the preview"): K samples on the area lights give the
// unshadowed light, one shadow map per emitter or punctual light its visibility (common/light_shadow.glsl).
//  - area-light sample y_k (one-sided):  f(x1) cos1 max(0, n_y.(-w)) / d^2 * Le / (K p_A(y_k)) * V   (weight = Le/(K p_A))
//  - punctual light:                      f(x1) cos1 I(-w) / d^2 * V   (KHR_lights_punctual spot falloff)
// The area estimator is unbiased per sample, so the image converges to the exact direct light as K grows.
// The area-light samples are interleaved like the VPL gather (gather.frag.glsl, same deinterleaved block layout): pixel
// subset s uses samples s, s + k^2, ... with weight k^2, and the geometry-aware merge recombines the subsets. The
// punctual lights are few and exact, so they are drawn at every pixel (k = 1) and added after the merge
// (deinterleave.frag.glsl): interleaving one point light over k x k subsets would leave it at one pixel in k^2, and the
// merge would turn its sharp shadow edges into k-pixel stair-steps.
// The renderer draws the table in runs of one kind of shadow map each (DIRECT_MAP_KIND; renderer/gl/direct_pass.cpp):
// the samples of one area emitter, whose cells' maps share one blocker search, or all punctual or all directional
// lights, a map each. The emitter's blocker search ran before, once per k x k block (preview/blocker_search.frag.glsl,
// layer uSearchLayer of uBlockerSearch); a punctual light's filter runs inside the loop. llvmpipe runs the body of a branch for the whole SIMD group whatever its condition, so filtering inside the
// loop only when the map changes would cost one filter per sample; for the same reason the loop body has no branches.
#define DIRECT_MAP_AREA 0         // an area emitter's cube map: soft shadows
#define DIRECT_MAP_PUNCTUAL 1     // a point or spot light's cube map
#define DIRECT_MAP_DIRECTIONAL 2  // a directional light's orthographic map
#include "common/brdf.glsl"
#include "common/fullscreen.glsl"
#include "common/interleaved.glsl"
#include "common/math.glsl"
#include "common/units.glsl"
#include "common/light_shadow.glsl"
#include "common/medium.glsl"

struct DirectLight {
  vec4 position;  // xyz, w: 0 area sample, 1 point, 2 spot, 3 directional (xyz unused)
  vec4 axis;      // emitter normal (area), spot axis or a directional light's direction of travel; w: cos(outer cone)
  vec4 weight;    // rgb: Le / (K p_A) (area), intensity in candela, or irradiance in lux (directional); w: cos(inner)
  vec4 shadow;    // x: the light's cube shadow map (its orthographic map for a directional light, its cell's map
                  // for an area-light sample); y: an area-light sample's emitter
  vec4 centre;    // xyz: where that shadow map was rendered from (the sample's cell centre, or the punctual light)
};
// A uniform block of at most DIRECT_UBO_LIGHTS lights (set by the renderer), bound from light uUboBase on: llvmpipe
// reads a UBO faster than a storage buffer; a longer list is drawn in ranges.
layout(std140, binding = BINDING_DIRECT_LIGHTS) uniform DirectLights { DirectLight lights[DIRECT_UBO_LIGHTS]; };

#if DIRECT_MAP_KIND == DIRECT_MAP_AREA
// Per k x k block and emitter, the blocker search's sum of blocker points (xyz) and their count (w).
layout(binding = UNIT_BLOCKER_SEARCH) uniform sampler2DArray uBlockerSearch;
uniform int uSearchLayer;  // this run's emitter
#endif

layout(location = 0) out vec4 outColor;

// Light i's reflected radiance at surface s: shadowed through its map when `shadowed` (a constant at every call), else
// unshadowed (visibility 1). rotation: the punctual and directional lights' filter rotation; search: an area run's
// blocker search.
vec3 directLight(int i, InterleavedSurface s, float rotation, BlockerSearch search, bool shadowed) {
  vec3 x1 = s.x1, n1 = s.n1, ng = s.ng, wo = s.wo;
  DirectLight l = lights[i - uUboBase];
#if DIRECT_MAP_KIND == DIRECT_MAP_DIRECTIONAL
  // Arrives from -direction with its irradiance, no falloff with distance.
  vec3 w = -l.axis.xyz;
  float dist2 = 1.0, emitted = 1.0;
#else
  vec3 d = l.position.xyz - x1;
  float dist2 = dot(d, d);
  vec3 w = d * inversesqrt(max(dist2, 1e-30));
  float cosLight = -dot(l.axis.xyz, w);
#if DIRECT_MAP_KIND == DIRECT_MAP_AREA
  // One-sided emitter, cosine at the light.
  float emitted = max(cosLight, 0.0);
#else
  // A point light, or a spot light with the KHR_lights_punctual falloff.
  float t = clamp((cosLight - l.axis.w) / max(0.001, l.weight.w - l.axis.w), 0.0, 1.0);
  float emitted = l.position.w == 2.0 ? t * t : 1.0;
#endif
#endif
  float visibility = 1.0;
  if (shadowed) {
#if DIRECT_MAP_KIND == DIRECT_MAP_DIRECTIONAL
    visibility = directionalVisibility(int(l.shadow.x), l.axis.xyz, x1, ng, rotation);
#elif DIRECT_MAP_KIND == DIRECT_MAP_PUNCTUAL
    visibility = pointLightVisibility(int(l.shadow.x), l.centre.xyz, x1, ng, rotation);
#else
    visibility = areaSampleVisibility(search, areaShadowCell(int(l.shadow.x), l.centre.xyz, x1, ng), l.position.xyz,
                                      l.axis.xyz);
#endif
  }
  // One-sided receiver: the light must be on the side the geometric normal faces.
  float cos1 = dot(n1, w);
  bool reaches = dist2 > 0.0 && dot(ng, w) > 0.0 && cos1 > 0.0 && emitted > 0.0;
  // Through participating media, the transmittance between the light and x1 (1 without media).
  return reaches ? evaluateBrdf(s.brdf, n1, wo, w) * (cos1 / dist2 * emitted * visibility * l.weight.rgb) *
                       mediaLightTransmittance(l.position, l.axis.xyz, x1, reaches && visibility > 0.0)
                 : vec3(0.0);
}

void main() {
  InterleavedSurface s;
  if (!interleavedSurface(s)) {
    outColor = vec4(0.0);
    return;
  }
  vec3 sum = vec3(0.0);
  int k2 = uInterleave * uInterleave;
#if DIRECT_MAP_KIND != DIRECT_MAP_AREA
  // Filter rotation per pixel (interleaved gradient noise, Jimenez 2014): deterministic.
  float rotation = 6.2831853 * fract(52.9829189 * fract(dot(vec2(s.px), vec2(0.06711056, 0.00583715))));
#endif
#if DIRECT_MAP_KIND == DIRECT_MAP_AREA
  // The search of this pixel's block: the pixel's texel in its subset's block is the block's index.
  vec4 found = texelFetch(uBlockerSearch, ivec3(ivec2(gl_FragCoord.xy) - uBlockOrigin, uSearchLayer), 0);
  BlockerSearch search = BlockerSearch(found.xyz, int(found.w));
#endif
#if DIRECT_MAP_KIND == DIRECT_MAP_AREA
  // Where the block's search found no blocker every sample's visibility is 1 (areaSampleVisibility), and the map reads
  // and their set-up were about 45% of this pass (docs/benchmarks.md "GL preview"). llvmpipe runs a branch's body
  // under a lane mask for every pixel, but a loop only while one of its lanes still iterates (at least once): so the
  // samples are summed in two loops, each entered by one kind of pixel, unshadowed where the block has no blocker and
  // through the maps where it has. A SIMD group of one kind pays one masked iteration of the other loop instead of
  // one per sample. The sum is the single loop's, term for term.
  int first = uLightBegin + uSubsetOffset;
  bool blocked = search.blockers > 0;
  for (int i = first; i < (blocked ? first : uLightEnd); i += k2) sum += directLight(i, s, 0.0, search, false);
  for (int i = first; i < (blocked ? uLightEnd : first); i += k2) sum += directLight(i, s, 0.0, search, true);
#else
  for (int i = uLightBegin + uSubsetOffset; i < uLightEnd; i += k2)
    sum += directLight(i, s, rotation, blockerSearchBegin(), true);
#endif
#if DIRECT_MAP_KIND == DIRECT_MAP_AREA
  outColor = interleavedOutput(s, sum * float(k2));
#else
  // Reflected radiance at every pixel (k = 1): not merged, so not divided by the reflectance.
  outColor = vec4(sum, 1.0);
#endif
}
