#version 450 core
// Which pixels a pass of the multi-resolution rings (common/ssbc.glsl) runs at, as a depth mask, once per G-buffer:
// depth 1 where it runs, 0 where it adds nothing. The pass is then drawn at a smaller depth with GL_LESS, so that
// llvmpipe's early depth test ends the shader for a SIMD group whose pixels all fail. A discard did the same job at
// several times the cost: a 640x480 pass that discarded every pixel took 6 ms, one that wrote every pixel 0.7 ms.
// SSBC_MASK_FINE: pixels whose block is not flat (ssbc_flat.frag.glsl), for SSBC_FINE_PASS. Otherwise: pixels whose
// coarse rings cannot be interpolated from the coarse grid, for SSBC_FALLBACK_PASS (SSBC_UPSAMPLE_PASS in the second
// step), and where it is 0 for the bilinear interpolation (SSBC_SPLIT).
#include "common/units.glsl"
#include "common/brdf.glsl"
#include "common/fullscreen.glsl"
#define SSBC_SPLIT 1
#include "common/ssbc.glsl"

#ifdef SSBC_MASK_FINE
layout(binding = UNIT_PASS_INPUT7) uniform sampler2D uFlat;  // per coarse block: 1 where every fine tap is coplanar with its pixel
#endif

void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  SsbcReceiver r;
  bool runs = ssbcReceiver(px, r);
#ifdef SSBC_MASK_FINE
  runs = runs && texelFetch(uFlat, px / kSsbcCoarseSpacing, 0).x <= 0.5;
#else
  vec3 coarse;
  runs = runs && !ssbcCoarseInterpolated(r, px, coarse);
#endif
  gl_FragDepth = runs ? 1.0 : 0.0;
}
