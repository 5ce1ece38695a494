#version 450 core
// Pass 5, one step of screen-space bias compensation (common/ssbc.glsl) at every uScale-th pixel: output texel t
// holds T_r(I) at the full-resolution pixel t * uScale (uScale 1: every pixel; 2: the half-resolution grid that
// ssbc_upsample.frag.glsl interpolates). With SSBC_COARSE_PASS it holds only the coarse rings, at the pixels
// kSsbcCoarseSpacing t (uScale kSsbcCoarseSpacing), which ssbcSplitAt interpolates.
#include "common/brdf.glsl"
#include "common/fullscreen.glsl"
#include "common/ssbc.glsl"

uniform int uScale;
layout(location = 0) out vec4 outColor;

void main() {
  ivec2 px = ivec2(gl_FragCoord.xy) * uScale;
#ifdef SSBC_COARSE_PASS
  vec3 value = ssbcCoarseAt(min(px, textureSize(gPosition, 0) - 1));
#else
  vec3 value = ssbcAt(min(px, textureSize(gPosition, 0) - 1));
#endif
  outColor = vec4(any(greaterThanEqual(px, textureSize(gPosition, 0))) ? vec3(0.0) : value, 1.0);
}
