#version 450 core
// Geometry-aware de-interleaving (MANYLIGHTS 8): average the k x k window, which holds every VPL subset once, over
// neighbours on the same surface (relative depth and normal tests), renormalised by the accepted weight so that
// rejected neighbours do not darken the result. The direct light and the VPL gather are interleaved alike and share
// the weights, so both are merged here at once (two outputs).
#include "common/fullscreen.glsl"

layout(binding = 6) uniform sampler2D uDirectRaw;    // deinterleaved blocks (direct.frag.glsl)
layout(binding = 7) uniform sampler2D uIndirectRaw;  // deinterleaved blocks (gather.frag.glsl)
layout(binding = 10) uniform sampler2D gMergeKey;   // xyz shading normal, w distance to the camera (0: background)
uniform int uInterleave;
uniform ivec2 uBlockSize;
uniform vec3 uCameraPosition;
layout(location = 0) out vec4 outDirect;
layout(location = 1) out vec4 outIndirect;

// Texel of pixel q in the deinterleaved layout: block (q mod k), texel q / k inside it. The quotient comes from a float
// multiply (exact for q < 2^22 / k): llvmpipe has no vector integer division and would run it lane by lane.
ivec2 rawTexel(ivec2 q) {
  ivec2 quotient = ivec2((vec2(q) + 0.5) / float(uInterleave));
  return (q - quotient * uInterleave) * uBlockSize + quotient;
}

void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(gPosition, 0);
  vec4 pos = texelFetch(gPosition, px, 0);
  if (pos.w <= 0.0 || uInterleave <= 1) {
    outDirect = vec4(texelFetch(uDirectRaw, rawTexel(px), 0).rgb, 1.0);
    outIndirect = vec4(texelFetch(uIndirectRaw, rawTexel(px), 0).rgb, 1.0);
    return;
  }
  vec4 key = texelFetch(gMergeKey, px, 0);
  vec3 n = key.xyz;
  float depth = key.w;
  int lo = -(uInterleave / 2);
  vec3 sumDirect = vec3(0.0), sumIndirect = vec3(0.0);
  float weight = 0.0;
  for (int dy = lo; dy < lo + uInterleave; ++dy)
    for (int dx = lo; dx < lo + uInterleave; ++dx) {
      ivec2 q = px + ivec2(dx, dy);
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size))) continue;
      vec4 qk = texelFetch(gMergeKey, q, 0);
      if (qk.w <= 0.0) continue;
      if (abs(qk.w - depth) > 0.05 * depth) continue;
      if (dot(qk.xyz, n) < 0.9) continue;
      ivec2 t = rawTexel(q);
      sumDirect += texelFetch(uDirectRaw, t, 0).rgb;
      sumIndirect += texelFetch(uIndirectRaw, t, 0).rgb;
      weight += 1.0;
    }
  if (weight > 0.0) {
    outDirect = vec4(sumDirect / weight, 1.0);
    outIndirect = vec4(sumIndirect / weight, 1.0);
  } else {
    outDirect = vec4(texelFetch(uDirectRaw, rawTexel(px), 0).rgb, 1.0);
    outIndirect = vec4(texelFetch(uIndirectRaw, rawTexel(px), 0).rgb, 1.0);
  }
}
