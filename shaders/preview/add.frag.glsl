#version 450 core
// Accumulates one compensation step into the residual sum R = R1 + R2.
layout(binding = 6) uniform sampler2D uSource;
layout(location = 0) out vec4 outColor;
void main() { outColor = texelFetch(uSource, ivec2(gl_FragCoord.xy), 0); }
