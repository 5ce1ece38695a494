// The surface the interleaved passes (common/interleaved.glsl) shade, in two integer texels of the G-buffer, written by
// preview/gbuffer.frag.glsl. The direct light and the gather read a subset's pixels k apart, a cache line per pixel and
// texture: two fetches instead of five float textures took the direct light at 640x480 from 23.6 to 19.9 ms
// (docs/benchmarks.md "The interleaved passes' surface in two texels").
//   gSurface: the world position's three floats, bit for bit, and the geometric normal, octahedral in two 16-bit
//             snorms; G_NO_SURFACE in w where the pixel sees no surface (a code packSnorm2x16 never makes: it clamps to
//             -32767; preview/gbuffer_background.frag.glsl writes it). The direct light's blocker
//             search (preview/blocker_search.frag.glsl) reads only this one.
//   gShading: the shading normal (octahedral), the base colour and metallic, roughness and specular, as halves.
#define G_NO_SURFACE 0x80008000u

vec2 octahedralEncode(vec3 n) {
  vec2 p = n.xy / (abs(n.x) + abs(n.y) + abs(n.z));
  vec2 signs = vec2(p.x >= 0.0 ? 1.0 : -1.0, p.y >= 0.0 ? 1.0 : -1.0);
  return n.z < 0.0 ? (1.0 - abs(p.yx)) * signs : p;
}

vec3 octahedralDecode(vec2 e) {
  vec3 n = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  float fold = max(-n.z, 0.0);
  n.xy += vec2(n.x >= 0.0 ? -fold : fold, n.y >= 0.0 ? -fold : fold);
  return normalize(n);
}

uvec4 packSurface(vec3 position, vec3 geoNormal) {
  return uvec4(floatBitsToUint(position), packSnorm2x16(octahedralEncode(geoNormal)));
}

uvec4 packShading(vec3 normal, vec3 baseColor, float metallic, float roughness, float specular) {
  return uvec4(packSnorm2x16(octahedralEncode(normal)), packHalf2x16(baseColor.rg),
               packHalf2x16(vec2(baseColor.b, metallic)), packHalf2x16(vec2(roughness, specular)));
}

// The inverses; a surface texel of the background (w = G_NO_SURFACE) unpacks to meaningless values.
void unpackSurface(uvec4 surface, out vec3 position, out vec3 geoNormal) {
  position = uintBitsToFloat(surface.xyz);
  geoNormal = octahedralDecode(unpackSnorm2x16(surface.w));
}

void unpackShading(uvec4 shading, out vec3 normal, out vec3 baseColor, out float metallic, out float roughness,
                   out float specular) {
  normal = octahedralDecode(unpackSnorm2x16(shading.x));
  vec2 rg = unpackHalf2x16(shading.y), bMetallic = unpackHalf2x16(shading.z), roughSpecular = unpackHalf2x16(shading.w);
  baseColor = vec3(rg, bMetallic.x);
  metallic = bMetallic.y;
  roughness = roughSpecular.x;
  specular = roughSpecular.y;
}
