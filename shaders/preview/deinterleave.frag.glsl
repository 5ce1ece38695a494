#version 450 core
// Geometry-aware de-interleaving (docs/theory.md §8): average the k x k window, which holds every VPL subset once, over
// neighbours on the same surface (relative depth and normal tests), renormalised by the accepted weight so that
// rejected neighbours do not darken the result. The direct light and the VPL gather are interleaved alike, so the
// merge is linear in them: the row pass reads both and merges uWeights.x direct + uWeights.y indirect (1, 1 per frame:
// I0, the input of the compensation). A component alone (the direct light at full resolution and the gather on its
// grid when s > 1, a component read back) is merged by the variant DEINTERLEAVE_ONE_INPUT, which reads only it.
// The window is filtered separably, rows then columns (DEINTERLEAVE_COLUMNS 0 / 1): 2k instead of k^2 neighbours per
// pixel. The row pass writes each row segment's weighted sum with its accepted weight in w, so on a surface the column
// pass divides the weighted sum by the total weight; at a discontinuity a diagonal neighbour counts only when the row's
// centre is on the pixel's surface too.
// The window is centred on the pixel: offsets -k/2 .. k/2, and for even k the two end taps (the same subset, k apart)
// weigh 1/2 each, so every subset still weighs 1. A window of k taps from -k/2 to k/2 - 1 is lopsided: where it is cut
// at a crease or the image border, the renormalisation weighs the pixels on one side of each surface up and those on
// the other side down, which moved the mean of the Cornell box's indirect light at k = 4 by +1.5 % at 64^2 (+0.7 % at
// 128^2); centred, +1.3 % (+0.5 %).
// The interleaved passes write light per unit of reflectance (common/reflectance.glsl): the column pass multiplies the
// pixel's own reflectance back in, so the average does not blur textures. It then adds uWeights.x times the punctual
// lights' direct light, drawn at every pixel and not merged (direct.frag.glsl).
#include "common/units.glsl"
#include "common/fullscreen.glsl"
#include "common/reflectance.glsl"
#include "common/deinterleaved_texel.glsl"

#if DEINTERLEAVE_COLUMNS
layout(binding = UNIT_PASS_INPUT0) uniform sampler2D uRows;        // row sums, accepted count in w
layout(binding = UNIT_PASS_INPUT1) uniform sampler2D uPunctualDirect;  // per pixel, reflected radiance
uniform float uPunctualWeight;                                     // uWeights.x of the row pass
#elif DEINTERLEAVE_ONE_INPUT
layout(binding = UNIT_PASS_INPUT0) uniform sampler2D uIn;  // deinterleaved blocks of one component
uniform float uWeight;                                     // its weight
#else
layout(binding = UNIT_PASS_INPUT0) uniform sampler2D uDirectIn;    // deinterleaved blocks of the direct light
layout(binding = UNIT_PASS_INPUT1) uniform sampler2D uIndirectIn;  // same for the gather
uniform vec2 uWeights;                              // of the direct light and of the gather
#endif
layout(binding = UNIT_G_MERGE_KEY) uniform sampler2D gMergeKey;   // xyz shading normal, w distance to the camera (0: background)
uniform int uInterleave;
uniform ivec2 uBlockSize;
layout(location = 0) out vec4 outColor;

// The input at pixel q: the row sum (columns), or the weighted raw values with a count of 1 (rows).
vec4 inputAt(ivec2 q) {
#if DEINTERLEAVE_COLUMNS
  return texelFetch(uRows, q, 0);
#elif DEINTERLEAVE_ONE_INPUT
  return vec4(uWeight * texelFetch(uIn, deinterleavedTexel(q, uInterleave, uBlockSize), 0).rgb, 1.0);
#else
  ivec2 t = deinterleavedTexel(q, uInterleave, uBlockSize);
  vec3 value = uWeights.x * texelFetch(uDirectIn, t, 0).rgb + uWeights.y * texelFetch(uIndirectIn, t, 0).rgb;
  return vec4(value, 1.0);
#endif
}

void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(gMergeKey, 0);
  vec4 key = texelFetch(gMergeKey, px, 0);
  vec4 sum = vec4(0.0);
  if (key.w <= 0.0) {
    // Background: nothing to merge with; the row pass passes the texel on with a count of 1.
    sum = inputAt(px);
  } else {
    vec3 n = key.xyz;
    float depth = key.w;
    int reach = uInterleave / 2;
    bool even = 2 * reach == uInterleave;
    for (int i = -reach; i <= reach; ++i) {
#if DEINTERLEAVE_COLUMNS
      ivec2 q = px + ivec2(0, i);
#else
      ivec2 q = px + ivec2(i, 0);
#endif
      ivec2 qc = clamp(q, ivec2(0), size - 1);
      vec4 qk = texelFetch(gMergeKey, qc, 0);
      bool accepted = q == qc && qk.w > 0.0 && abs(qk.w - depth) <= 0.05 * depth && dot(qk.xyz, n) >= 0.9;
      float weight = even && abs(i) == reach ? 0.5 : 1.0;
      sum += (accepted ? weight : 0.0) * inputAt(qc);
    }
  }
#if DEINTERLEAVE_COLUMNS
  // p itself always passes its own test and its row sum counts p, so w >= 1 (background: the count of 1 passed on).
  vec3 light = sum.rgb / sum.w;
  // Background texels hold no light, and no base colour to take back (gbuffer_background.frag.glsl).
  light = key.w > 0.0 ? light * mergeReflectance(texelFetch(gBaseColor, px, 0).rgb) : light;
  // A grid without a direct light of its own binds some other texture here, with weight 0.
  vec3 punctual = uPunctualWeight > 0.0 ? uPunctualWeight * texelFetch(uPunctualDirect, px, 0).rgb : vec3(0.0);
  outColor = vec4(light + punctual, 1.0);
#else
  outColor = sum;
#endif
}
