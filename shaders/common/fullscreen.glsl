// Screen-space passes read the G-buffer at integer pixel coordinates (no filtering).
#include "common/units.glsl"
layout(binding = UNIT_G_POSITION) uniform sampler2D gPosition;   // xyz world position, w 1 where a surface was hit
layout(binding = UNIT_G_NORMAL) uniform sampler2D gNormal;     // xyz shading normal, w metallic
layout(binding = UNIT_G_BASE_COLOR) uniform sampler2D gBaseColor;  // rgb base colour (texture included), w roughness
layout(binding = UNIT_G_EMISSION) uniform sampler2D gEmission;   // rgb emitted radiance, w specular
layout(binding = UNIT_G_GEO_NORMAL) uniform sampler2D gGeoNormal;  // xyz geometric normal (winding order)
