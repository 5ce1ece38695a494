#version 450 core
// The image through the media (docs/theory.md §16): the radiance leaving the surface a pixel sees, attenuated by the
// transmittance along the camera ray to it, plus the light the media scatter into the ray (preview/media_merge.frag.glsl,
// on the indirect light's grid, interpolated):
//   L = T(camera, surface) L_surface + uWeights.y L_lights + uWeights.z L_vpls + uWeights.w C (L_lights + L_vpls),
// C the approximate bias compensation's factor of the first medium the ray meets (renderer/gl/media_pass.h).
#include "common/units.glsl"
#include "common/fullscreen.glsl"
#include "common/medium.glsl"

uniform vec3 uCameraPosition;
#include "common/media_ray.glsl"

layout(binding = UNIT_PASS_INPUT0) uniform sampler2D uSurface;  // what the passes before computed, full resolution
layout(binding = UNIT_PASS_INPUT1) uniform sampler2D uLights;   // merged single scattering of the lights
layout(binding = UNIT_PASS_INPUT2) uniform sampler2D uVpls;     // merged in-scattering of the VPLs
uniform vec4 uWeights;
uniform ivec2 uImageSize;

layout(location = 0) out vec4 outColor;

void main() {
  ivec2 px = ivec2(gl_FragCoord.xy);
  vec3 surface = texelFetch(uSurface, px, 0).rgb;
  MediaRay r;
  vec3 transmittance = mediaRayAt(px, uImageSize, r) ? cameraTransmittance(r, r.end, true) : vec3(1.0);
  vec2 uv = (vec2(px) + 0.5) / vec2(uImageSize);
  vec3 lights = texture(uLights, uv).rgb, vpls = texture(uVpls, uv).rgb;
  int first = 0;
  for (int m = 1; m < PREVIEW_MEDIA; ++m)
    if (r.range[m].x < r.range[m].y && (r.range[m].x < r.range[first].x || r.range[first].x >= r.range[first].y))
      first = m;
  vec3 compensation = media[first].compensation.rgb * (lights + vpls);
  outColor = vec4(uWeights.x * transmittance * surface + uWeights.y * lights + uWeights.z * vpls +
                      uWeights.w * compensation,
                  1.0);
}
