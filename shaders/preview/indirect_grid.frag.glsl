#version 450 core
// The inputs of the indirect light's grid (common/downscale.glsl), read from the full-resolution G-buffer bound at its
// units:
//   INDIRECT_GRID_GBUFFER 1: the grid's G-buffer, the full G-buffer's texels at the representatives (the gather and the
//                            compensation then read it as theirs);
//   INDIRECT_GRID_GBUFFER 0: the compensation's input I0 = the de-interleaved direct light at the representative + the
//                            grid's de-interleaved gather.
#include "common/units.glsl"
#include "common/fullscreen.glsl"
#include "common/downscale.glsl"

#if INDIRECT_GRID_GBUFFER
layout(binding = UNIT_G_MERGE_KEY) uniform sampler2D gMergeKey;
#include "common/gbuffer_outputs.glsl"

void main() {
  ivec2 q = representativePixel(gPosition, ivec2(gl_FragCoord.xy));
  outPosition = texelFetch(gPosition, q, 0);
  outNormal = texelFetch(gNormal, q, 0);
  outBaseColor = texelFetch(gBaseColor, q, 0);
  outEmission = texelFetch(gEmission, q, 0);
  outShading = texelFetch(gShading, q, 0);
  outMergeKey = texelFetch(gMergeKey, q, 0);
  outSurface = texelFetch(gSurface, q, 0);
}
#else
layout(binding = UNIT_PASS_INPUT0) uniform sampler2D uDirect;    // full resolution, de-interleaved
layout(binding = UNIT_PASS_INPUT1) uniform sampler2D uIndirect;  // the grid's, de-interleaved
layout(location = 0) out vec4 outColor;

void main() {
  ivec2 texel = ivec2(gl_FragCoord.xy);
  ivec2 q = representativePixel(gPosition, texel);
  outColor = vec4(texelFetch(uDirect, q, 0).rgb + texelFetch(uIndirect, texel, 0).rgb, 1.0);
}
#endif
