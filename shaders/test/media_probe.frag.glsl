#version 450 core
// The preview's media functions (common/medium.glsl) on given segments and points, for tests/gl_smoke_test.cpp: pixel
// i of a one-row target receives the optical depth of segment i (rgb) and the grids' density at point i (a). Compiled
// with the media pass's defines (MediaPass::layout()) and read with its table and grids bound.
#include "common/units.glsl"
#include "common/medium.glsl"

// Column i: row 0 the segment's start, row 1 its end, row 2 the point.
layout(binding = UNIT_PASS_INPUT0) uniform sampler2D uProbes;

layout(location = 0) out vec4 outColor;

void main() {
  int i = int(gl_FragCoord.x);
  vec3 a = texelFetch(uProbes, ivec2(i, 0), 0).xyz, b = texelFetch(uProbes, ivec2(i, 1), 0).xyz;
  vec3 p = texelFetch(uProbes, ivec2(i, 2), 0).xyz;
#ifdef PREVIEW_MEDIA_GRIDS
  // Each grid reads 0 outside its box, and the boxes are disjoint: the sum is the density of the grid holding p.
  float density = 0.0;
  for (int g = 0; g < PREVIEW_MEDIA_GRIDS; ++g) density += gridDensity(g, p);
#else
  float density = 1.0;
#endif
  outColor = vec4(opticalDepth(a, b - a, 0.0, 1.0, true), density);
}
