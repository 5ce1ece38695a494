// A camera ray through the media (docs/theory.md §16-§18), for the passes that integrate along it
// (preview/media_lights.frag.glsl, preview/media_vpls.frag.glsl, preview/media_compose.frag.glsl): the ray of a pixel,
// the range of each medium before the surface the pixel sees, the transmittance from the camera, and equiangular
// distances (Kulla & Fajardo 2012) as renderer/offline/camera_sample.h draws them. Compiled with PREVIEW_MEDIA > 0 (the
// media count, common/medium.glsl), after a declaration of uCameraPosition (the pass's own, or common/interleaved.glsl's).
#include "common/fullscreen.glsl"
#include "common/medium.glsl"

uniform mat4 uInvViewProj;      // clip space -> world, for the rays of pixels that see no surface
uniform float uSceneDiagonal;   // a span reaching infinity is cut as camera_sample.h mediaSpanEnd() cuts it

struct MediaRay {
  vec3 origin, dir;         // dir unit
  float end;                // distance to the surface the pixel sees (1e30: none)
  float a, b;               // the span of the media before `end`
  vec2 range[PREVIEW_MEDIA];    // each medium's part of the ray, [t0, t1] within [0, end] (empty: t0 >= t1)
};

// The camera ray through the centre of pixel px of an image of `size` pixels whose G-buffer is bound; false when it
// crosses no medium.
bool mediaRayAt(ivec2 px, ivec2 size, out MediaRay r) {
  vec4 pos = texelFetch(gPosition, px, 0);
  r.origin = uCameraPosition;
  if (pos.w > 0.0) {
    vec3 d = pos.xyz - uCameraPosition;
    r.end = length(d);
    r.dir = d / max(r.end, 1e-30);
  } else {
    vec2 ndc = (vec2(px) + 0.5) / vec2(size) * 2.0 - 1.0;
    vec4 far = uInvViewProj * vec4(ndc, 1.0, 1.0);
    r.dir = normalize(far.xyz / far.w - uCameraPosition);
    r.end = 1e30;
  }
  r.a = 1e30;
  r.b = 0.0;
  float leastSigmaT = 1e30;
  for (int m = 0; m < PREVIEW_MEDIA; ++m) {
    vec2 t = mediumRange(m, r.origin, r.dir);
    t = vec2(max(t.x, 0.0), min(t.y, r.end));
    r.range[m] = t;
    if (t.x < t.y) {
      r.a = min(r.a, t.x);
      r.b = max(r.b, t.y);
      vec3 st = media[m].sigmaT.rgb;
      leastSigmaT = min(leastSigmaT, min(st.r, min(st.g, st.b)));
    }
  }
  // A medium filling all space, seen where no surface ends the ray: cut where its least attenuated channel's
  // transmittance is 1e-6, or at 1000 scene diagonals.
  if (r.b >= 1e29) r.b = r.a + (leastSigmaT > 0.0 ? 14.0 / leastSigmaT : 1000.0 * uSceneDiagonal);
  return r.a < r.b;
}

// The medium holding the ray's point at t, or -1 (between boxes).
int mediumAlong(MediaRay r, float t) {
  int found = -1;
  for (int m = 0; m < PREVIEW_MEDIA; ++m)
    if (t >= r.range[m].x && t < r.range[m].y) found = m;
  return found;
}

// Transmittance from the camera to the ray's point at t, the grids' part given: `gridDepth`, their optical depth from
// the ray's entry into each to t (0 without grids).
vec3 cameraTransmittanceGiven(MediaRay r, float t, vec3 gridDepth) {
  vec3 depth = gridDepth;
  for (int m = 0; m < PREVIEW_MEDIA; ++m) {
#ifdef PREVIEW_MEDIA_GRIDS
    if (gridOfMedium(m) >= 0) continue;
#endif
    depth += media[m].sigmaT.rgb * max(0.0, min(r.range[m].y, t) - r.range[m].x);
  }
  return exp(-depth);
}

#ifdef PREVIEW_MEDIA_GRIDS
// Grid g's optical depth along the ray from the ray's entry into it to t (0, not marched, where `needed` is false).
vec3 gridDepthAlong(MediaRay r, int g, float t, bool needed) {
  int m = mediaGridMedium[g];
  vec2 range = r.range[m];
  return media[m].sigmaT.rgb * gridDensityIntegral(g, r.origin, r.dir, range.x, needed ? min(range.y, t) : range.x);
}
#endif

// Transmittance from the camera to the ray's point at t (ray-marched from the camera through each density grid the
// ray crosses; not marched, and meaningless, where `needed` is false: see opticalDepth in common/medium.glsl).
vec3 cameraTransmittance(MediaRay r, float t, bool needed) {
  vec3 gridDepth = vec3(0.0);
#ifdef PREVIEW_MEDIA_GRIDS
  for (int g = 0; g < PREVIEW_MEDIA_GRIDS; ++g) gridDepth += gridDepthAlong(r, g, t, needed);
#endif
  return cameraTransmittanceGiven(r, t, gridDepth);
}

// Equiangular distances in [a, b) around p: t = delta + h tan(theta), theta uniform between the span's angles seen
// from p, pdf h / ((thetaB - thetaA)(h^2 + (t - delta)^2)), which cancels a 1/d^2 toward p. The angles are set up
// once per point (two arc tangents), each distance then costs one tangent.
struct Equiangular {
  float delta, h, thetaA, thetaB;
};

Equiangular equiangularAround(MediaRay r, vec3 p, float minH) {
  Equiangular e;
  e.delta = dot(p - r.origin, r.dir);
  e.h = max(minH, length(r.origin + r.dir * e.delta - p));
  e.thetaA = atan(r.a - e.delta, e.h);
  e.thetaB = atan(r.b - e.delta, e.h);
  return e;
}

// The distance of the uniform number u, and its pdf.
float equiangularDistance(Equiangular e, float u, out float pdf) {
  float t = e.delta + e.h * tan(mix(e.thetaA, e.thetaB, u));
  pdf = e.h / ((e.thetaB - e.thetaA) * (e.h * e.h + (t - e.delta) * (t - e.delta)));
  return t;
}

// Interleaved gradient noise (Jimenez 2014): a deterministic number in [0, 1) per pixel, which the merge of the k x k
// subsets and the box filter of neighbouring pixels average.
float pixelJitter(ivec2 px) { return fract(52.9829189 * fract(dot(vec2(px), vec2(0.06711056, 0.00583715)))); }
