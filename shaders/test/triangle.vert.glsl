#version 450 core
// One triangle from uniform clip-space corners: the smallest draw that exercises the whole pipeline.
uniform vec2 uCorners[3];

void main() { gl_Position = vec4(uCorners[gl_VertexID], 0.0, 1.0); }
