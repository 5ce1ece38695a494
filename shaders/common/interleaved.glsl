// The pixel and the surface one fragment of an interleaved pass shades (Keller & Heidrich 2001; deinterleaved block
// layout, Segovia et al. 2006 — see common/gather.glsl). The direct-light and the VPL gather passes share it, so both
// split the lights into the same k x k subsets and the de-interleave pass can merge them with one set of weights.
// Needs common/brdf.glsl and common/fullscreen.glsl (the G-buffer samplers) included first. Both passes write their
// result per unit of the receiver's reflectance (common/reflectance.glsl, interleavedOutput).
#include "common/reflectance.glsl"

uniform vec3 uCameraPosition;
uniform int uInterleave;     // k
uniform ivec2 uSubsetXY;     // (sx, sy) of this draw's block
uniform ivec2 uBlockOrigin;  // lower-left texel of the block in the output
uniform ivec2 uImageSize;    // G-buffer size
// Lights of this draw's subset are i = s, s + k^2, ... in a global numbering; the draw's range of lights starts this
// many lights before the subset's first one. Set per draw by the renderer: the modulo is uniform, and llvmpipe would
// otherwise run it lane by lane for every fragment (no vector integer division).
uniform int uSubsetOffset;
// The lights of one draw (renderer: drawLightTable): a range of a shadow-map chunk whose table entries fit one uniform
// block bound from light uUboBase on.
uniform int uFirstLight;  // first light of this shadow-map chunk (its layer 0)
uniform int uLightBegin;  // first light of this draw's range, inside the chunk
uniform int uLightEnd;    // one past the last light of this draw's range
uniform int uUboBase;     // light at the start of the bound uniform-buffer range (<= uLightBegin)

struct InterleavedSurface {
  ivec2 px;         // pixel in the full image
  vec3 x1;          // world position
  vec3 n1;          // shading normal
  vec3 ng;          // geometric normal
  vec3 wo;          // unit direction toward the camera
  BrdfParams brdf;
};

// What an interleaved pass writes for the light `reflected` (the sum over its subset, already scaled by k^2) of
// surface s.
vec4 interleavedOutput(InterleavedSurface s, vec3 reflected) {
  return vec4(reflected / mergeReflectance(s.brdf.baseColor), 1.0);
}

// The surface seen by this fragment's pixel; false outside the image or where the pixel sees no surface.
bool interleavedSurface(out InterleavedSurface s) {
  ivec2 px = (ivec2(gl_FragCoord.xy) - uBlockOrigin) * uInterleave + uSubsetXY;
  if (any(greaterThanEqual(px, uImageSize))) return false;
  // Two fetches of the packed surface (common/gbuffer_packing.glsl) instead of five float textures.
  uvec4 surface = texelFetch(gSurface, px, 0);
  if (surface.w == G_NO_SURFACE) return false;
  uvec4 shading = texelFetch(gShading, px, 0);
  s.px = px;
  unpackSurface(surface, s.x1, s.ng);
  unpackShading(shading, s.n1, s.brdf.baseColor, s.brdf.metallic, s.brdf.roughness, s.brdf.specular);
  s.wo = normalize(uCameraPosition - s.x1);
  return true;
}
