// One step of screen-space bias compensation at one pixel (Novak, Engelhardt, Dachsbacher 2011; MANYLIGHTS 6):
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
// (local) footprint. The factors of a tap that depend on q alone (unit normal, dA, whether it takes part) are
// precomputed per mip texel (uTaps, ssbc_taps.frag.glsl).
// Needs common/brdf.glsl and common/fullscreen.glsl (the G-buffer samplers) included before it.

layout(binding = 6) uniform sampler2D uInput;  // I (reflected light only, no emission), with mips
layout(binding = 9) uniform sampler2D uTaps;   // per mip texel: unit normal, dA (0: not used) (ssbc_taps.frag.glsl)
uniform vec3 uCameraPosition;
uniform vec3 uCameraForward;
uniform float uClampBound;
uniform float uFocalPixels;  // (height / 2) / tan(yfov / 2)
uniform int uMaxLevel;

const int kSsbcRingTexels = 2;
// Window offsets of the ring taps for kSsbcRingTexels = 2 (see ssbcAt).
const ivec2 kSsbcLevel0Taps[12] = ivec2[](ivec2(0, -2), ivec2(-1, -1), ivec2(0, -1), ivec2(1, -1), ivec2(-2, 0),
                                          ivec2(-1, 0), ivec2(1, 0), ivec2(2, 0), ivec2(-1, 1), ivec2(0, 1),
                                          ivec2(1, 1), ivec2(0, 2));
const ivec2 kSsbcRingTaps[20] = ivec2[](ivec2(-1, -2), ivec2(0, -2), ivec2(1, -2), ivec2(-2, -1), ivec2(-1, -1),
                                        ivec2(0, -1), ivec2(1, -1), ivec2(2, -1), ivec2(-2, 0), ivec2(-1, 0),
                                        ivec2(1, 0), ivec2(2, 0), ivec2(-2, 1), ivec2(-1, 1), ivec2(0, 1),
                                        ivec2(1, 1), ivec2(2, 1), ivec2(-1, 2), ivec2(0, 2), ivec2(1, 2));

vec3 ssbcAt(ivec2 px) {
  vec4 pos = texelFetch(gPosition, px, 0);
  if (pos.w <= 0.0 || isinf(uClampBound)) return vec3(0.0);
  vec4 nm = texelFetch(gNormal, px, 0), bc = texelFetch(gBaseColor, px, 0), em = texelFetch(gEmission, px, 0);
  vec3 x1 = pos.xyz, n1 = nm.xyz;
  BrdfParams p1 = BrdfParams(bc.rgb, nm.w, bc.w, em.w);
  vec3 wo = normalize(uCameraPosition - x1);
  // Footprint: the residual is non-zero only where |x1 - x2| < 1/sqrt(b) (MANYLIGHTS 4).
  float radius = inversesqrt(uClampBound);
  float z = max(dot(x1 - uCameraPosition, uCameraForward), 1e-4);
  float radiusPx = radius * uFocalPixels / z;
  int topLevel = clamp(int(ceil(log2(max(radiusPx / float(kSsbcRingTexels), 1.0)))), 0, uMaxLevel);
  vec2 pc = vec2(px) + 0.5;
  vec3 sum = vec3(0.0);
  for (int level = 0; level <= topLevel; ++level) {
    float scale = float(1 << level);
    float inner = level == 0 ? -1.0 : float(kSsbcRingTexels) * scale * 0.5;
    float outer = float(kSsbcRingTexels) * scale;
    ivec2 base = ivec2(floor(pc / scale));
    ivec2 levelSize = textureSize(gPosition, level);
    // Only window texels that can lie in the ring are visited (llvmpipe evaluates a skipped tap under a lane mask
    // at full cost): at level 0 the 12 pixels with 0 < |q - p| <= 2 (p itself has x2 = x1 and adds nothing); above,
    // the 5 x 5 window without its corners (>= 1.5 sqrt 2 texels away) and its centre (<= 0.5 sqrt 2 texels away).
    int tapCount = level == 0 ? 12 : 20;
    for (int tap = 0; tap < tapCount; ++tap) {
      ivec2 q = base + (level == 0 ? kSsbcLevel0Taps[tap] : kSsbcRingTaps[tap]);
      if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, levelSize))) continue;
      vec2 qc = (vec2(q) + 0.5) * scale;
      float r = length(qc - pc);
      if (r <= inner || r > outer) continue;
      vec4 tapData = texelFetch(uTaps, q, level);
      float area = tapData.w;
      if (area <= 0.0) continue;
      vec3 x2 = texelFetch(gPosition, q, level).xyz;
      vec3 d = x2 - x1;
      float dist2 = dot(d, d);
      // G <= 1 / d^2: beyond the footprint sphere max(G - b, 0) is 0 whatever the normals (MANYLIGHTS 4).
      if (!(dist2 > 1e-12) || dist2 * uClampBound >= 1.0) continue;
      vec3 w = d * inversesqrt(dist2);
      float cos1 = dot(n1, w), cos2 = -dot(tapData.xyz, w);
      if (cos1 <= 0.0 || cos2 <= 0.0) continue;
      float g = cos1 * cos2 / dist2;
      if (g <= uClampBound) continue;
      vec3 radiance = texelFetch(uInput, q, level).rgb;
      sum += evaluateBrdf(p1, n1, wo, w) * (g - uClampBound) * radiance * area;
    }
  }
  return sum;
}
