// Cube shadow maps (renderer/gl/shadow_maps.h): depth = distance to the caster / far, one cube per caster.
// Normal-offset lookup: the receiver point moves along its geometric normal by about one shadow texel's world size
// at that distance, which removes acne on surfaces seen at grazing angles without a large constant bias.
float shadowVisibility(samplerCubeArrayShadow maps, int layer, vec3 casterPos, vec3 x, vec3 geoNormal, float far,
                       float bias) {
  float texelAngle = 2.0 / float(textureSize(maps, 0).x);
  vec3 p = x + geoNormal * (1.5 * texelAngle * length(x - casterPos));
  vec3 d = p - casterPos;
  // Hardware 2x2 PCF (linear filtering with depth comparison) softens the texel staircase.
  return texture(maps, vec4(d, float(layer)), (length(d) - bias) / far);
}
