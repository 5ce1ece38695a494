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
  vec3 d = x + geoNormal * (1.5 * texelAngle * distance) - casterPos;
  vec3 a = abs(d);
  // Major axis m (signed), its face (+x, -x, +y, -y, +z, -z) and the face coordinates of the GL cube-map convention the
  // maps are rendered with (shadow_maps.cpp): face f looks down the axis with view space (s, u, -target), i.e.
  //   +-x: (-sign(m) d.z, -d.y) / |m|,  +-y: (d.x, sign(m) d.z) / |m|,  +-z: (sign(m) d.x, -d.y) / |m|,
  // where sign(m) / |m| = 1 / m. Written with selects, not branches: llvmpipe would run all three branches for every
  // lane.
  bool xMajor = a.x >= a.y && a.x >= a.z;
  bool yMajor = !xMajor && a.y >= a.z;
  float m = xMajor ? d.x : yMajor ? d.y : d.z;
  float inv = 0.5 / m, absInv = abs(inv);
  vec2 uv = vec2(xMajor ? -d.z * inv : d.x * (yMajor ? absInv : inv), yMajor ? d.z * inv : -d.y * absInv) + 0.5;
  float face = (xMajor ? 0.0 : yMajor ? 2.0 : 4.0) + (m > 0.0 ? 0.0 : 1.0);
  return texture(maps, vec4(uv, float(6 * caster) + face, (length(d) - bias) / far));
}

float shadowVisibility(sampler2DArrayShadow maps, int caster, vec3 casterPos, vec3 x, vec3 geoNormal, float far,
                       float bias) {
  return shadowVisibilityAt(maps, caster, casterPos, x, length(x - casterPos), geoNormal, far, bias);
}
