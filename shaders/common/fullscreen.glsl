// Screen-space passes read the G-buffer at integer pixel coordinates (no filtering).
layout(binding = 0) uniform sampler2D gPosition;   // xyz world position, w 1 where a surface was hit
layout(binding = 1) uniform sampler2D gNormal;     // xyz shading normal, w metallic
layout(binding = 2) uniform sampler2D gBaseColor;  // rgb base colour (texture included), w roughness
layout(binding = 3) uniform sampler2D gEmission;   // rgb emitted radiance, w specular
layout(binding = 4) uniform sampler2D gGeoNormal;  // xyz geometric normal (winding order)
