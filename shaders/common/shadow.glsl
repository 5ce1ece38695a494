// Cube shadow maps (renderer/gl/shadow_maps.h): depth = distance to the caster / far, one cube per caster, stored as
// layers 6 caster + face of a 2D array. The face and its texture coordinates are found here with the same face
// orientations the maps were rendered with (GL cube-map convention, shadow_maps.cpp): a 90 degree perspective view
// looking down the major axis of the offset.
// Normal-offset lookup: the receiver point moves along its geometric normal by about one shadow texel's world size
// at that distance, which removes acne on surfaces seen at grazing angles without a large constant bias.
// distance = |x - casterPos|, which the caller usually has already.
float shadowVisibilityAt(sampler2DArrayShadow maps, int caster, vec3 casterPos, vec3 x, float distance, vec3 geoNormal,
                         float far, float bias) {
  float texelAngle = 2.0 / float(textureSize(maps, 0).x);
  vec3 p = x + geoNormal * (1.5 * texelAngle * distance);
  vec3 d = p - casterPos;
  vec3 a = abs(d);
  // Major axis, its face (+x, -x, +y, -y, +z, -z) and the face coordinates of the GL cube-map convention the maps are
  // rendered with (shadow_maps.cpp): face f looks down the axis with view space (s, u, -target). Written with selects,
  // not branches: llvmpipe would run all three branches for every lane.
  bool xMajor = a.x >= a.y && a.x >= a.z;
  bool yMajor = !xMajor && a.y >= a.z;
  float major = xMajor ? a.x : yMajor ? a.y : a.z;
  vec2 st = xMajor ? vec2(-sign(d.x) * d.z, -d.y) : yMajor ? vec2(d.x, sign(d.y) * d.z) : vec2(sign(d.z) * d.x, -d.y);
  float face = xMajor ? (d.x > 0.0 ? 0.0 : 1.0) : yMajor ? (d.y > 0.0 ? 2.0 : 3.0) : (d.z > 0.0 ? 4.0 : 5.0);
  vec2 uv = st / major * 0.5 + 0.5;
  // Hardware 2x2 PCF (linear filtering with depth comparison) softens the texel staircase.
  return texture(maps, vec4(uv, float(6 * caster) + face, (length(d) - bias) / far));
}

float shadowVisibility(sampler2DArrayShadow maps, int caster, vec3 casterPos, vec3 x, vec3 geoNormal, float far,
                       float bias) {
  return shadowVisibilityAt(maps, caster, casterPos, x, length(x - casterPos), geoNormal, far, bias);
}
