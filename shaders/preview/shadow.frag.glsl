#version 450 core
// Radial distance instead of z: one comparison value works for every cube face.
uniform float uShadowFar;
in vec3 gOffset;

void main() { gl_FragDepth = length(gOffset) / uShadowFar; }
