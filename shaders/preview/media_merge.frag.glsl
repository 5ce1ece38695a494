#version 450 core
// Merge of the media passes' k x k interleaved subsets (preview/media_lights.frag.glsl, media_vpls.frag.glsl): each
// pixel averages the k x k window around it, one pixel of every subset, leaving out those whose camera ray ends at a
// different depth (another surface: its ray crosses another length of medium). Written in the image layout, the lights'
// single scattering to colour 0 and the VPLs' in-scattering to colour 1.
#include "common/units.glsl"
#include "common/fullscreen.glsl"

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
  vec3 lights = vec3(0.0), vplLight = vec3(0.0);
  float weight = 0.0;
  for (int y = 0; y < k; ++y)
    for (int x = 0; x < k; ++x) {
      ivec2 q = lo + ivec2(x, y);
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, uImageSize))) continue;
      float e = rayEnd(q);
      if (abs(e - end) > 0.05 * min(e, end)) continue;
      ivec2 texel = (q % k) * uBlockSize + q / k;
      lights += texelFetch(uLightsRaw, texel, 0).rgb;
      vplLight += texelFetch(uVplsRaw, texel, 0).rgb;
      weight += 1.0;
    }
  outLights = vec4(lights / max(weight, 1.0), 1.0);
  outVpls = vec4(vplLight / max(weight, 1.0), 1.0);
}
