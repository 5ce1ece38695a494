#version 450 core
// The blocker search of an area emitter's soft shadows (common/light_shadow.glsl), once per k x k block of pixels for
// the direct pass (preview/direct.frag.glsl), which reads it at every pixel of the block: the search is most of that
// pass's cost (16 map reads per pixel against k^2 fewer light samples), and a block's pixels, whose k^2 subsets of
// samples the de-interleave merges anyway, lie close enough to share their blockers. Its taps are spread over the
// emitter's samples (each read from its own cell's map, so over every cell in proportion to its samples) and over the
// block's pixels (tap j from pixel j mod k^2, toward its own receiver), at fractions t in [0.15, 0.85] of the way
// from the sample to the receiver, rotated per block. At k = 1 this is the per-pixel search the direct pass had.
// Writes the sum of the blockers' points (xyz) and their count (w).
#include "common/fullscreen.glsl"
#include "common/math.glsl"
#include "common/light_shadow.glsl"

uniform int uInterleave;    // k
uniform ivec2 uImageSize;   // G-buffer size
// Tap j: the emitter sample y_j (xyz) and its cell's map (w), the emitter's normal there, its cell's centre, and the
// pixel of the block it searches from (xy, in [0, k)^2).
uniform vec4 uTapSample[BLOCKER_SEARCH_TAPS];
uniform vec3 uTapNormal[BLOCKER_SEARCH_TAPS];
uniform vec3 uTapCentre[BLOCKER_SEARCH_TAPS];
uniform vec2 uTapPixel[BLOCKER_SEARCH_TAPS];

layout(location = 0) out vec4 outSearch;

void main() {
  ivec2 block = ivec2(gl_FragCoord.xy);
  // Interleaved gradient noise (Jimenez 2014) per block: at k = 1 the direct pass's former per-pixel rotation.
  float rotation = fract(52.9829189 * fract(dot(vec2(block), vec2(0.06711056, 0.00583715))));
  BlockerSearch search = blockerSearchBegin();
  for (int j = 0; j < BLOCKER_SEARCH_TAPS; ++j) {
    ivec2 px = min(block * uInterleave + ivec2(uTapPixel[j]), uImageSize - 1);
    // One fetch for the point and its geometric normal (common/gbuffer_packing.glsl).
    uvec4 surface = texelFetch(gSurface, px, 0);
    vec3 x1, ng;
    unpackSurface(surface, x1, ng);
    float t = 0.15 + 0.7 * fract(0.618034 * (float(j) + 0.5) + rotation);
    blockerSearchTap(search, areaShadowCell(int(uTapSample[j].w), uTapCentre[j], x1, ng), uTapSample[j].xyz,
                     uTapNormal[j], t, surface.w != G_NO_SURFACE);
  }
  outSearch = vec4(search.pointSum, float(search.blockers));
}
