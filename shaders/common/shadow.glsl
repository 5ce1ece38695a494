// VPL shadow maps (renderer/gl/shadow_maps.h): depth = distance to the caster / far, from cube faces stored as layers
// of a 2D array: a whole cube (6 layers) or a hemicube around a surface VPL's normal (3 layers). The face and its
// texture coordinates are found here with the same orientations the maps were drawn with (shadow_maps.cpp): a 90
// degree perspective view looking down the major axis of the offset.
#include "common/math.glsl"

// The offset from the caster that a lookup reads: the receiver x moved along its geometric normal by about one shadow
// texel's world size at that distance (normal-offset lookup), which removes acne on surfaces seen at grazing angles
// without a large constant bias. size: the maps' face size in texels; distance = |x - casterPos|, which the caller
// usually has already.
vec3 shadowLookupOffset(float size, vec3 casterPos, vec3 x, float distance, vec3 geoNormal) {
  return x + geoNormal * (1.5 * (2.0 / size) * distance) - casterPos;
}

// The lookups below return the shadow texture's coordinates (u, v, layer, depth reference) for the offset d of
// shadowLookupOffset, so that a caller choosing between a cube and a hemicube fetches once: llvmpipe runs both sides
// of a branch for every lane.

// A whole cube, from layer firstLayer on.
vec4 cubeShadowCoordinates(vec3 d, int firstLayer, float far, float bias) {
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
  return vec4(uv, float(firstLayer) + face, (length(d) - bias) / far);
}

// A hemicube around the unit normal n, from layer firstLayer on: the face along n, then the upper halves of the faces
// along +s (upper half of layer 1) and -s (its lower half), +t and -t (layer 2), with n up, in the frame (s, t, n) of
// orthonormalFrame. A receiver behind the caster's plane reads the map at the horizon (a VSL can reach slightly past
// it; a point VPL's cosine is 0 there anyway).
vec4 hemicubeShadowCoordinates(vec3 d, float size, int firstLayer, vec3 n, float far, float bias) {
  vec3 s, t;
  orthonormalFrame(n, s, t);
  float ls = dot(d, s), lt = dot(d, t), ln = max(dot(d, n), 0.0);
  bool front = ln >= max(abs(ls), abs(lt));
  bool sMajor = abs(ls) >= abs(lt);
  float m = sMajor ? ls : lt;
  // Front face: (s, t) / n. Side face along +-s: (t, n) / |s|; along +-t: (s, n) / |t|. Selects, not branches.
  vec2 uv = (front ? vec2(ls, lt) : vec2(sMajor ? lt : ls, ln)) * (0.5 / (front ? ln : abs(m))) + 0.5;
  // A side face's upper half is the upper half of its layer for +s, +t and the lower half for -s, -t; the 2x2 filter
  // stays inside its half.
  float halfTexel = 0.5 / size;
  float v = m > 0.0 ? max(uv.y, 0.5 + halfTexel) : min(uv.y - 0.5, 0.5 - halfTexel);
  uv.y = front ? uv.y : v;
  float layer = float(firstLayer) + (front ? 0.0 : sMajor ? 1.0 : 2.0);
  return vec4(uv, layer, (length(d) - bias) / far);
}
