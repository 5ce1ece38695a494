#version 450 core
#include "common/scene.glsl"

layout(binding = 5) uniform sampler2DArray uBaseColorTextures;

in vec3 vPosition;
in vec3 vNormal;
in vec2 vUv;
flat in vec3 vGeoNormal;
flat in uint vMaterial;

layout(location = 0) out vec4 outPosition;
layout(location = 1) out vec4 outNormal;
layout(location = 2) out vec4 outBaseColor;
layout(location = 3) out vec4 outEmission;
layout(location = 4) out vec4 outGeoNormal;

void main() {
  GlMaterial m = sceneMaterials[vMaterial];
  vec3 base = m.baseColor.rgb;
  if (m.baseColor.w >= 0.0) base *= texture(uBaseColorTextures, vec3(vUv, m.baseColor.w)).rgb;
  outPosition = vec4(vPosition, 1.0);
  outNormal = vec4(normalize(vNormal), m.params.x);
  outBaseColor = vec4(base, m.params.y);
  outEmission = vec4(m.emission.rgb, m.params.z);
  outGeoNormal = vec4(vGeoNormal, 0.0);
}
