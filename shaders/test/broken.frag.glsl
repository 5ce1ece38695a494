#version 450 core
#include "common/math.glsl"

layout(location = 0) out vec4 outColor;

void main() {
  outColor = vec4(undeclaredVariable, 1.0);
}
