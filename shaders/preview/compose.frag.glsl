#version 450 core
// final = Le + I0 + R1 + R2 with I0 = direct + de-interleaved indirect (docs/theory.md §6).
#include "common/units.glsl"
#include "common/fullscreen.glsl"

layout(binding = UNIT_PASS_INPUT0) uniform sampler2D uI0;         // direct + indirect (deinterleave.frag.glsl)
layout(binding = UNIT_PASS_INPUT2) uniform sampler2D uResidual1;  // R1 = T_r(I0)
layout(binding = UNIT_PASS_INPUT3) uniform sampler2D uResidual2;  // R2 = T_r(R1)
uniform int uResidualSteps;  // compensation steps whose results R1, R2 are current (0-2)
layout(location = 0) out vec4 outColor;

void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  vec3 i0 = texelFetch(uI0, px, 0).rgb;
  // Le as the camera sees it (gbuffer.frag.glsl; 0 on the background, gbuffer_background.frag.glsl).
  vec3 le = texelFetch(gEmission, px, 0).rgb;
  // Selects, not products: a target not written this frame may hold anything.
  vec3 r1 = uResidualSteps >= 1 ? texelFetch(uResidual1, px, 0).rgb : vec3(0.0);
  vec3 r2 = uResidualSteps >= 2 ? texelFetch(uResidual2, px, 0).rgb : vec3(0.0);
  outColor = vec4(le + i0 + r1 + r2, 1.0);
}
