// The VPL table of the gather (common/gather.glsl) and of the media's in-scattering (preview/media_vpls.frag.glsl),
// filled by renderer/gl/gather_pass.cpp (VplGpu). A medium VPL (docs/theory.md §17) has geoNormal.w = 1, its phase
// function's g in baseColor.w and no surface: normal is 0, geoNormal.xyz the direction its light travelled on (what a
// paraboloid visibility map is oriented by), lambertPower its flux.
struct GlVpl {
  vec4 position;   // xyz, w: VSL radius (0 = point)
  vec4 normal;     // xyz shading normal, w metallic
  vec4 incoming;   // xyz toward where the light came from, w roughness
  vec4 flux;       // rgb Phi, w specular
  vec4 baseColor;  // rgb (texture included)
  vec4 geoNormal;  // xyz geometric normal
  // rgb f(x2) Phi = baseColor / pi Phi for a pure-Lambert VPL, 0 where its light arrived from behind the shading normal
  // (then f(x2) = 0): the whole VPL factor of the pure-Lambert loop, precomputed by the renderer.
  vec4 lambertPower;
};
layout(std140, binding = BINDING_VPLS) uniform Vpls { GlVpl vpls[GATHER_UBO_VPLS]; };

