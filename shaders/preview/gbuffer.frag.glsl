#version 450 core
#include "common/scene.glsl"

layout(binding = 5) uniform sampler2DArray uBaseColorTextures;

in vec3 vPosition;
in vec3 vNormal;
in vec2 vUv;
flat in vec3 vGeoNormal;
flat in uint vMaterial;
uniform vec3 uCameraPosition;

layout(location = 0) out vec4 outPosition;
layout(location = 1) out vec4 outNormal;
layout(location = 2) out vec4 outBaseColor;
layout(location = 3) out vec4 outEmission;
layout(location = 4) out vec4 outGeoNormal;
// Shading normal and distance to the camera in one texel: the geometry-aware merges (deinterleave.frag.glsl,
// the coarse-ring interpolation of common/ssbc.glsl) test every neighbour with one fetch instead of two and no length().
layout(location = 5) out vec4 outMergeKey;

void main() {
  GlMaterial m = sceneMaterials[vMaterial];
  vec3 base = m.baseColor.rgb;
  if (m.baseColor.w >= 0.0) base *= texture(uBaseColorTextures, vec3(vUv, m.baseColor.w)).rgb;
  outPosition = vec4(vPosition, 1.0);
  vec3 n = normalize(vNormal);
  outNormal = vec4(n, m.params.x);
  outMergeKey = vec4(n, length(vPosition - uCameraPosition));
  outBaseColor = vec4(base, m.params.y);
  outEmission = vec4(m.emission.rgb, m.params.z);
  outGeoNormal = vec4(vGeoNormal, 0.0);
}
