#version 450 core
// In-scattering of the VPLs along camera rays (docs/theory.md §17): per pixel and VPL of its interleaving subset, one
// distance t drawn equiangularly around the VPL over the span of the media the ray crosses (as the CPU's VPL render,
// renderer/offline/vpl_renderer.cpp mediumAlongRay, draws it), and there
//   T(0, t) sigma_s(x) f_p(x; -dir, w) G_b [VPL end: f(x2; w_in, -w) | f_p(x2; w_in, -w)] Phi T(x, x2) V / pdf(t),
//   G = (cosine at the VPL if it lies on a surface) / d^2, G_b = min(G, b)   (no cosine at the medium point x),
// V from the gather's VPL visibility technique (common/visibility.glsl). Interleaved like the gather (pixel subset s
// takes VPLs s, s + k^2, ... with weight k^2) and written in its deinterleaved block layout; merged by
// preview/media_merge.frag.glsl.
#include "common/media_interleaved.glsl"
#include "common/phase.glsl"
#include "common/visibility.glsl"
#include "common/vpl_table.glsl"

uniform float uClampBound;  // b

layout(location = 0) out vec4 outColor;

void main() {
  MediaPixel pixel;
  if (!interleavedMediaPixel(pixel)) {
    outColor = vec4(0.0);
    return;
  }
  MediaRay r = pixel.ray;
  int k2 = pixel.k2;
  float jitter = pixel.jitter, minH = pixel.minH;
  vec3 sum = vec3(0.0);
  for (int i = uLightBegin + uSubsetOffset; i < uLightEnd; i += k2) {
    GlVpl vpl = vpls[i - uUboBase];
    vec3 x2 = vpl.position.xyz;
    float pdf;
    float t = equiangularDistance(equiangularAround(r, x2, minH), fract(jitter + 0.618034 * float(i)), pdf);
    int m = mediumAlong(r, t);
    int medium = max(m, 0);
    vec3 x = r.origin + r.dir * t;
    vec3 d = x2 - x;
    float dist2 = max(dot(d, d), 1e-30);
    float dist = sqrt(dist2);
    vec3 w = d / dist;
    bool mediumVpl = vpl.geoNormal.w > 0.5;
    float cos2 = mediumVpl ? 1.0 : -dot(vpl.normal.xyz, w);
    bool faces = mediumVpl || dot(vpl.geoNormal.xyz, w) < 0.0;
#ifdef BRDF_LAMBERT_ONLY
    vec3 end = vpl.lambertPower.rgb;
#else
    BrdfParams p2 = BrdfParams(vpl.baseColor.rgb, vpl.normal.w, vpl.incoming.w, vpl.flux.w);
    vec3 end = mediumVpl ? vpl.flux.rgb : evaluateBrdf(p2, vpl.normal.xyz, vpl.incoming.xyz, -w) * vpl.flux.rgb;
#endif
    end *= mediumVpl ? phaseHG(dot(vpl.incoming.xyz, w), vpl.baseColor.w) : 1.0;
    float v = vplVisibility(i - uFirstLight, x2, vpl.geoNormal.xyz, x, dist, vec3(0.0));
    float gb = min(cos2 / dist2, uClampBound);
    float phase = phaseHG(dot(w, r.dir), media[medium].sigmaS.w);
    bool contributes = m >= 0 && faces && cos2 > 0.0 && pdf > 0.0 && v > 0.0;
    vec3 term = cameraTransmittance(r, t, contributes) * mediumSigmaS(medium, x) * (phase * gb * v / pdf) * end *
                mediaTransmittance(x, x2, contributes);
    sum += contributes ? term : vec3(0.0);
  }
  outColor = vec4(sum * float(k2), 1.0);
}
