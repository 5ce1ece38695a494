#version 450 core
// Per block of kSsbcCoarseSpacing x kSsbcCoarseSpacing pixels (common/ssbc.glsl), once per camera: 1 when every
// surface texel that a fine-ring tap of a pixel in the block can reach (the pixels within 5 of the block, the reach
// of the level-1 ring) lies on the plane of one surface, else 0. For such a pixel every fine tap is coplanar with it,
// so cos theta_1 = 0 and the fine rings add exactly nothing (G = 0 <= b): the fine pass (SSBC_FINE_PASS) skips
// those pixels (its mask, ssbc_mask.frag.glsl), and only the ones near creases, silhouettes and curved surfaces pay
// for the fine rings. Background and off-screen texels do not take part in a tap, so they do not break a plane.
// Separable, because the windows of neighbouring blocks overlap (14 x 14 pixels at a stride of 4): SSBC_FLAT_ROWS
// summarises each 14-pixel row segment of a block's window (its first surface texel's plane, and whether the others
// lie on it); the column pass then checks that a block's 14 segments lie on one plane.
#include "common/units.glsl"
#include "common/fullscreen.glsl"
#include "common/brdf.glsl"
#include "common/ssbc.glsl"

const int kReach = 5;
const int kWindow = kSsbcCoarseSpacing + 2 * kReach;

#if SSBC_FLAT_ROWS
layout(binding = UNIT_G_MERGE_KEY) uniform sampler2D gMergeKey;  // xyz shading normal, w distance to the camera (0: background)
layout(location = 0) out vec4 outPlane;            // xyz unit normal n0, w offset c0 of the plane n0 . x = c0
layout(location = 1) out vec4 outState;            // x: 1 if the segment has a surface texel, y: 1 if all lie on the
                                                   // plane, z: the offset tolerance

void main() {
  ivec2 size = textureSize(gPosition, 0);
  int y = int(gl_FragCoord.y);
  int lo = int(gl_FragCoord.x) * kSsbcCoarseSpacing - kReach;
  bool planar = true, found = false;
  vec3 n0 = vec3(0.0);
  float c0 = 0.0, tolerance = 0.0;
  for (int x = lo; x < lo + kWindow; ++x) {
    ivec2 q = clamp(ivec2(x, y), ivec2(0), size - 1);
    vec4 key = texelFetch(gMergeKey, q, 0);
    bool use = q.x == x && key.w > 0.0;
    // The first surface texel defines the plane n0 . x = c0; the others must share the normal and lie on that plane
    // (within a millionth of the camera distance, about float precision).
    bool first = use && !found;
    n0 = first ? key.xyz : n0;
    float offset = dot(n0, texelFetch(gPosition, q, 0).xyz);
    c0 = first ? offset : c0;
    tolerance = first ? 1e-6 * key.w + 1e-7 : tolerance;
    found = found || use;
    planar = planar && (!use || (dot(key.xyz, n0) >= 1.0 - 1e-6 && abs(offset - c0) <= tolerance));
  }
  bool inside = y < size.y;
  outPlane = vec4(n0, c0);
  outState = vec4(found && inside ? 1.0 : 0.0, planar ? 1.0 : 0.0, tolerance, 0.0);
}
#else
layout(binding = UNIT_PASS_INPUT4) uniform sampler2D uRowPlanes;  // SSBC_FLAT_ROWS outPlane
layout(binding = UNIT_PASS_INPUT6) uniform sampler2D uRowStates;  // SSBC_FLAT_ROWS outState
layout(location = 0) out vec4 outFlat;

void main() {
  int rows = textureSize(uRowPlanes, 0).y;
  int x = int(gl_FragCoord.x);
  int lo = int(gl_FragCoord.y) * kSsbcCoarseSpacing - kReach;
  bool planar = true, found = false;
  vec4 p0 = vec4(0.0);
  float tolerance = 0.0;
  for (int y = lo; y < lo + kWindow; ++y) {
    int row = clamp(y, 0, rows - 1);
    vec4 plane = texelFetch(uRowPlanes, ivec2(x, row), 0), state = texelFetch(uRowStates, ivec2(x, row), 0);
    bool use = row == y && state.x > 0.5;
    bool first = use && !found;
    p0 = first ? plane : p0;
    tolerance = first ? state.z : tolerance;
    found = found || use;
    planar = planar && (!use || (state.y > 0.5 && dot(plane.xyz, p0.xyz) >= 1.0 - 1e-6 &&
                                 abs(plane.w - p0.w) <= tolerance + state.z));
  }
  outFlat = vec4(planar ? 1.0 : 0.0, 0.0, 0.0, 1.0);
}
#endif
