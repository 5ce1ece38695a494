#version 450 core
// Pass 5, one step of screen-space bias compensation (common/ssbc.glsl) at every uScale-th pixel: output texel t
// holds T_r(I) at the pixel t * uScale (uScale 1: every pixel). Multi-resolution rings (common/ssbc.glsl), each pass
// but the first drawn through a depth mask (ssbc_mask.frag.glsl): SSBC_COARSE_PASS holds only the coarse rings, at the
// pixels kSsbcCoarseSpacing t (uScale kSsbcCoarseSpacing); SSBC_SPLIT writes them interpolated where p's interpolation
// is complete (or p is no receiver) and SSBC_FALLBACK_PASS evaluates them where it is not; SSBC_FINE_PASS then adds
// the fine rings where they are not zero. In the second step (R2 = T_r(R1), about a tenth of the compensation)
// SSBC_UPSAMPLE_PASS takes the place of the fallback: it extrapolates the coarse rings from the samples on p's surface.
#include "common/units.glsl"
#include "common/brdf.glsl"
#include "common/fullscreen.glsl"
#include "common/ssbc.glsl"

uniform int uScale;
layout(location = 0) out vec4 outColor;
#ifdef SSBC_COARSE_PASS
layout(location = 1) out vec4 outFar;  // the far rings alone (levels >= kSsbcFallbackExactLevels)
#endif

void main() {
  ivec2 px = ivec2(gl_FragCoord.xy) * uScale;
  ivec2 size = textureSize(gPosition, 0);
  ivec2 pc = min(px, size - 1);
  float alpha = 1.0;
#if defined(SSBC_UPSAMPLE_PASS)
  // The coarse rings of the second step where they cannot be interpolated, from the coarse samples on p's surface;
  // its fine rings follow (SSBC_FINE_PASS).
  SsbcReceiver r;
  vec3 value = ssbcReceiver(pc, r) ? ssbcFromCoarseSamples(uCoarse, r, pc) : vec3(0.0);
#elif defined(SSBC_COARSE_PASS)
  SsbcReceiver r;
  bool receiver = ssbcReceiver(pc, r);
  vec3 far = ssbcRings(r, pc, kSsbcFallbackExactLevels, r.topLevel);
  vec3 value = ssbcRings(r, pc, kSsbcFineLevels, min(r.topLevel, kSsbcFallbackExactLevels - 1)) + far;
  value = receiver ? value : vec3(0.0);
  outFar = vec4(receiver && all(lessThan(px, size)) ? far : vec3(0.0), 1.0);
#elif defined(SSBC_FALLBACK_PASS)
  // Where the coarse rings cannot be interpolated. Drawn through a depth mask (ssbc_mask.frag.glsl), so that only
  // SIMD groups at creases and silhouettes evaluate the coarse rings; a branch or loop would run for every group
  // (llvmpipe).
  SsbcReceiver r;
  ssbcReceiver(pc, r);
  // The near coarse rings exactly, the far ones from the samples on p's surface.
  vec3 value = ssbcRings(r, pc, kSsbcFineLevels, min(r.topLevel, kSsbcFallbackExactLevels - 1)) +
               ssbcFromCoarseSamples(uCoarseFar, r, pc);
#elif defined(SSBC_FINE_PASS)
  // Added (blending) to the step's output: the fine rings, drawn through a depth mask
  // (ssbc_mask.frag.glsl) that holds only the pixels whose block is not flat (ssbc_flat.frag.glsl); elsewhere every
  // fine tap is coplanar with p and adds nothing.
  SsbcReceiver r;
  ssbcReceiver(pc, r);
  vec3 value = ssbcLevel0(r, pc) + ssbcLevel1(r, pc);
  alpha = 0.0;
#elif defined(SSBC_SPLIT)
  // The coarse rings interpolated from the coarse grid, drawn where the fallback mask is 0: there every sample with a
  // non-zero bilinear weight lies on p's surface (ssbcCoarseInterpolated), so the interpolation is the bilinear
  // filter's, one filtered fetch; or p sees no surface and gets 0. The fine rings come from the SSBC_FINE_PASS.
  vec2 coarsePosition = vec2(pc) / float(kSsbcCoarseSpacing) + 0.5;
  vec3 value = texelFetch(gPosition, pc, 0).w > 0.0 ? texture(uCoarse, coarsePosition / vec2(textureSize(uCoarse, 0))).rgb
                                                    : vec3(0.0);
#else
  vec3 value = ssbcFullAt(pc);
#endif
  outColor = vec4(any(greaterThanEqual(px, size)) ? vec3(0.0) : value, alpha);
}
