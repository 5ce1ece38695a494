// Screen-space passes read the G-buffer at integer pixel coordinates (no filtering).
#include "common/units.glsl"
layout(binding = UNIT_G_POSITION) uniform sampler2D gPosition;   // xyz world position, w 1 where a surface was hit
layout(binding = UNIT_G_NORMAL) uniform sampler2D gNormal;     // xyz shading normal, w metallic
layout(binding = UNIT_G_BASE_COLOR) uniform sampler2D gBaseColor;  // rgb base colour (texture included), w roughness
// rgb Le toward the camera (0 behind a one-sided emitter), w specular
layout(binding = UNIT_G_EMISSION) uniform sampler2D gEmission;
// The interleaved passes' surface, packed (common/gbuffer_packing.glsl): the position and geometric normal (winding
// order), and the shading normal with the base colour and the BRDF's parameters.
layout(binding = UNIT_G_SURFACE) uniform usampler2D gSurface;
layout(binding = UNIT_G_SHADING) uniform usampler2D gShading;
#include "common/gbuffer_packing.glsl"
