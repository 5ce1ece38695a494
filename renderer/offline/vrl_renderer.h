#pragma once
// Virtual ray lights (Novak, Nowrouzezahrai, Dachsbacher, Jarosz 2012a; docs/theory.md §19) and progressive virtual
// beam lights (Novak et al. 2012b; §20) on the CPU, with exact shadow rays.
//
// Per camera sample through a jittered pixel position (camera ray o + t d, first hit x at distance s):
//   L = [media part of the ray] + T(o, s) [surface part at x]
// Media part (the ray's media intervals, docs/theory.md §16-§17):
//   - single scattering: one forced free flight t, T(t) sigma_s / pdf times estimateDirectLight at the medium point;
//   - every SURFACE VPL: one distance equiangular around it (Kulla & Fajardo 2012), the transfer of §17;
//   - every VRL (flux Phi, medium m, span [t0, t1) along start + v e), Settings::vrlSamples samples of
//       Phi int_u int_v sigma_s(u) sigma_s(v) f_p(theta_u) f_p(theta_v) V T(o, u) T(u, v) T(start, v) / |x_u - x_v|^2
//     v from the two-line pdf p(v) ~ 1 / sqrt(h^2 + (v - v_c)^2 sin^2 theta) (h the lines' distance, theta their
//     angle, v_c the VRL point closest to the camera line; inverted with asinh/sinh), uniform in [t0, t1) for nearly
//     parallel lines (sin theta < 1e-4); then u equiangular around x_v over the ray's media span. Weight
//     1 / (p(v) p(u)). This is the paper's ISOTROPIC sampling: for anisotropic media (g != 0) the phase functions are
//     evaluated exactly in the weight but not importance sampled (the paper's anisotropic piecewise approximation in
//     the equiangular domain is not implemented), so strongly forward media (|g| near 1) are noisier, not biased.
// Surface part at x (one-sided surfaces):
//   Le(x) + estimateDirectLight(x) + sum over SURFACE VPLs of the exact transfer (no clamp) with V and transmittance
//   + every VRL, Settings::vrlSamples samples of
//       Phi int_v sigma_s(v) f_p(theta_v) T(start, v) T(v, x) V f_r(x) cos_x / |x - x_v|^2 dv,  v equiangular around x.
// Medium VPLs are skipped: each is a one-sample estimate of its segment's VRL, which replaces it. One shadow ray per
// VRL sample (batched), its media transmittance from EmbreeScene::transmittance. No clamping: the VRL singularities
// (1/h ray-to-point, log(1/h) and 1/sin theta ray-to-ray) are integrable; clampEnergyRemoved is 0.
// In a scene without media and with no VRLs the image is bit-identical to renderVpl(Method::Vpl, clampBound = inf)
// with the same VPLs (the same random numbers, the same sums).
//
// Virtual beam lights (Method::Vbl): pass i = 0 .. beamPasses-1 generates a fresh VplSet with seed settings.seed + i
// and renders the estimator above with every VRL thickened to a beam of radius
//   r_i = r_1 (i + 1)^((alpha - 1) / 2),  alpha = Settings::beamShrink, r_1 = Settings::beamRadius or, when 0, 2 % of
//   the scene diagonal
// (the progressive photon beams schedule, docs/theory.md §20). Kernel: the beam's light is spread UNIFORMLY over the
// disc of radius r_i perpendicular to it (the 2-D kernel 1 / (pi r^2)): each VRL sample draws v as above, then a point
// x_v' = x_v + offset uniform in that disc, and the transmittance along the beam (from start + offset), to the
// receiver, the visibility and the distances are evaluated from x_v' (sigma_s and g of the beam's medium). This is
// not the photon-beam Epanechnikov-type kernel of §20; as r_i -> 0 it converges to the VRL estimate (consistent, the
// bias shrinks with r_i). The image is the running mean of the passes (each pass weighted by its samples).

#include "renderer/core/parallel.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/settings.h"
#include "renderer/vpl/vpl.h"

#include <functional>

namespace vplab {

/// Renders settings.width x settings.height by virtual ray lights (the VPLs and VRLs of `vpls`). Progressive over
/// settings.samplesPerPixel, multithreaded, cancellable through control.
VplRenderResult renderVrl(const OfflineScene& offline, const VplSet& vpls, const Settings& settings,
                          RenderControl* control = nullptr,
                          std::function<void(const Image& mean, int samplesSoFar)> onPass = {});

/// Progressive virtual beam lights: settings.beamPasses passes, each with its own VplSet (seed settings.seed + i) and
/// settings.samplesPerPixel samples per pixel, beams of shrinking radius. onPass gets the running mean after every
/// pass; control->onProgress the overall fraction.
VplRenderResult renderVbl(const OfflineScene& offline, const Settings& settings, RenderControl* control = nullptr,
                          std::function<void(const Image& mean, int samplesSoFar)> onPass = {});

/// The beam radius of pass i (0-based) of renderVbl: r_1 (i + 1)^((beamShrink - 1) / 2).
float beamRadiusForPass(const Settings& settings, float sceneDiagonal, int pass);

}  // namespace vplab
