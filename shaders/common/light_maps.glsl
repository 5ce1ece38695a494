// The lights' shadow maps as the direct pass binds them (renderer/gl/light_shadows.h): a cube map of radial distances
// per point or spot light and per area-light cell, and an orthographic map per directional light. Read by the direct
// light (common/light_shadow.glsl) and the media's single scattering (preview/media_lights.frag.glsl).
layout(binding = UNIT_LIGHT_SHADOWS) uniform samplerCubeArray uLightShadows;
// Directional lights: an orthographic map each (layer of a 2D array) over the disc of radius uSceneRadius around
// uSceneCentre perpendicular to the light's direction, storing the distance along the direction from the plane
// uSceneRadius behind the centre.
layout(binding = UNIT_DIRECTIONAL_SHADOWS) uniform sampler2DArray uDirectionalShadows;
uniform vec3 uSceneCentre;
uniform float uSceneRadius;
uniform float uDirectionalShadowTexel;  // 2 uSceneRadius / map size, metres
uniform float uLightShadowTexel;  // angle of a texel at a face's centre, 2 / faceSize: a point or spot light's map
uniform float uAreaShadowTexel;   // the same for an area-light cell's map, drawn with fewer texels
// Each cube's distances are stored as fractions of its scale (renderer/gl/light_shadows.h); 1 where no triangle lies.
layout(std430, binding = BINDING_LIGHT_SHADOW_SCALES) readonly buffer LightShadowScales { float lightShadowScales[]; };

// The distance stored in cube `cube` in direction u (infinite where nothing lies).
float lightShadowDistance(vec3 u, float cube) {
  float stored = texture(uLightShadows, vec4(u, cube)).r;
  return stored >= 1.0 ? 3.0e38 : stored * lightShadowScales[int(cube)];
}
