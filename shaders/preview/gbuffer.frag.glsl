#version 450 core
#include "common/units.glsl"
#include "common/scene.glsl"
#include "common/gbuffer_packing.glsl"

layout(binding = UNIT_SCENE_TEXTURES) uniform sampler2DArray uSceneTextures;  // base-colour and emissive textures

in vec3 vPosition;
in vec3 vNormal;
in vec2 vUv;
flat in vec3 vGeoNormal;
flat in uint vMaterial;
uniform vec3 uCameraPosition;

#include "common/gbuffer_outputs.glsl"

// SCENE_TEXTURED 0: no material of the scene has a texture. llvmpipe runs a branch's body for every pixel under a lane
// mask, so the texture lookups would cost every pixel of an untextured scene (0.8-2 ms of the Cornell box's 640x480
// G-buffer); such a scene draws this variant without them.
void main() {
  GlMaterial m = sceneMaterials[vMaterial];
  vec3 base = m.baseColor.rgb;
#if SCENE_TEXTURED
  if (m.baseColor.w >= 0.0) base *= texture(uSceneTextures, vec3(vUv, m.baseColor.w)).rgb;
#endif
  outPosition = vec4(vPosition, 1.0);
  vec3 n = normalize(vNormal);
  outNormal = vec4(n, m.params.x);
  outMergeKey = vec4(n, length(vPosition - uCameraPosition));
  outBaseColor = vec4(base, m.params.y);
  vec3 emission = m.emission.rgb;
#if SCENE_TEXTURED
  if (m.emission.w >= 0.0) {
    vec2 st = vec2(dot(m.emissiveUvRow0.xyz, vec3(vUv, 1.0)), dot(m.emissiveUvRow1.xyz, vec3(vUv, 1.0)));
    emission *= texture(uSceneTextures, vec3(st, m.emission.w)).rgb;
  }
#endif
  // Le as the camera sees it: a one-sided emitter only from the side its geometric normal faces, so that the
  // compositions add it without a test.
  bool front = dot(vGeoNormal, uCameraPosition - vPosition) > 0.0;
  outEmission = vec4(front ? emission : vec3(0.0), m.params.z);
  outShading = packShading(n, base, m.params.x, m.params.y, m.params.z);
  outSurface = packSurface(vPosition, vGeoNormal);
}
