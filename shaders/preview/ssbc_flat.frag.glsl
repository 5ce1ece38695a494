#version 450 core
// Per block of kSsbcCoarseSpacing x kSsbcCoarseSpacing pixels (common/ssbc.glsl), once per camera: 1 when every
// surface texel that a fine-ring tap of a pixel in the block can reach (the pixels within 5 of the block, the reach
// of the level-1 ring) lies on the plane of one surface, else 0. For such a pixel every fine tap is coplanar with it,
// so cos theta_1 = 0 and the fine rings add exactly nothing (G = 0 <= b): the fine pass (SSBC_FINE_PASS) discards
// those pixels, and only the ones near creases, silhouettes and curved surfaces pay for the fine rings. Background
// and off-screen texels do not take part in a tap, so they do not break a plane.
#include "common/fullscreen.glsl"
#include "common/brdf.glsl"
#include "common/ssbc.glsl"

layout(binding = 10) uniform sampler2D gMergeKey;  // xyz shading normal, w distance to the camera (0: background)
layout(location = 0) out vec4 outFlat;

const int kReach = 5;

void main() {
  ivec2 size = textureSize(gPosition, 0);
  ivec2 lo = ivec2(gl_FragCoord.xy) * kSsbcCoarseSpacing - kReach;
  ivec2 hi = lo + (kSsbcCoarseSpacing - 1 + 2 * kReach);
  bool planar = true, found = false;
  vec3 n0 = vec3(0.0);
  float c0 = 0.0, tolerance = 0.0;
  for (int y = lo.y; y <= hi.y; ++y)
    for (int x = lo.x; x <= hi.x; ++x) {
      ivec2 q = clamp(ivec2(x, y), ivec2(0), size - 1);
      vec4 key = texelFetch(gMergeKey, q, 0);
      bool use = all(equal(q, ivec2(x, y))) && key.w > 0.0;
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
  outFlat = vec4(planar ? 1.0 : 0.0, 0.0, 0.0, 1.0);
}
