// Pass 4, VPL gather (docs/theory.md §1, §4, §7, §8), included by preview/gather.frag.glsl (GATHER_VSL 0: point VPLs only)
// and preview/gather_vsl.frag.glsl (GATHER_VSL 1: point VPLs and VSLs). llvmpipe executes both sides of a branch under
// a lane mask even when the condition is uniform, so the VSL code would cost every point-VPL evaluation ~30% of the
// gather; the renderer picks the variant from the VPL set.
//   point VPL:  f(x1; wo, w) G_b(x1, x2) V f(x2; w_in, -w) Phi,  G_b = min(G, b)     (same as vpl_contribution.h)
//   VSL:        Phi T V, T = 1 / (pi r^2) * integral over the cone Omega subtended by the sphere of radius r around
//               x2 of f(x1; wo, w) f(x2; w_in, -w) max(0, n1.w) max(0, n2.(-w)) dw   (Hasan et al. 2009, §7),
//               evaluated by the deterministic approximation of common/vsl.glsl (no per-pixel random samples); a VPL
//               of radius 0 in such a set is the unclamped point VPL (T's limit), as on the CPU. No G clamp: T is
//               bounded by construction. V is the shadow-map visibility toward the sphere centre.
//   Interleaved sampling (Keller & Heidrich 2001): pixel (x, y) uses the subset s = (y mod k) k + (x mod k), i.e.
//   VPLs i = s, s + k^2, ..., each with flux * k^2; the de-interleave pass merges the k x k subsets.
//   Deinterleaved layout (Segovia et al. 2006): the output is split into k x k blocks of ceil(w/k) x ceil(h/k) texels;
//   block (sx, sy) holds the pixels (x, y) = (local.x k + sx, local.y k + sy), drawn by one draw call whose subset is
//   a uniform. Every fragment of a draw then reads the same VPL in the same iteration: the buffer index is uniform, so
//   the loads are not per-lane gathers (the cost that dominates on llvmpipe), and only N/k^2 VPLs are evaluated.
//   The VPLs come from a uniform buffer, not a storage buffer: llvmpipe reads a UBO faster. A UBO holds at most
//   GATHER_UBO_VPLS VPLs (set by the renderer from GL_MAX_UNIFORM_BLOCK_SIZE), so each draw covers a sub-range of a
//   shadow-map chunk, bound with glBindBufferRange from VPL uUboBase on.
#include "common/units.glsl"
#include "common/brdf.glsl"
#include "common/fullscreen.glsl"
#include "common/interleaved.glsl"
#include "common/visibility.glsl"
#if GATHER_VSL
#include "common/vsl.glsl"
#endif

#include "common/vpl_table.glsl"
#include "common/medium.glsl"
#include "common/phase.glsl"

uniform float uClampBound;

// The VPL's end of a transfer toward x1 along w (unit, from x1 to the VPL). A surface VPL: its cosine, its one-sided
// surface and its BRDF. In a scene with media a medium VPL has none of these (docs/theory.md §17): cosine 1, light toward
// every side, and its phase function, which mediaTransfer() applies with the transmittance between the ends.
#if PREVIEW_MEDIA
bool isMediumVpl(GlVpl vpl) { return vpl.geoNormal.w > 0.5; }
float vplEndCosine(GlVpl vpl, vec3 w) { return isMediumVpl(vpl) ? 1.0 : -dot(vpl.normal.xyz, w); }
bool vplFaces(GlVpl vpl, vec3 w) { return isMediumVpl(vpl) || dot(vpl.geoNormal.xyz, w) < 0.0; }
vec3 vplEndBrdf(GlVpl vpl, BrdfParams p2, vec3 w) {
  return isMediumVpl(vpl) ? vec3(1.0) : evaluateBrdf(p2, vpl.normal.xyz, vpl.incoming.xyz, -w);
}
// Where `needed` is false (the transfer is zero anyway) the transmittance is not marched, and the result is meaningless.
vec3 mediaTransfer(GlVpl vpl, vec3 x1, vec3 w, bool needed) {
  float phase = isMediumVpl(vpl) ? phaseHG(dot(vpl.incoming.xyz, w), vpl.baseColor.w) : 1.0;
  return phase * mediaTransmittance(x1, vpl.position.xyz, needed);
}
#else
float vplEndCosine(GlVpl vpl, vec3 w) { return -dot(vpl.normal.xyz, w); }
bool vplFaces(GlVpl vpl, vec3 w) { return dot(vpl.geoNormal.xyz, w) < 0.0; }
vec3 vplEndBrdf(GlVpl vpl, BrdfParams p2, vec3 w) { return evaluateBrdf(p2, vpl.normal.xyz, vpl.incoming.xyz, -w); }
vec3 mediaTransfer(GlVpl vpl, vec3 x1, vec3 w, bool needed) { return vec3(1.0); }
#endif // b (a large finite value stands for infinity); point-VPL sets only

layout(location = 0) out vec4 outColor;

void main() {
  InterleavedSurface surface;
  if (!interleavedSurface(surface)) {
    outColor = vec4(0.0);
    return;
  }
  ivec2 px = surface.px;
  vec3 x1 = surface.x1, n1 = surface.n1, ng = surface.ng, wo = surface.wo;
  BrdfParams p1 = surface.brdf;
  int k2 = uInterleave * uInterleave;
  // First VPL of this pixel's subset inside the draw's range (common/interleaved.glsl).
  int first = uLightBegin + uSubsetOffset;
  vec3 sum = vec3(0.0);
  float scale = float(k2);  // the subset's VPLs stand for all k^2 subsets
#if GATHER_VSL
  // Virtual spherical lights: one transfer per VPL (common/vsl.glsl), every VPL through the same code.
#ifdef BRDF_LAMBERT_ONLY
  // Pure Lambert at both ends: f(x1) leaves the loop, f(x2) Phi comes precomputed (lambertPower), as below.
  vec3 f1 = dot(n1, wo) > 0.0 ? p1.baseColor * kInvPi : vec3(0.0);
#endif
  for (int i = first; i < uLightEnd; i += k2) {
    GlVpl vpl = vpls[i - uUboBase];
    vec3 x2 = vpl.position.xyz;
    float v = vplVisibility(i - uFirstLight, x2, vpl.geoNormal.xyz, x1, length(x2 - x1), ng);
#ifdef BRDF_LAMBERT_ONLY
    sum += vslLambertCosineTransfer(x1, n1, ng, x2, vpl.normal.xyz, vpl.geoNormal.xyz, vpl.position.w) * v *
           vpl.lambertPower.rgb;
#elif defined(VSL_LAMBERT_VPLS)
    // The draw's VPLs lie on Lambert materials (the renderer puts them first): no lobe at their end, and f(x2) Phi
    // comes precomputed.
    sum += vslLambertVplTransfer(x1, n1, ng, wo, p1, x2, vpl.normal.xyz, vpl.geoNormal.xyz, vpl.position.w) * v *
           vpl.lambertPower.rgb;
#else
    BrdfParams p2 = BrdfParams(vpl.baseColor.rgb, vpl.normal.w, vpl.incoming.w, vpl.flux.w);
    sum += vslApproxTransfer(x1, n1, ng, wo, p1, x2, vpl.normal.xyz, vpl.geoNormal.xyz, vpl.incoming.xyz, p2,
                             vpl.position.w) * v * vpl.flux.rgb;
#endif
  }
#ifdef BRDF_LAMBERT_ONLY
  sum *= f1;
#endif
#elif defined(BRDF_LAMBERT_ONLY)
  // Pure Lambert at both ends: f(x1) = albedo1 / pi and f(x2) = albedo2 / pi do not depend on w, so f(x1) leaves the
  // loop and f(x2) Phi comes precomputed with the VPL (lambertPower), and the body is written without `continue`:
  // llvmpipe pays for every branch in mask bookkeeping, while a zero factor costs one select. Same terms as the
  // general loop below.
  vec3 f1 = dot(n1, wo) > 0.0 ? p1.baseColor * kInvPi : vec3(0.0);
  for (int i = first; i < uLightEnd; i += k2) {
    GlVpl vpl = vpls[i - uUboBase];
    vec3 x2 = vpl.position.xyz;
    vec3 d = x2 - x1;
    float dist2 = dot(d, d);
    float invDist = inversesqrt(max(dist2, 1e-30));
    vec3 w = d * invDist;
    float cos1 = dot(n1, w), cos2 = vplEndCosine(vpl, w);
    // One-sided surfaces at both ends, clamped cosines, G bounded by b (docs/theory.md §4).
    bool contributes = dist2 > 0.0 && dot(ng, w) > 0.0 && vplFaces(vpl, w) && cos1 > 0.0 && cos2 > 0.0;
    float v = vplVisibility(i - uFirstLight, x2, vpl.geoNormal.xyz, x1, dist2 * invDist, ng);
    float gv = contributes ? min(cos1 * cos2 * invDist * invDist, uClampBound) * v : 0.0;
    sum += gv * vpl.lambertPower.rgb * mediaTransfer(vpl, x1, w, gv > 0.0);
  }
  sum *= f1;
#else
  // The same terms at glossy ends, also without branches. A glossy receiver takes every VPL of the draw's range at its
  // own pixel, unscaled: its lobe turns a VPL into a highlight narrower than the k x k window, which its subset's pixel
  // would hold at k^2 times its value (or miss), and the merge would spread over the window at that strength
  // (cornell-glossy at 128^2, b = 20, k = 4: relMSE 7.1 at unit mean, mean +7 %; now 0.75, the merge's blur of the
  // highlights, and 0.9996). The cost: k saves nothing on glossy pixels.
  const bool everyVpl = p1.metallic > 0.0 || p1.specular > 0.0;
  if (everyVpl) scale = 1.0;
  for (int i = everyVpl ? uLightBegin : first; i < uLightEnd; i += everyVpl ? 1 : k2) {
    GlVpl vpl = vpls[i - uUboBase];
    vec3 x2 = vpl.position.xyz;
    BrdfParams p2 = BrdfParams(vpl.baseColor.rgb, vpl.normal.w, vpl.incoming.w, vpl.flux.w);
    vec3 d = x2 - x1;
    float dist2 = dot(d, d);
    float invDist = inversesqrt(max(dist2, 1e-30));
    vec3 w = d * invDist;
    float cos1 = dot(n1, w), cos2 = vplEndCosine(vpl, w);
    bool contributes = dist2 > 0.0 && dot(ng, w) > 0.0 && vplFaces(vpl, w) && cos1 > 0.0 && cos2 > 0.0;
    float v = vplVisibility(i - uFirstLight, x2, vpl.geoNormal.xyz, x1, dist2 * invDist, ng);
    float gv = min(cos1 * cos2 * invDist * invDist, uClampBound) * v;
    // Glossy at both ends: f(x1) from the viewer, f(x2) from the VPL's stored incoming direction.
    sum += contributes ? evaluateBrdf(p1, n1, wo, w) * gv * vplEndBrdf(vpl, p2, w) * vpl.flux.rgb *
                             mediaTransfer(vpl, x1, w, contributes && gv > 0.0)
                       : vec3(0.0);
  }
#endif
  outColor = interleavedOutput(surface, sum * scale);
}
