#version 450 core
// Geometry-aware upsampling of one half-resolution compensation step (ssbc.frag.glsl with uScale 2): pixel p blends
// the low-resolution samples at the full-resolution pixels 2 t around it with bilinear weights, keeping only those on
// the same surface (relative depth and normal tests, as in deinterleave.frag.glsl). The residual is smooth along a
// surface but grows steeply toward creases and changes abruptly across them and across silhouettes: a pixel whose
// interpolation would need a sample from another surface (or off screen) evaluates the integral itself at full
// resolution. Only pixels at such discontinuities pay the full cost, and there the residual is largest; dropping the
// rejected samples instead lost 8% of the recovered energy on the Cornell box.
#include "common/brdf.glsl"
#include "common/fullscreen.glsl"
#include "common/ssbc.glsl"

layout(binding = 7) uniform sampler2D uLow;  // T_r(I) at the pixels 2 t
#ifndef SSBC_SPLIT
layout(binding = 10) uniform sampler2D gMergeKey;  // xyz shading normal, w distance to the camera (0: background)
#endif
layout(location = 0) out vec4 outColor;

void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  vec4 pos = texelFetch(gPosition, px, 0);
  if (pos.w <= 0.0 || isinf(uClampBound)) {
#ifdef SSBC_FALLBACK_PASS
    discard;
#endif
    outColor = vec4(0.0);
    return;
  }
  ivec2 size = textureSize(gPosition, 0);
  ivec2 lowSize = textureSize(uLow, 0);
  vec4 key = texelFetch(gMergeKey, px, 0);
  vec3 n = key.xyz;
  float depth = key.w;
  ivec2 base = px >> 1;
  // p sits on a low-resolution sample (even coordinate) or halfway between two (odd).
  vec2 f = vec2(px & 1) * 0.5;
  vec3 sum = vec3(0.0);
  bool complete = true;
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i <= 1; ++i) {
      float wb = (i == 0 ? 1.0 - f.x : f.x) * (j == 0 ? 1.0 - f.y : f.y);
      ivec2 t = base + ivec2(i, j);
      ivec2 q = t * 2;
      if (wb <= 0.0) continue;
      bool inside = all(lessThan(t, lowSize)) && all(lessThan(q, size));
      vec4 qk = inside ? texelFetch(gMergeKey, q, 0) : vec4(0.0);
      if (qk.w <= 0.0 || abs(qk.w - depth) > 0.02 * depth || dot(qk.xyz, n) < 0.95) {
        complete = false;
        break;
      }
      sum += wb * texelFetch(uLow, t, 0).rgb;
    }
#if defined(SSBC_FALLBACK_PASS)
  // Multi-resolution rings: written where the interpolation above is incomplete, after the pass without
  // SSBC_FALLBACK_PASS wrote 0 there. A discarded fragment ends the shader for its SIMD group once every lane has
  // discarded (llvmpipe), so only groups at discontinuities evaluate T_r.
  SsbcReceiver r;
  if (complete || !ssbcReceiver(px, r)) discard;
  outColor = vec4(ssbcSplitCompleteAt(r, px), 0.0);
#elif defined(SSBC_SPLIT)
  outColor = vec4(complete ? sum : vec3(0.0), 1.0);
#else
  outColor = vec4(complete ? sum : ssbcAt(px), 1.0);
#endif
}
