#version 450 core
// Per-texel factors of the compensation integral (common/ssbc.glsl) that depend on the tap texel q alone, computed
// once per camera for every mip level instead of once per (pixel, tap, step): x2 and the unit normal at q, and
//   dA(q) = omega_pix(q) |x2 - camera|^2 / |cos theta_q|,  omega_pix = 4^l cos^3(alpha) / f^2   (pinhole, f in px)
// with dA = 0 (and x2 = 0) for a texel that must not take part (background or straddling a discontinuity:
// mip-averaged coverage < 1 or averaged normal shorter than 0.9). dA is multiplied into the input radiance once per
// step (ssbc_radiance.frag.glsl), which also moves the normal's y code beside it.
// Level 0 reads the G-buffer; SSBC_AVERAGE_FINER, every level above it, averages the position (coverage in w) and the
// normal of the level below (ssbcAverageFiner) and writes those means for the next level.
#include "common/brdf.glsl"
#include "common/fullscreen.glsl"
#include "common/ssbc.glsl"

uniform int uLevel;
layout(location = 0) out vec4 outTap;   // xyz x2, w the normal's x
layout(location = 1) out vec4 outArea;  // x dA(q) (0: not used), y the normal's y and z sign (ssbcNormalYCode)
#if SSBC_AVERAGE_FINER
layout(binding = UNIT_PASS_INPUT1) uniform sampler2D uFinerPosition;  // level uLevel - 1: position, coverage in w
layout(binding = UNIT_PASS_INPUT2) uniform sampler2D uFinerNormal;    // level uLevel - 1: normal (not renormalised)
layout(location = 2) out vec4 outPosition;                            // level uLevel: their means
layout(location = 3) out vec4 outNormal;
#endif

void main() {
  ivec2 q = ivec2(gl_FragCoord.xy);
#if SSBC_AVERAGE_FINER
  vec4 qp = ssbcAverageFiner(uFinerPosition, q);
  vec3 qn = ssbcAverageFiner(uFinerNormal, q).xyz;
  outPosition = qp;
  outNormal = vec4(qn, 0.0);
#else
  vec4 qp = texelFetch(gPosition, q, 0);
  vec3 qn = texelFetch(gNormal, q, 0).xyz;
#endif
  float qnLen = length(qn);
  if (qp.w < 0.999 || qnLen < 0.9) {
    outTap = vec4(0.0);
    outArea = vec4(0.0);
    return;
  }
  qn /= qnLen;
  // Pixel solid angle from the off-axis angle alpha of the texel centre, times the pixels the texel stands for.
  float scale = float(1 << uLevel);
  vec2 offset = (vec2(q) + 0.5) * scale - vec2(textureSize(gPosition, 0)) * 0.5;
  float cosAlpha = uFocalPixels * inversesqrt(uFocalPixels * uFocalPixels + dot(offset, offset));
  float omega = scale * scale * cosAlpha * cosAlpha * cosAlpha / (uFocalPixels * uFocalPixels);
  vec3 toCamera = uCameraPosition - qp.xyz;
  float camDist2 = dot(toCamera, toCamera);
  float cosQ = max(abs(dot(qn, toCamera * inversesqrt(camDist2))), 0.05);
  outTap = vec4(qp.xyz, qn.x);
  outArea = vec4(omega * camDist2 / cosQ, ssbcNormalYCode(qn), 0.0, 0.0);
}
