#version 450 core
// Pass 6: exposure in stops, clamp to [0, 1], sRGB transfer (IEC 61966-2-1), as renderer/image/tonemap.cpp does.
#include "common/units.glsl"
layout(binding = UNIT_PASS_INPUT0) uniform sampler2D uLinear;
uniform float uExposureScale;
layout(location = 0) out vec4 outColor;

float srgb(float c) {
  c = clamp(c, 0.0, 1.0);
  return c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055;
}

void main() {
  vec3 c = texelFetch(uLinear, ivec2(gl_FragCoord.xy), 0).rgb * uExposureScale;
  outColor = vec4(srgb(c.r), srgb(c.g), srgb(c.b), 1.0);
}
