#version 450 core
// final = Le + I0 + R1 + R2 with I0 = direct + de-interleaved indirect (MANYLIGHTS 6); also writes I0 alone, the
// input of the first compensation step.
#include "common/fullscreen.glsl"

layout(binding = 6) uniform sampler2D uDirect;
layout(binding = 7) uniform sampler2D uIndirect;
layout(binding = 8) uniform sampler2D uResidual;
uniform int uStage;
uniform vec3 uCameraPosition;  // 0: write I0, 1: write the final image
layout(location = 0) out vec4 outColor;

void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  vec3 i0 = texelFetch(uDirect, px, 0).rgb + texelFetch(uIndirect, px, 0).rgb;
  if (uStage == 0) {
    outColor = vec4(i0, 1.0);
    return;
  }
  vec4 pos = texelFetch(gPosition, px, 0);
  // One-sided emitters: Le is seen only from the side the geometric normal faces.
  bool front = pos.w > 0.0 && dot(texelFetch(gGeoNormal, px, 0).xyz, uCameraPosition - pos.xyz) > 0.0;
  vec3 le = front ? texelFetch(gEmission, px, 0).rgb : vec3(0.0);
  outColor = vec4(le + i0 + texelFetch(uResidual, px, 0).rgb, 1.0);
}
