#pragma once
// The preview's representative lights (docs/methods.md "The preview at many VPLs"): a VPL set larger than
// Settings::previewRepresentatives is reduced, per view, to a cut of the light tree (light_tree.h) of that many
// nodes, and each node is lit by its representative VPL r with its flux scaled by luminance(I_C) / luminance(I_r).
// The tree draws r with probability luminance(I_r) / luminance(I_C), so the scaled VPL's contribution equals the
// cluster's in expectation over the tree's seed, whatever the cut: the power is preserved, the cut only decides
// where the clusters are small. The existing gather (cube maps or ISM) renders the reduced set unchanged.
//
// The cut for a view: kRepresentativePoints camera-visible points (primary hits through a grid over the image) stand
// for the pixels; starting from the root, the node C of largest
//   sum_p B_p(C) luminance(I_C) / E_p
// is replaced by its children until the cut holds previewRepresentatives nodes, with B_p the lightcut error bound at
// point p (lightcut_bound.h) and E_p p's unshadowed estimate through the first kRepresentativeSeedCut nodes of the
// cut: each node's bound relative to the light at the points it could change, the lightcuts criterion summed over the
// view. The bounds use the importance bound b_imp (vpl_importance.h), not the user's clamp bound: changing b does
// not move a representative, so it keeps the VPL maps. Nodes of equal sums (no point sees them) are refined by
// their luminance(I_C). A representative that stays in the cut keeps its place in the reduced set (a refined node
// hands its representative to one of its children), so that a visibility technique keeps the maps of the places
// whose caster did not move.
// Not reduced: sets of at most previewRepresentatives VPLs, and sets with medium VPLs (no orientation cone to bound).

#include <cstdint>
#include <memory>
#include <vector>

#include "renderer/offline/light_tree.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"
#include "renderer/vpl/vpl.h"

namespace vplab {

/// Camera-visible points a view's cut is chosen for.
inline constexpr int kRepresentativePoints = 256;
/// Nodes of the first cut whose unshadowed estimate normalises each point's bounds.
inline constexpr int kRepresentativeSeedCut = 64;

/// Whether the preview reduces `vpls` under `settings` (see above).
bool previewReducesVpls(const VplSet& vpls, const Settings& settings);

/// What the last selection did.
struct RepresentativeStats {
  std::size_t vpls = 0;             ///< VPLs of the full set
  std::size_t representatives = 0;  ///< lights of the reduced set
  std::size_t points = 0;           ///< camera-visible points the cut was chosen for
  std::size_t moved = 0;            ///< places of the reduced set whose VPL changed with the last selection
  double treeSeconds = 0.0;         ///< the light tree's build (once per VPL set)
  double selectSeconds = 0.0;       ///< the last selection
};

class RepresentativeLights {
 public:
  /// Over `vpls` (kept by reference: it must outlive this). Builds the light tree when the set is reduced.
  RepresentativeLights(const OfflineScene& offline, const VplSet& vpls, const Settings& settings);

  /// The set the preview gathers for `camera` and `settings`: `vpls` itself when it is not reduced, else the reduced
  /// set. The same cut as the last call gives the same VplSet (same id, so the preview does nothing); the same seed,
  /// camera and settings give the same representatives at any thread count.
  const VplSet& select(const Camera& camera, const Settings& settings);
  bool reduces() const { return tree_ != nullptr; }
  const RepresentativeStats& stats() const { return stats_; }
  /// The tree nodes of the last cut, in the reduced set's order.
  const std::vector<uint32_t>& cut() const { return cut_; }

 private:
  const OfflineScene& offline_;
  const VplSet& vpls_;
  std::unique_ptr<LightTree> tree_;
  std::vector<BrdfParams> brdfs_;
  std::vector<uint32_t> cut_;
  VplSet reduced_;
  RepresentativeStats stats_;
};

}  // namespace vplab
