#version 450 core
// The G-buffer's background, after preview/gbuffer.frag.glsl has drawn the surfaces: a full-screen triangle at depth 0,
// the cleared depth (reversed depth's infinity), drawn with GL_EQUAL, so that only the pixels no surface covers are
// written, instead of clearing four whole targets before the surfaces are drawn (on llvmpipe those clears took 2 to 8
// ms of the 640x480 G-buffer's 9 to 18, docs/benchmarks.md). What marks the background: w = 0 in position and merge
// key, a zero normal (the compensation's coarser levels average zeros there: a short averaged normal flags an edge) and
// G_NO_SURFACE in the packed surface (common/gbuffer_packing.glsl); the other targets are written too, with zeros.
#include "common/gbuffer_packing.glsl"
#include "common/gbuffer_outputs.glsl"

void main() {
  outPosition = vec4(0.0);
  outNormal = vec4(0.0);
  outBaseColor = vec4(0.0);
  outEmission = vec4(0.0);
  outShading = uvec4(0u);
  outMergeKey = vec4(0.0);
  outSurface = uvec4(0u, 0u, 0u, G_NO_SURFACE);
}
