#version 450 core
// Single scattering of the lights along camera rays (docs/theory.md §16, §18): per pixel, the integral over the media
// the ray crosses before its surface of T(0, t) sigma_s(x(t)) f_p L_light(x(t)) (sigma_s varies in a density grid),
// with the direct pass's lights (preview/direct.frag.glsl: its K area-light samples and punctual lights) and their
// shadow maps:
//   L_light = weight cosLight / d^2 * T(light, x) * V          (area sample y_k, one-sided, weight = Le / (K p_A))
//           = I(-w) / d^2 * T(light, x) * V                     (point or spot light, KHR_lights_punctual falloff)
//           = E * T(x -> infinity) * V                          (directional light)
// estimated with uMediaSteps distances per punctual or directional light, drawn equiangularly around it (uniformly over
// the span for a directional light), stratified and rotated per pixel and per light. An area light's samples share
// those distances: each of a pixel's samples takes uAreaSteps of them (uMediaSteps over the samples the pixel takes, at
// least one), rotated per pixel and per sample, so that a pixel marches toward the light uMediaSteps times, not
// uMediaSteps times per sample (the estimate stays unbiased; its noise is what the merge of the subsets averages).
// V is one lookup in the light's map (no filter: a medium point has no surface to bias against, and the ray's integral
// smooths the shadow's edge).
// Interleaved like the direct pass: pixel subset s takes the area samples s, s + k^2, ... with weight k^2; the few
// punctual and directional lights are taken at every pixel. Written in the deinterleaved block layout
// (common/interleaved.glsl) and merged by preview/media_merge.frag.glsl.
#include "common/media_interleaved.glsl"
#include "common/phase.glsl"

// The layout of the direct pass's light table (preview/direct.frag.glsl).
struct DirectLight {
  vec4 position;  // xyz, w: 0 area sample, 1 point, 2 spot, 3 directional
  vec4 axis;      // emitter normal, spot axis or direction of travel; w: cos(outer cone)
  vec4 weight;    // rgb: Le / (K p_A), intensity or irradiance; w: cos(inner cone)
  vec4 shadow;    // x: the light's map
  vec4 centre;    // xyz: where that map was rendered from
};
layout(std140, binding = BINDING_DIRECT_LIGHTS) uniform DirectLights {
  DirectLight lights[DIRECT_UBO_LIGHTS];
};

#include "common/light_maps.glsl"

uniform int uMediaSteps;   // distances per punctual or directional light and pixel
uniform int uAreaSteps;    // distances per area sample and pixel
uniform int uAreaFirst;    // this subset's first area sample in the bound range
uniform int uAreaEnd;      // one past the last area sample in the bound range
uniform int uPunctualEnd;  // one past the last point or spot light; directional lights follow up to uLightEnd

layout(location = 0) out vec4 outColor;

const int kAreaLight = 0, kPunctualLight = 1, kDirectionalLight = 2;

// T(0, t) sigma_s f_p L_light(x(t)) / pdf(t), summed over the light's distances and divided by their count. `kind` is
// a constant at every call, so each loop below is compiled without the other kinds' code.
vec3 scatteredLight(DirectLight l, const int kind, MediaRay r, float rotation, float minH, int steps) {
  vec3 sum = vec3(0.0);
  Equiangular around = equiangularAround(r, l.position.xyz, minH);
#ifdef PREVIEW_MEDIA_GRIDS
  // The distances grow with j (u does, and both mappings below are increasing), so the march through each grid from
  // the camera continues from the previous distance: one march per light and grid instead of one per distance (each
  // as fine). Grids the ray crosses one behind the other each add their whole depth once the distance is past them.
  float marchedTo[PREVIEW_MEDIA_GRIDS], marched[PREVIEW_MEDIA_GRIDS];
  for (int g = 0; g < PREVIEW_MEDIA_GRIDS; ++g) {
    marchedTo[g] = r.range[mediaGridMedium[g]].x;
    marched[g] = 0.0;
  }
#endif
  for (int j = 0; j < steps; ++j) {
    float u = (float(j) + rotation) / float(steps);
    float pdf, t;
    if (kind == kDirectionalLight) {
      t = mix(r.a, r.b, u);
      pdf = 1.0 / (r.b - r.a);
    } else {
      t = equiangularDistance(around, u, pdf);
    }
    int m = mediumAlong(r, t);
    int medium = max(m, 0);
    vec3 x = r.origin + r.dir * t;
    vec3 w;
    float falloff, visibility;
    if (kind == kDirectionalLight) {
      w = -l.axis.xyz;
      falloff = 1.0;
      vec3 s, tt;
      orthonormalFrame(l.axis.xyz, s, tt);
      vec3 p = x - uSceneCentre;
      vec2 uv = vec2(dot(p, s), dot(p, tt)) / (2.0 * uSceneRadius) + 0.5;
      float depth = dot(p, l.axis.xyz) + uSceneRadius;
      float stored = texture(uDirectionalShadows, vec3(uv, l.shadow.x)).r;
      visibility = stored >= depth - 2.0 * uDirectionalShadowTexel ? 1.0 : 0.0;
    } else {
      vec3 d = l.position.xyz - x;
      float dist2 = max(dot(d, d), 1e-30);
      w = d * inversesqrt(dist2);
      float cosLight = -dot(l.axis.xyz, w);
      if (kind == kAreaLight) {
        falloff = max(cosLight, 0.0) / dist2;
      } else {
        float s = clamp((cosLight - l.axis.w) / max(0.001, l.weight.w - l.axis.w), 0.0, 1.0);
        falloff = (l.position.w == 2.0 ? s * s : 1.0) / dist2;
      }
      vec3 fromCentre = x - l.centre.xyz;
      float stored = lightShadowDistance(fromCentre, l.shadow.x);
      float texel = kind == kAreaLight ? uAreaShadowTexel : uLightShadowTexel;
      visibility = stored >= length(fromCentre) * (1.0 - 2.0 * texel) ? 1.0 : 0.0;
    }
    float phase = phaseHG(dot(w, r.dir), media[medium].sigmaS.w);
    bool contributes = m >= 0 && pdf > 0.0 && falloff * visibility > 0.0;
#ifdef PREVIEW_MEDIA_GRIDS
    vec3 gridDepth = vec3(0.0);
    for (int g = 0; g < PREVIEW_MEDIA_GRIDS; ++g) {
      int gm = mediaGridMedium[g];
      vec2 range = r.range[gm];
      float reach = min(max(t, range.x), range.y);  // not clamp: the range is empty where the ray misses the grid
      marched[g] += gridDensityIntegral(g, r.origin, r.dir, marchedTo[g], reach);
      marchedTo[g] = max(marchedTo[g], reach);
      gridDepth += media[gm].sigmaT.rgb * marched[g];
    }
    vec3 toCamera = cameraTransmittanceGiven(r, t, gridDepth);
#else
    vec3 toCamera = cameraTransmittance(r, t, contributes);
#endif
    vec3 term = toCamera * mediumSigmaS(medium, x) * (phase * falloff * visibility / pdf) * l.weight.rgb *
                mediaLightTransmittance(l.position, l.axis.xyz, x, contributes);
    sum += contributes ? term : vec3(0.0);
  }
  return sum / float(steps);
}

void main() {
  MediaPixel at;
  if (!interleavedMediaPixel(at)) {
    outColor = vec4(0.0);
    return;
  }
  MediaRay r = at.ray;
  int k2 = at.k2;
  float jitter = at.jitter, minH = at.minH;
  vec3 sum = vec3(0.0);
  // Each light's distances rotated by its own amount (the golden ratio's fraction), so that lights do not share strata;
  // a pixel's area samples (i = subset + k^2 q) by their ordinal q, so that the pixel's few distances spread over [0, 1).
  for (int i = uAreaFirst; i < uAreaEnd; i += k2)
    sum += float(k2) * scatteredLight(lights[i - uUboBase], kAreaLight, r, fract(jitter + 0.618034 * float(i / k2)),
                                      minH, uAreaSteps);
  for (int i = max(uAreaEnd, uLightBegin); i < uPunctualEnd; ++i)
    sum += scatteredLight(lights[i - uUboBase], kPunctualLight, r, fract(jitter + 0.618034 * float(i)), minH,
                          uMediaSteps);
  for (int i = max(uPunctualEnd, uLightBegin); i < uLightEnd; ++i)
    sum += scatteredLight(lights[i - uUboBase], kDirectionalLight, r, fract(jitter + 0.618034 * float(i)), minH,
                          uMediaSteps);
  outColor = vec4(sum, 1.0);
}
