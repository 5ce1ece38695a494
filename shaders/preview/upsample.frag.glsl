#version 450 core
// The full-resolution image from the indirect light's grid (Settings::indirectDownscale, common/downscale.glsl;
// docs/theory.md §8), in two passes:
//   UPSAMPLE_GRID_LIGHT 1, on the grid: the light that arrives at each texel, the selected terms (the gather, R1, R2)
//                          divided by the texel's reflectance (common/reflectance.glsl), and the plane of the 2x2
//                          texels from it on where all four lie on it (else 0);
//   UPSAMPLE_GRID_LIGHT 0, per pixel: that light interpolated from the grid texels of the pixel's 2x2 bilinear footprint
//                          that lie on its own surface (the same plane within 1 % of the distance to the camera, normals
//                          within 25 degrees), renormalised by the accepted weight, times the pixel's own reflectance,
//                          plus the pixel's own terms, emission and the direct light.
// So textures stay as sharp as the G-buffer while the light that arrives is interpolated. Most pixels lie inside a flat
// 2x2 block on its plane: there every footprint texel is accepted and the interpolation is the bilinear filter's, one
// filtered fetch instead of testing four texels. Where no footprint texel lies on the pixel's surface (a feature
// thinner than s pixels) the footprint texel nearest in space is taken (the texel of the pixel's own block is in the
// footprint and always sees a surface, so there is one). A wider search for a texel on the pixel's surface was tried:
// llvmpipe runs a rarely taken branch under a lane mask for every pixel, and it tripled the pass's cost.
#include "common/units.glsl"
#include "common/fullscreen.glsl"
#include "common/reflectance.glsl"

layout(location = 0) out vec4 outColor;
// The terms summed (each 0 or 1): x the pixel's emission and direct light, y the gather, z R1, w R2. Selects, not
// products: a target not written this frame may hold anything.
uniform vec4 uTerms;

#if UPSAMPLE_GRID_LIGHT
// The grid's G-buffer is bound at the G-buffer units.
layout(binding = UNIT_PASS_INPUT1) uniform sampler2D uIndirect;   // de-interleaved gather
layout(binding = UNIT_PASS_INPUT2) uniform sampler2D uResidual1;  // R1 = T_r(I0)
layout(binding = UNIT_PASS_INPUT3) uniform sampler2D uResidual2;  // R2 = T_r(R1)
layout(binding = UNIT_G_MERGE_KEY) uniform sampler2D gMergeKey;
layout(location = 1) out vec4 outBlockPlane;

// (n, n . x) of texel t's surface when the texels t + (0..1, 0..1) all lie on it (the same tests as a pixel's), else 0.
vec4 blockPlane(ivec2 t) {
  vec4 key = texelFetch(gMergeKey, t, 0);
  if (key.w <= 0.0) return vec4(0.0);
  vec3 n = key.xyz;
  float offset = dot(n, texelFetch(gPosition, t, 0).xyz), tolerance = 0.01 * key.w;
  ivec2 last = textureSize(gMergeKey, 0) - 1;
  for (int i = 1; i < 4; ++i) {
    ivec2 q = min(t + ivec2(i & 1, i >> 1), last);
    vec4 qk = texelFetch(gMergeKey, q, 0);
    if (qk.w <= 0.0 || dot(qk.xyz, n) < 0.9 || abs(dot(n, texelFetch(gPosition, q, 0).xyz) - offset) > tolerance)
      return vec4(0.0);
  }
  return vec4(n, offset);
}

void main() {
  ivec2 t = ivec2(gl_FragCoord.xy);
  outBlockPlane = blockPlane(t);
  vec3 light = vec3(0.0);
  if (uTerms.y > 0.0) light += texelFetch(uIndirect, t, 0).rgb;
  if (uTerms.z > 0.0) light += texelFetch(uResidual1, t, 0).rgb;
  if (uTerms.w > 0.0) light += texelFetch(uResidual2, t, 0).rgb;
  outColor = vec4(light / mergeReflectance(texelFetch(gBaseColor, t, 0).rgb), 1.0);
}
#else
layout(binding = UNIT_G_MERGE_KEY) uniform sampler2D gMergeKey;
layout(binding = UNIT_PASS_INPUT0) uniform sampler2D uDirect;         // full resolution, de-interleaved
layout(binding = UNIT_PASS_INPUT1) uniform sampler2D uGridLight;      // the first pass's light (bilinear, clamped)
layout(binding = UNIT_PASS_INPUT2) uniform sampler2D uGridBlockPlane; // the first pass's block planes
layout(binding = UNIT_PASS_INPUT4) uniform sampler2D uGridPosition;   // grid G-buffer
layout(binding = UNIT_PASS_INPUT5) uniform sampler2D uGridMergeKey;   // grid G-buffer
uniform int uDownscale;

void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  vec4 pos = texelFetch(gPosition, px, 0);
  vec3 own = vec3(0.0);
  if (uTerms.x > 0.0) {
    own = texelFetch(uDirect, px, 0).rgb;
    // Le as the camera sees it (gbuffer.frag.glsl; 0 on the background, gbuffer_background.frag.glsl).
    own += texelFetch(gEmission, px, 0).rgb;
  }
  if (pos.w <= 0.0 || uTerms.yzw == vec3(0.0)) {
    outColor = vec4(own, 1.0);
    return;
  }
  vec4 key = texelFetch(gMergeKey, px, 0);
  vec3 n = key.xyz;
  float tolerance = 0.01 * key.w;
  ivec2 last = textureSize(uGridPosition, 0) - 1;
  vec2 g = (vec2(px) + 0.5) / float(uDownscale) - 0.5;
  ivec2 base = ivec2(floor(g));
  vec2 f = g - vec2(base);
  vec4 plane = texelFetch(uGridBlockPlane, clamp(base, ivec2(0), last), 0);
  bool inFlatBlock =
      plane.xyz != vec3(0.0) && dot(plane.xyz, n) >= 0.9 && abs(dot(plane.xyz, pos.xyz) - plane.w) <= tolerance;
  vec3 light = texture(uGridLight, (g + 0.5) / vec2(last + 1)).rgb;
  // The other pixels test the four texels one by one.
  if (!inFlatBlock) {
    vec3 sum = vec3(0.0), nearestLight = vec3(0.0);
    float weight = 0.0, nearest = 1e30;
    for (int j = 0; j <= 1; ++j)
      for (int i = 0; i <= 1; ++i) {
        ivec2 t = clamp(base + ivec2(i, j), ivec2(0), last);
        vec4 tk = texelFetch(uGridMergeKey, t, 0);
        if (tk.w <= 0.0) continue;
        vec3 d = texelFetch(uGridPosition, t, 0).xyz - pos.xyz;
        vec3 texelLight = texelFetch(uGridLight, t, 0).rgb;
        if (dot(d, d) < nearest) {
          nearest = dot(d, d);
          nearestLight = texelLight;
        }
        if (dot(tk.xyz, n) < 0.9 || abs(dot(n, d)) > tolerance) continue;
        // Never exactly 0, so that an accepted texel counts where the pixel lies on a texel row (s odd).
        float w = max(i == 0 ? 1.0 - f.x : f.x, 1e-3) * max(j == 0 ? 1.0 - f.y : f.y, 1e-3);
        sum += w * texelLight;
        weight += w;
      }
    light = weight > 0.0 ? sum / weight : nearestLight;
  }
  outColor = vec4(own + light * mergeReflectance(texelFetch(gBaseColor, px, 0).rgb), 1.0);
}
#endif
