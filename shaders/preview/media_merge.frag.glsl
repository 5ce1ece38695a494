#version 450 core
// Merge of the media passes' k x k interleaved subsets (preview/media_lights.frag.glsl, media_vpls.frag.glsl): each
// pixel averages the k x k window around it, one pixel of every subset, leaving out those whose camera ray ends at a
// different depth (another surface: its ray crosses another length of medium). Written in the image layout, the lights'
// single scattering to colour 0 and the VPLs' in-scattering to colour 1.
#include "common/units.glsl"
#include "common/fullscreen.glsl"
#include "common/deinterleaved_texel.glsl"

layout(binding = UNIT_PASS_INPUT0) uniform sampler2D uLightsRaw;  // deinterleaved block layout
layout(binding = UNIT_PASS_INPUT1) uniform sampler2D uVplsRaw;
uniform int uInterleave;
uniform ivec2 uBlockSize;
uniform ivec2 uImageSize;
uniform vec3 uCameraPosition;

layout(location = 0) out vec4 outLights;
layout(location = 1) out vec4 outVpls;

// The distance along the pixel's ray to its surface; 1e30 where it sees none.
float rayEnd(ivec2 px) {
  vec4 p = texelFetch(gPosition, px, 0);
  return p.w > 0.0 ? distance(p.xyz, uCameraPosition) : 1e30;
}

void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  float end = rayEnd(px);
  int k = uInterleave;
  ivec2 lo = px - ivec2((k - 1) / 2);
  ivec2 last = uImageSize - 1;
  vec3 lights = vec3(0.0), vplLight = vec3(0.0);
  float weight = 0.0;
  // Window pixels outside the image or on another surface are fetched at a clamped pixel and left out by selects:
  // llvmpipe would run a branch under a lane mask.
  for (int y = 0; y < k; ++y)
    for (int x = 0; x < k; ++x) {
      ivec2 q = lo + ivec2(x, y);
      bool inside = all(greaterThanEqual(q, ivec2(0))) && all(lessThanEqual(q, last));
      q = clamp(q, ivec2(0), last);
      float e = rayEnd(q);
      bool accepted = inside && abs(e - end) <= 0.05 * min(e, end);
      ivec2 texel = deinterleavedTexel(q, k, uBlockSize);
      vec3 l = texelFetch(uLightsRaw, texel, 0).rgb, v = texelFetch(uVplsRaw, texel, 0).rgb;
      lights += accepted ? l : vec3(0.0);
      vplLight += accepted ? v : vec3(0.0);
      weight += accepted ? 1.0 : 0.0;
    }
  outLights = vec4(lights / max(weight, 1.0), 1.0);
  outVpls = vec4(vplLight / max(weight, 1.0), 1.0);
}
