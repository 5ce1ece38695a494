// The camera ray of the pixel an interleaved media pass's fragment draws (preview/media_lights.frag.glsl,
// media_vpls.frag.glsl), in the deinterleaved block layout of common/interleaved.glsl.
#include "common/brdf.glsl"
#include "common/fullscreen.glsl"
#include "common/interleaved.glsl"
#include "common/media_ray.glsl"

struct MediaPixel {
  ivec2 px;
  MediaRay ray;
  float minH;    // the smallest distance from the ray an equiangular distance is drawn around (1e-6 scene diagonals)
  float jitter;  // pixelJitter(px)
  int k2;        // subsets, k^2
};

// False outside the image or where the ray crosses no medium (the pass writes 0 there).
bool interleavedMediaPixel(out MediaPixel p) {
  p.px = (ivec2(gl_FragCoord.xy) - uBlockOrigin) * uInterleave + uSubsetXY;
  p.minH = 1e-6 * uSceneDiagonal;
  p.jitter = pixelJitter(p.px);
  p.k2 = uInterleave * uInterleave;
  return all(lessThan(p.px, uImageSize)) && mediaRayAt(p.px, uImageSize, p.ray);
}
