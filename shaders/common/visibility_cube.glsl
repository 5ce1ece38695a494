// VPL visibility from one cube shadow map per VPL (renderer/gl/vpl_visibility.h CubeVisibility, shadow_maps.h).
#include "common/shadow.glsl"

layout(binding = UNIT_VISIBILITY) uniform sampler2DArrayShadow uVisibilityMaps;
uniform float uShadowFar;
uniform float uShadowBias;

// caster: the VPL's index inside the bound chunk; distance = |x - casterPos|.
float vplVisibility(int caster, vec3 casterPos, vec3 casterNormal, vec3 x, float distance, vec3 geoNormal) {
  return shadowVisibilityAt(uVisibilityMaps, caster, casterPos, x, distance, geoNormal, uShadowFar, uShadowBias);
}
