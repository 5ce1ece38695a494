// The indirect light's grid at 1/s of the image's width and height (Settings::indirectDownscale; docs/theory.md §8).
// Each grid texel stands for one pixel of its s x s block, its representative, so that the point it shades is a point
// the camera sees: an average of positions across a silhouette would lie on neither surface. The representative is
// the block's centre pixel, or where that sees no surface the first pixel in raster order that does; a texel is
// background only where its whole block is.
uniform int uDownscale;

ivec2 representativePixel(sampler2D fullPosition, ivec2 gridTexel) {
  ivec2 last = textureSize(fullPosition, 0) - 1;
  ivec2 origin = gridTexel * uDownscale;
  ivec2 centre = min(origin + ivec2(uDownscale / 2), last);
  if (texelFetch(fullPosition, centre, 0).w > 0.0) return centre;
  for (int y = 0; y < uDownscale; ++y)
    for (int x = 0; x < uDownscale; ++x) {
      ivec2 q = min(origin + ivec2(x, y), last);
      if (texelFetch(fullPosition, q, 0).w > 0.0) return q;
    }
  return centre;
}
