// VPL visibility from one shadow map per VPL (renderer/gl/vpl_visibility.h CubeVisibility, shadow_maps.h): a whole
// cube for a medium VPL, a hemicube for a surface VPL.
#include "common/shadow.glsl"

layout(binding = UNIT_VISIBILITY) uniform sampler2DArrayShadow uVisibilityMaps;
uniform float uShadowFar;
uniform float uShadowBias;
// How many of the chunk's casters (its first ones, the medium VPLs) have whole cubes.
uniform int uWholeCubes;

// caster: the VPL's index inside the bound chunk; distance = |x - casterPos|.
float vplVisibility(int caster, vec3 casterPos, vec3 casterNormal, vec3 x, float distance, vec3 geoNormal) {
  float size = float(textureSize(uVisibilityMaps, 0).x);
  // Six layers per whole cube, then three per hemicube.
  int firstLayer = 3 * caster + 3 * min(caster, uWholeCubes);
  vec3 d = shadowLookupOffset(size, casterPos, x, distance, geoNormal);
  vec4 at = hemicubeShadowCoordinates(d, size, firstLayer, casterNormal, uShadowFar, uShadowBias);
#if PREVIEW_MEDIA > 0
  // Only a scene with media has medium VPLs.
  at = caster < uWholeCubes ? cubeShadowCoordinates(d, firstLayer, uShadowFar, uShadowBias) : at;
#endif
  return texture(uVisibilityMaps, at);
}
