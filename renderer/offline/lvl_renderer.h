#pragma once
// Local virtual lights (Davidovic, Krivanek, Hasan, Slusallek, Bala 2010, "Combining global and local virtual lights
// for detailed glossy illumination"; docs/theory.md §21), Embree pass.
//
// The transport splits at the bound b (docs/theory.md §4): T = T_b + T_r. The global (bounded) part is the VPL
// render's: every pixel sample sums the VPLs with G_b = min(G, b). The residual T_r, which acts only where
// G > b (|x - y| < 1/sqrt(b)), is Kollig & Keller's compensation (§5) with its vertices shared by the pixels of a tile:
//
//   1. Tiles of lvlTileSize^2 pixels; per camera sample, the pixels' first hits x_m (each pixel's own random stream,
//      so the global part is the VPL render's sample for sample). A tile is split into groups: pixels with the same
//      material and shading normals within about 25 degrees of the group's first pixel (row-major, deterministic).
//   2. Each group G of M pixels gets K_G = max(1, round(lvlLightsPerTile M / M_tile)) local lights. Local light k
//      picks a pixel m_k stratified over the group (k + u) M / K_G, samples w from f(x_m) cos (Interaction::sample)
//      and traces to its first hit y_k.
//   3. Every pixel x of the group sees y_k through one shadow ray. The density of y_k is the group's mixture
//        p_G(y) = 1/M sum_m p_brdf(x_m -> y) |cos theta_y| / |x_m - y|^2 V(x_m, y)   (area measure at y),
//      and the estimate at pixel x is the balance heuristic over the group's pixels (Veach 1997):
//        R(x) = 1/K_G sum_k f(x; wo, w_k) cos_x (1 - b / G(x, y_k))+ |cos theta_y| / d^2 V(x, y_k) L_r(y_k -> x) /
//        p_G(y_k)
//      with the stratified picks averaging to the uniform mixture. M = 1 is exactly Kollig-Keller's estimate
//      f (1 - b/G) cos_x L_r / p_brdf, drawn from the same random numbers.
//   4. L_r(y -> x) = direct light at y + the bounded VPL gather at y + Kollig-Keller's compensation at y (the
//      residual's next bounces, up to Settings::maxDepth), never Le(y). It is computed once per local light that
//      some pixel needs (G > b, visible), toward the generating pixel (or the first pixel that needs it):
//      - y pure Lambert: the estimate does not depend on the outgoing direction, so every pixel uses it as it is.
//      - y glossy and other pixels need it: every sample of light arriving at y is kept (IncidentSample: the two
//        direct-light samples, the visible VPLs' G_b f(x2) Phi, the compensation's sampled direction) and re-evaluated
//        toward each pixel x as sum f(y; x - y, wi) weight. Nothing is approximated: the MIS weights and the
//        compensation's direction keep the pdfs of the evaluating direction, which cover f toward x, so the estimate
//        stays unbiased, at more variance where x's reflected lobe at y differs from the evaluating one. To bound
//        the cost, the VPL samples are resampled to kGlossyIncidentSamples for the other pixels (systematic
//        resampling in proportion to their weight's channel sum, unbiased); the evaluating pixel sums them all.
//
// b = inf leaves no residual: the image is the VPL render's, bit for bit. Random numbers: each pixel's stream for its
// camera sample, its local lights and their L_r; a stream per (seed, tile, sample) for the stratified picks; tiles
// do not depend on the thread count. Scenes with participating media are refused (SceneError): the residual in
// media is vpl-kk's and vpl-abc's.

#include <functional>

#include "renderer/core/parallel.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/offline/vpl_renderer.h"
#include "renderer/settings.h"
#include "renderer/vpl/vpl.h"

namespace vplab {

/// Renders settings.width x settings.height with bounded global VPLs plus local virtual lights (see above).
/// clampEnergyRemoved reports the bound's share of the global gather, as for vpl-kk.
VplRenderResult renderLvl(const OfflineScene& offline, const VplSet& vpls, const Settings& settings,
                          RenderControl* control = nullptr,
                          std::function<void(const Image& mean, int samplesSoFar)> onPass = {});

}  // namespace vplab
