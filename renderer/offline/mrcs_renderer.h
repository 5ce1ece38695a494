#pragma once
// Matrix row-column sampling (Hasan, Pellacini, Bala 2007; docs/methods.md "Matrix row-column sampling"): the
// bounded VPL sum of Method::Vpl seen as a pixels x VPLs matrix A, A_pj = f(x_p) min(G, b) V f(x2_j) Phi_j.
//   1. Rows: R pixels (Settings::mrcsRows), stratified over the image in raster order, each shaded at the pixel's
//      centre; for each, the luminance of every VPL's term with an exact shadow ray: the reduced column
//      rho_j in R^R of every VPL j.
//   2. Columns: the VPLs are split into K clusters (Settings::mrcsClusters) top-down: the cluster of largest cost
//        cost(C) = sum_{i,j in C} |rho_i| |rho_j| |rho_i / |rho_i| - rho_j / |rho_j||^2 = 2 (W_C^2 - |sum_C rho|^2),
//      W_C = sum_C |rho_j|, is split along a random direction of R^R (a hash of the seed and the split) at the point
//      of least summed cost of the two parts, until K clusters (or every VPL alone). The paper starts with a sampling
//      clustering for the first half of the clusters; here the splitting does all of them.
//   3. Each cluster keeps one representative r, drawn with probability |rho_r| / W_C, whose flux is scaled by
//      W_C / |rho_r|: the reduced VPL set. Every pixel is then rendered by renderVpl with Method::Vpl over it.
// A VPL whose reduced column is zero (it lights none of the rows) has no representative: its light is lost (the
// paper's estimator has the same blind spot; it shows in the energy ratio). With K at least the number of non-zero
// columns every such VPL is its own cluster with weight 1: the exact sum over the VPLs that light a row.
// Same refusals as lightcuts (media, VSLs: requireLightcutsApply's reasons).

#include <cstdint>
#include <vector>

#include "renderer/offline/render_methods.h"

namespace vplab {

/// The reduced VPL set of steps 1-3, with what it cost.
struct MrcsReduction {
  VplSet reduced;                         ///< the representatives, fluxes scaled by W_C / |rho_r|
  std::vector<uint32_t> representatives;  ///< index of each reduced VPL in the input set
  std::size_t rows = 0;                   ///< rows that hit a surface
  std::size_t darkColumns = 0;            ///< VPLs that light no row (left out)
  double rowSeconds = 0.0;
  double clusterSeconds = 0.0;
};

MrcsReduction reduceVplsByRowColumnSampling(const OfflineScene& offline, const VplSet& vpls, const Settings& settings);

struct MrcsRenderResult : VplRenderResult {
  MrcsReduction reduction;
};

/// Renders settings.width x settings.height with MRCS; `seconds` includes the rows and the clustering.
MrcsRenderResult renderMrcs(const OfflineScene& offline, const VplSet& vpls, const Settings& settings,
                            RenderControl* control = nullptr, OnPass onPass = {});

}  // namespace vplab
