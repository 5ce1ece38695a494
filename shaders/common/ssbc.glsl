// One step of screen-space bias compensation at one pixel (Novak, Engelhardt, Dachsbacher 2011; docs/theory.md §6):
//   T_r(I)(p) = sum over pixels q in the footprint of the sphere of radius 1/sqrt(b) around x1 of
//               f(x1; wo, w) max(G(x1, x2) - b, 0) L_I(x2 -> x1) dA(q),
//   dA(q) = omega_pix(q) |x2 - camera|^2 / |cos theta_q|,  omega_pix = A_pix cos^3(alpha) / f^2  (pinhole, f in px)
// L_I(x2 -> x1) is the image value at q (diffuse assumption: the radiance q sends to the camera). Hierarchical, in
// rings: level 0 covers the pixels within kSsbcRingTexels of p, level l the ring (kSsbcRingTexels 2^(l-1),
// kSsbcRingTexels 2^l] (pixel distances of the texel centres), each level-l texel standing for 4^l pixels, up to the
// level whose ring reaches the footprint radius. The integrand (G - b) falls like 1/d^2 while a ring's area grows like
// d^2, so every octave of distance matters about equally: all of it must be integrated, and finest where the residual
// is largest (next to p, i.e. at creases). Conservative: samples off screen, on the background, or straddling a
// discontinuity (mip-averaged coverage < 1 or averaged normal shorter than 0.9) add nothing; V~ = 1 inside the
// (local) footprint. The factors of a tap that depend on q alone are precomputed per mip texel, so that a tap reads
// two texels: x2 with the x of q's unit normal (uTaps, ssbc_taps.frag.glsl, once per frame) and L_I dA with its y and
// the sign of its z (uTapRadiance, ssbc_radiance.frag.glsl, once per step; 0 where q does not take part), each with
// every mip level copied into one buffer texture (common/ssbc_levels.glsl).
//
// Multi-resolution rings (SSBC_SPLIT, Settings::ssbcCoarseRings): the rings at and above kSsbcFineLevels (texels at
// least kSsbcCoarseSpacing px away) vary on the scale of their own radius along a surface, so they are evaluated only
// at the pixels kSsbcCoarseSpacing t (ssbc.frag.glsl with SSBC_COARSE_PASS) and interpolated bilinearly between
// samples on the same surface; the fine rings, where the residual is largest and steepest, are evaluated at every
// pixel whose fine taps are not all coplanar with it (SSBC_FINE_PASS, ssbc_flat.frag.glsl). A pixel whose
// interpolation would need a sample from another surface evaluates the coarse rings itself.
//
// llvmpipe runs an if under a lane mask and a loop's body at least once for the whole SIMD group; only a failed early
// depth test or a discard ends the shader early (once every lane of the group has failed). The tap is therefore
// branch-free, and work that only some pixels need goes to a pass drawn through a depth mask of those pixels
// (SSBC_FINE_PASS, SSBC_FALLBACK_PASS; ssbc_mask.frag.glsl), which costs far less than discarding the others.
// Needs common/brdf.glsl and common/fullscreen.glsl (the G-buffer samplers) included before it.
#include "common/units.glsl"
#include "common/ssbc_levels.glsl"

// Per mip texel: rgb I dA (I: reflected light only, no emission; 0 where the texel does not take part), w the y of its
// unit normal coded by ssbcNormalYCode.
layout(binding = UNIT_PASS_INPUT0) uniform samplerBuffer uTapRadiance;
// Per mip texel: xyz x2, w the x of its unit normal (ssbc_taps.frag.glsl).
layout(binding = UNIT_PASS_INPUT3) uniform samplerBuffer uTaps;
// The first texel of each level in those buffers.
uniform int uTapLevelBase[kSsbcMaxLevels];
uniform vec3 uCameraPosition;
uniform vec3 uCameraForward;
uniform float uClampBound;
uniform float uFocalPixels;  // (height / 2) / tan(yfov / 2)
uniform int uMaxLevel;

const int kSsbcRingTexels = 2;
// Window offsets of the ring taps for kSsbcRingTexels = 2 (see ssbcLevel0, ssbcLevel1, ssbcRings).
const ivec2 kSsbcLevel0Taps[12] = ivec2[](ivec2(0, -2), ivec2(-1, -1), ivec2(0, -1), ivec2(1, -1), ivec2(-2, 0),
                                          ivec2(-1, 0), ivec2(1, 0), ivec2(2, 0), ivec2(-1, 1), ivec2(0, 1),
                                          ivec2(1, 1), ivec2(0, 2));
// At level l >= 2, with p in the lower half of its texel in x and y (mirrored along an axis where it lies in the upper
// half), the texels of the ring (1, 2] texels around p are among these 16 of the 5 x 5 window: the others lie nearer
// than 1 or beyond 2 texels for every such p.
const ivec2 kSsbcRingTaps[16] = ivec2[](ivec2(-1, -2), ivec2(0, -2), ivec2(1, -2), ivec2(-2, -1), ivec2(-1, -1),
                                        ivec2(0, -1), ivec2(1, -1), ivec2(-2, 0), ivec2(-1, 0), ivec2(1, 0),
                                        ivec2(2, 0), ivec2(-2, 1), ivec2(-1, 1), ivec2(0, 1), ivec2(1, 1),
                                        ivec2(0, 2));
// At level 1 the centre of p's texel is 0.25 texels from p in x and y, so the ring (1, 2] texels holds exactly these
// 10 texels for p at even coordinates (mirrored along an axis where p's coordinate is odd).
const ivec2 kSsbcLevel1Taps[10] = ivec2[](ivec2(-1, -2), ivec2(0, -2), ivec2(-2, -1), ivec2(-1, -1), ivec2(1, -1),
                                          ivec2(-2, 0), ivec2(1, 0), ivec2(-1, 1), ivec2(0, 1), ivec2(1, 1));

// Levels below this (ssbcLevel0, ssbcLevel1) are evaluated at every pixel, the others on the grid of
// kSsbcCoarseSpacing pixels (SSBC_SPLIT).
const int kSsbcFineLevels = 2;
const int kSsbcCoarseSpacing = 1 << kSsbcFineLevels;  // the inner radius (px) of the first coarse ring
// A pixel whose coarse rings cannot be interpolated (SSBC_FALLBACK_PASS) evaluates the levels below this itself and
// extrapolates the ones above (the far rings, >= 8 px away) from the coarse samples on its own surface.
const int kSsbcFallbackExactLevels = kSsbcFineLevels + 2;

struct SsbcReceiver {
  vec3 x1, n1, wo;
  BrdfParams brdf;
  vec2 pc;       // pixel centre
  ivec2 size;    // level-0 size
  int topLevel;  // the level whose ring reaches the footprint radius
};

// False where p has no surface or nothing is clamped.
bool ssbcReceiver(ivec2 px, out SsbcReceiver r) {
  vec4 pos = texelFetch(gPosition, px, 0);
  vec4 nm = texelFetch(gNormal, px, 0), bc = texelFetch(gBaseColor, px, 0), em = texelFetch(gEmission, px, 0);
  r.x1 = pos.xyz;
  r.n1 = nm.xyz;
  r.brdf = BrdfParams(bc.rgb, nm.w, bc.w, em.w);
  r.wo = normalize(uCameraPosition - r.x1);
  r.pc = vec2(px) + 0.5;
  r.size = textureSize(gPosition, 0);
  // Footprint: the residual is non-zero only where |x1 - x2| < 1/sqrt(b) (docs/theory.md §4).
  float radius = inversesqrt(uClampBound);
  float z = max(dot(r.x1 - uCameraPosition, uCameraForward), 1e-4);
  float radiusPx = radius * uFocalPixels / z;
  r.topLevel = clamp(int(ceil(log2(max(radiusPx / float(kSsbcRingTexels), 1.0)))), 0, uMaxLevel);
  return pos.w > 0.0 && !isinf(uClampBound);
}

// A unit normal is stored as its x and this code of its y and the sign of its z, so that a tap decodes it with one
// square root (ssbcNormal): an octahedral code in one float took a quarter of the tap's cost.
float ssbcNormalYCode(vec3 n) {
  return n.z < 0.0 ? n.y + 4.0 : n.y;
}

// The unit normal of x and ssbcNormalYCode's code, its z from the unit length.
vec3 ssbcNormal(float x, float yCode) {
  bool below = yCode > 2.0;
  float y = below ? yCode - 4.0 : yCode;
  float z = sqrt(max(1.0 - x * x - y * y, 0.0));
  return vec3(x, y, below ? -z : z);
}

// One tap at texel q of a level of levelSize texels whose first is levelBase (uTapLevelBase); `use` false (outside
// the ring) or q off the level adds nothing.
vec3 ssbcTap(SsbcReceiver r, ivec2 q, int levelBase, ivec2 levelSize, bool use) {
  ivec2 qc = clamp(q, ivec2(0), levelSize - 1);
  int texel = ssbcTexel(levelBase, qc, levelSize);
  vec4 tap = texelFetch(uTaps, texel), radiance = texelFetch(uTapRadiance, texel);
  vec3 x2 = tap.xyz, n2 = ssbcNormal(tap.w, radiance.w), radianceArea = radiance.rgb;
  vec3 d = x2 - r.x1;
  float dist2 = dot(d, d);
  vec3 w = d * inversesqrt(max(dist2, 1e-12));
  float cos1 = max(dot(r.n1, w), 0.0), cos2 = max(-dot(n2, w), 0.0);
  // G <= 1 / d^2: beyond the footprint sphere max(G - b, 0) is 0 whatever the normals (docs/theory.md §4).
  float excess = max(cos1 * cos2 / max(dist2, 1e-12) - uClampBound, 0.0);
  // A texel that does not take part has I dA = 0.
  bool take = use && all(equal(q, qc)) && dist2 > 1e-12;
#ifdef BRDF_LAMBERT_ONLY
  // Pure Lambert: f(x1) does not depend on w and is applied once per sum (ssbcReflected).
  return take ? excess * radianceArea : vec3(0.0);
#else
  return take ? evaluateBrdf(r.brdf, r.n1, r.wo, w) * excess * radianceArea : vec3(0.0);
#endif
}

// A sum of ssbcTap values as reflected radiance: times f(x1) where the taps left it out (pure Lambert).
vec3 ssbcReflected(SsbcReceiver r, vec3 sum) {
#ifdef BRDF_LAMBERT_ONLY
  return dot(r.n1, r.wo) > 0.0 ? r.brdf.baseColor * kInvPi * sum : vec3(0.0);
#else
  return sum;
#endif
}

// Level 0: the 12 pixels with 0 < |q - p| <= 2 (p itself has x2 = x1 and adds nothing); all of them lie in the ring.
vec3 ssbcLevel0(SsbcReceiver r, ivec2 px) {
  vec3 sum = vec3(0.0);
  // Level 0 starts the buffers (uTapLevelBase[0] = 0).
  for (int tap = 0; tap < 12; ++tap) sum += ssbcTap(r, px + kSsbcLevel0Taps[tap], 0, r.size, true);
  return ssbcReflected(r, sum);
}

// Level 1 (if the footprint reaches it): the 10 texels of its ring, no per-tap ring test.
vec3 ssbcLevel1(SsbcReceiver r, ivec2 px) {
  ivec2 base = px >> 1;
  ivec2 mirror = 1 - 2 * (px & 1);
  ivec2 levelSize = max(r.size >> 1, ivec2(1));
  bool use = r.topLevel >= 1;
  vec3 sum = vec3(0.0);
  int levelBase = uTapLevelBase[1];
  for (int tap = 0; tap < 10; ++tap)
    sum += ssbcTap(r, base + kSsbcLevel1Taps[tap] * mirror, levelBase, levelSize, use);
  return ssbcReflected(r, sum);
}

// Levels first..last (>= 2) of the rings. Only window texels that can lie in the ring are visited (llvmpipe
// evaluates a skipped tap at full cost): the 16 of kSsbcRingTaps, mirrored to the half of its texel that p lies in.
vec3 ssbcRings(SsbcReceiver r, ivec2 px, int first, int last) {
  vec3 sum = vec3(0.0);
  for (int level = first; level <= last; ++level) {
    float scale = float(1 << level);
    float inner = float(kSsbcRingTexels) * scale * 0.5, outer = float(kSsbcRingTexels) * scale;
    ivec2 base = px >> level;
    ivec2 mirror = 1 - 2 * ((px >> (level - 1)) & 1);
    ivec2 levelSize = max(r.size >> level, ivec2(1));
    int levelBase = uTapLevelBase[level];
    // Texel centre of `base` relative to p, in pixels.
    vec2 centre = (vec2(base) + 0.5) * scale - r.pc;
    for (int tap = 0; tap < 16; ++tap) {
      ivec2 offset = kSsbcRingTaps[tap] * mirror;
      vec2 rel = vec2(offset) * scale + centre;
      float r2 = dot(rel, rel);
      sum += ssbcTap(r, base + offset, levelBase, levelSize, r2 > inner * inner && r2 <= outer * outer);
    }
  }
  return ssbcReflected(r, sum);
}

// The whole footprint at p.
vec3 ssbcFullAt(ivec2 px) {
  SsbcReceiver r;
  if (!ssbcReceiver(px, r)) return vec3(0.0);
  return ssbcLevel0(r, px) + ssbcLevel1(r, px) + ssbcRings(r, px, 2, r.topLevel);
}

#ifdef SSBC_SPLIT
layout(binding = UNIT_G_MERGE_KEY) uniform sampler2D gMergeKey;  // xyz shading normal, w distance to the camera (0: background)
layout(binding = UNIT_PASS_INPUT4) uniform sampler2D uCoarse;    // the coarse rings at the pixels kSsbcCoarseSpacing t
layout(binding = UNIT_PASS_INPUT6) uniform sampler2D uCoarseFar; // its far rings (levels >= kSsbcFallbackExactLevels) alone

// Whether the coarse sample at pixel q lies on the surface whose merge key is `key` (relative depth and normal tests,
// as in deinterleave.frag.glsl); false off screen (size: the level-0 size).
bool ssbcSampleOnSurface(vec4 key, ivec2 q, ivec2 size) {
  vec4 qk = texelFetch(gMergeKey, min(q, size - 1), 0);
  return all(lessThan(q, size)) && qk.w > 0.0 && abs(qk.w - key.w) <= 0.02 * key.w && dot(qk.xyz, key.xyz) >= 0.95;
}

// The coarse rings at p, interpolated bilinearly from the coarse grid. False (and coarse incomplete) where a sample
// with non-zero weight is off screen or on another surface (relative depth and normal tests, as in
// deinterleave.frag.glsl): such pixels evaluate the coarse rings themselves (ssbcRings), because renormalising over
// the remaining samples extrapolates the residual toward creases, where it is steepest (Cornell box: 44-50% of the
// clamped energy recovered instead of 52%, furnace over-compensated).
bool ssbcCoarseInterpolated(SsbcReceiver r, ivec2 px, out vec3 coarse) {
  vec4 key = texelFetch(gMergeKey, px, 0);
  ivec2 base = px / kSsbcCoarseSpacing;
  vec2 f = vec2(px - base * kSsbcCoarseSpacing) / float(kSsbcCoarseSpacing);
  ivec2 coarseSize = textureSize(uCoarse, 0);
  coarse = vec3(0.0);
  bool complete = true;
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i <= 1; ++i) {
      float wb = (i == 0 ? 1.0 - f.x : f.x) * (j == 0 ? 1.0 - f.y : f.y);
      ivec2 t = base + ivec2(i, j);
      bool ok = ssbcSampleOnSurface(key, t * kSsbcCoarseSpacing, r.size);
      complete = complete && (ok || wb <= 0.0);
      coarse += ok ? wb * texelFetch(uCoarse, min(t, coarseSize - 1), 0).rgb : vec3(0.0);
    }
  return complete;
}

// A coarse-grid quantity at p (coarseSamples: one texel per pixel kSsbcCoarseSpacing t), bilinear over the samples on
// p's surface, renormalised (each such sample weighted at least 1/64, so that a pixel between samples of which only
// zero-weight ones lie on its surface still gets them); 0 where none of the four does. Used for the far rings at a
// pixel whose interpolation is incomplete, and for the coarse rings of the second step at such a pixel.
vec3 ssbcFromCoarseSamples(sampler2D coarseSamples, SsbcReceiver r, ivec2 px) {
  vec4 key = texelFetch(gMergeKey, px, 0);
  ivec2 base = px >> kSsbcFineLevels;
  vec2 f = vec2(px - (base << kSsbcFineLevels)) * (1.0 / float(kSsbcCoarseSpacing));
  ivec2 coarseSize = textureSize(coarseSamples, 0);
  vec3 sum = vec3(0.0);
  float weight = 0.0;
  for (int j = 0; j <= 1; ++j)
    for (int i = 0; i <= 1; ++i) {
      float wb = max((i == 0 ? 1.0 - f.x : f.x) * (j == 0 ? 1.0 - f.y : f.y), 1.0 / 64.0);
      ivec2 t = base + ivec2(i, j);
      bool ok = ssbcSampleOnSurface(key, t << kSsbcFineLevels, r.size);
      sum += ok ? wb * texelFetch(coarseSamples, min(t, coarseSize - 1), 0).rgb : vec3(0.0);
      weight += ok ? wb : 0.0;
    }
  return weight > 0.0 ? sum / weight : vec3(0.0);
}

#endif
