// Texel of pixel q in the de-interleaved layout of k x k blocks of blockSize texels each (common/interleaved.glsl):
// block (q mod k), texel q / k inside it. The quotient comes from a float division (exact for 0 <= q < 2^22 / k):
// llvmpipe has no vector integer division and would run it lane by lane.
ivec2 deinterleavedTexel(ivec2 q, int k, ivec2 blockSize) {
  ivec2 quotient = ivec2((vec2(q) + 0.5) / float(k));
  return (q - quotient * k) * blockSize + quotient;
}
