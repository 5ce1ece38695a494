// The compensation's per-texel tap factors (preview/ssbc_taps.frag.glsl, ssbc_radiance.frag.glsl), as common/ssbc.glsl
// reads them: every mip level copied into one buffer texture, level l's rows of max(1, width >> l) texels one after
// another from its first texel (uTapLevelBase[l], renderer/gl/ssbc_pass.cpp) on. llvmpipe fetches a buffer's texel
// for about half of what a 2D texture's texel costs (docs/benchmarks.md, "The compensation's taps from buffer
// textures").

// At most this many levels: a 2D texture of GL_MAX_TEXTURE_SIZE 16384 (llvmpipe) has 15.
const int kSsbcMaxLevels = 16;

// Texel q of a level of levelSize texels whose first is levelBase.
int ssbcTexel(int levelBase, ivec2 q, ivec2 levelSize) {
  return levelBase + q.y * levelSize.x + q.x;
}

// Level l >= 1 of a quantity from level l - 1 (`finer`, level 0 of the bound texture, read through a bilinear sampler
// clamped to the edge): the mean of the 2 x 2 finer texels under texel q, one filtered fetch at their common corner. A
// finer level of odd size leaves its last row or column out, as the mip chain's sizes do; one texel wide or high, the
// clamp repeats it. The tap factors and each step's I dA average their own finer level this way while they are drawn,
// instead of reading mip chains that glGenerateMipmap made first.
vec4 ssbcAverageFiner(sampler2D finer, ivec2 q) {
  return textureLod(finer, vec2(2 * q + 1) / vec2(textureSize(finer, 0)), 0.0);
}
