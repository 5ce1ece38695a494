#version 450 core
// Pass 5, one step of screen-space bias compensation (common/ssbc.glsl) at every uScale-th pixel: output texel t
// holds T_r(I) at the pixel t * uScale (uScale 1: every pixel). Multi-resolution rings (common/ssbc.glsl):
// SSBC_COARSE_PASS holds only the coarse rings, at the pixels kSsbcCoarseSpacing t (uScale kSsbcCoarseSpacing);
// SSBC_SPLIT the interpolated coarse rings, SSBC_FINE_PASS adds the fine rings where they are not zero and
// SSBC_FALLBACK_PASS the coarse rings where they could not be interpolated. In the second step (R2 = T_r(R1), about
// a tenth of the compensation) SSBC_UPSAMPLE_PASS takes the coarse rings from the samples on p's surface everywhere,
// extrapolating where it cannot interpolate, and there is no fallback pass.
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
  // The coarse rings of the second step, from the coarse samples on p's surface; its fine rings follow
  // (SSBC_FINE_PASS).
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
  // Added (blending) to the SSBC_SPLIT pass's output where it lacks the coarse rings. Drawn through a depth mask
  // (ssbc_mask.frag.glsl), so that only SIMD groups at creases and silhouettes evaluate the coarse rings; a branch or
  // loop would run for every group (llvmpipe).
  SsbcReceiver r;
  ssbcReceiver(pc, r);
  // The near coarse rings exactly, the far ones from the samples on p's surface.
  vec3 value = ssbcRings(r, pc, kSsbcFineLevels, min(r.topLevel, kSsbcFallbackExactLevels - 1)) +
               ssbcFromCoarseSamples(uCoarseFar, r, pc);
  alpha = 0.0;
#elif defined(SSBC_FINE_PASS)
  // Added (blending) to the SSBC_SPLIT pass's output: the fine rings, drawn through a depth mask
  // (ssbc_mask.frag.glsl) that holds only the pixels whose block is not flat (ssbc_flat.frag.glsl); elsewhere every
  // fine tap is coplanar with p and adds nothing.
  SsbcReceiver r;
  ssbcReceiver(pc, r);
  vec3 value = ssbcLevel0(r, pc) + ssbcLevel1(r, pc);
  alpha = 0.0;
#elif defined(SSBC_SPLIT)
  // The coarse rings interpolated from the coarse grid (0 where incomplete: the fallback pass adds them); the fine
  // rings come from the SSBC_FINE_PASS.
  SsbcReceiver r;
  vec3 value = vec3(0.0);
  if (ssbcReceiver(pc, r)) {
    vec3 coarse;
    value = ssbcCoarseInterpolated(r, pc, coarse) ? coarse : vec3(0.0);
  }
#else
  vec3 value = ssbcFullAt(pc);
#endif
  outColor = vec4(any(greaterThanEqual(px, size)) ? vec3(0.0) : value, alpha);
}
