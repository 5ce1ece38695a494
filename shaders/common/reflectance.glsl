// What the preview's merges interpolate between pixels is the light that arrives, not what each receiver reflects of
// it: the interleaved passes (direct light, VPL gather) divide their result by the receiver's reflectance, and the
// de-interleave (and the upsample of the indirect light's grid) multiply the pixel's own back in, so that textures stay
// as sharp as the G-buffer where the light is averaged over k x k pixels or interpolated from a coarser grid. Exact for
// Lambert receivers of one albedo; for the GGX lobe the base colour stands in for its reflectance (exact for metals,
// whose F0 is the base colour). No surface reflects less than a dielectric's F0 of 0.04, so dark texels are not
// amplified.
vec3 mergeReflectance(vec3 baseColor) {
  return max(baseColor, vec3(0.04));
}
