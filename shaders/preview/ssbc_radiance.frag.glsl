#version 450 core
// The radiance factor of a compensation tap (common/ssbc.glsl) at mip level uLevel, once per step: I(q) dA(q), with
// dA from ssbc_taps.frag.glsl (0 where q does not take part), and beside it the code of q's normal's y that the tap
// reads with it. A tap then reads two texels instead of three.
// Level 0 reads the step's input; SSBC_AVERAGE_FINER, every level above it, averages I at the level below
// (ssbcAverageFiner) and writes that mean for the next level.
#include "common/units.glsl"
#include "common/ssbc_levels.glsl"
// I (reflected light only, no emission) at level uLevel (level 0), or at uLevel - 1 (SSBC_AVERAGE_FINER).
layout(binding = UNIT_PASS_INPUT0) uniform sampler2D uInput;
layout(binding = UNIT_PASS_INPUT5) uniform sampler2D uArea;  // x dA(q), y the normal's y code, per mip level
uniform int uLevel;
layout(location = 0) out vec4 outRadiance;
#if SSBC_AVERAGE_FINER
layout(location = 1) out vec4 outInput;  // I at level uLevel
#endif

void main() {
  ivec2 q = ivec2(gl_FragCoord.xy);
  vec2 area = texelFetch(uArea, q, uLevel).xy;
#if SSBC_AVERAGE_FINER
  vec3 radiance = ssbcAverageFiner(uInput, q).rgb;
  outInput = vec4(radiance, 1.0);
#else
  vec3 radiance = texelFetch(uInput, q, 0).rgb;
#endif
  outRadiance = vec4(radiance * area.x, area.y);
}
