#version 450 core
// The radiance factor of a compensation tap (common/ssbc.glsl) at mip level uLevel, once per step: I(q) dA(q), with
// dA from ssbc_taps.frag.glsl (0 where q does not take part), and beside it the code of q's normal's y that the tap
// reads with it. A tap then reads two texels instead of three.
#include "common/units.glsl"
layout(binding = UNIT_PASS_INPUT0) uniform sampler2D uInput;  // I (reflected light only, no emission), with mips
layout(binding = UNIT_PASS_INPUT5) uniform sampler2D uArea;  // x dA(q), y the normal's y code, per mip level
uniform int uLevel;
layout(location = 0) out vec4 outRadiance;

void main() {
  ivec2 q = ivec2(gl_FragCoord.xy);
  vec2 area = texelFetch(uArea, q, uLevel).xy;
  outRadiance = vec4(texelFetch(uInput, q, uLevel).rgb * area.x, area.y);
}
