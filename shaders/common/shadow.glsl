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
  // Face f looks down axis `target` with the GL `up`; view space is (s, u, -target), s = target x up, u = s x target.
  int face;
  vec3 target, up;
  if (a.x >= a.y && a.x >= a.z) {
    face = d.x > 0.0 ? 0 : 1;
    target = vec3(sign(d.x), 0.0, 0.0);
    up = vec3(0.0, -1.0, 0.0);
  } else if (a.y >= a.z) {
    face = d.y > 0.0 ? 2 : 3;
    target = vec3(0.0, sign(d.y), 0.0);
    up = vec3(0.0, 0.0, sign(d.y));
  } else {
    face = d.z > 0.0 ? 4 : 5;
    target = vec3(0.0, 0.0, sign(d.z));
    up = vec3(0.0, -1.0, 0.0);
  }
  vec3 s = cross(target, up), u = cross(s, target);
  vec2 uv = vec2(dot(s, d), dot(u, d)) / dot(target, d) * 0.5 + 0.5;
  // Hardware 2x2 PCF (linear filtering with depth comparison) softens the texel staircase.
  return texture(maps, vec4(uv, float(6 * caster + face), (length(d) - bias) / far));
}

float shadowVisibility(sampler2DArrayShadow maps, int caster, vec3 casterPos, vec3 x, vec3 geoNormal, float far,
                       float bias) {
  return shadowVisibilityAt(maps, caster, casterPos, x, length(x - casterPos), geoNormal, far, bias);
}
