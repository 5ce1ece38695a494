// Integer hashing for deterministic per-pixel random numbers (PCG-style permutation, Jarzynski & Olano 2020).
uint pcgHash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}
float hashToFloat(uint h) { return float(h >> 8u) * (1.0 / 16777216.0); }
