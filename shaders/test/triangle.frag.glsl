#version 450 core
#include "common/math.glsl"

uniform vec3 uColor;
layout(location = 0) out vec4 outColor;

// kPi comes from the include, so a broken include path fails this test.
void main() { outColor = vec4(uColor * (kPi * kInvPi), 1.0); }
