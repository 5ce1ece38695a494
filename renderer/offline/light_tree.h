#pragma once
// The light tree of lightcuts (Walter et al. 2005, docs/methods.md "Lightcuts"): a binary tree whose leaves are the
// surface VPLs of a VplSet and whose inner nodes are clusters that one representative VPL stands for.
//
// Per VPL i an intensity I_i = Phi_i * fmax_i (RGB), fmax_i >= f(x2_i; w_in, w) for every outgoing w (vplIntensity):
// the VPL's flux through the largest value its own BRDF takes, so that f(x2_i; w_in, w) Phi_i = s_i(w) I_i with
// 0 <= s_i <= 1 per channel. A node holds
//   - the sum of its VPLs' intensities I_C,
//   - the bounding box of their positions,
//   - an orientation cone (axis, half-angle) holding every VPL's shading normal,
//   - a representative VPL, chosen among its two children's with probability proportional to their intensities'
//     luminance (Walter et al. 2005 §4.1), by a hash of the seed and the node's place, so the same seed gives the
//     same tree.
// Built top-down in O(N log N): each node splits its VPLs in two along the widest of six dimensions (the positions
// and the normals scaled by half the root's diagonal, so that orientation splits count like spatial ones, the
// cluster size metric of Walter et al. 2005 §4.1), at the best of 16 bins by the cost sum over both sides of
// I * (box diagonal^2 + (diagonal / 2)^2 normal-box diagonal^2); from depth 48 on at the median, which bounds the depth
// by 48 + log2 N. Nodes are stored depth first: a node's first child follows it, its second child is stored by index;
// a tree of N VPLs has 2N - 1 nodes of 64 bytes.

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "renderer/core/brdf.h"
#include "renderer/vpl/vpl.h"

namespace vplab {

/// One node of the light tree: 64 bytes.
struct LightTreeNode {
  glm::vec3 boundsMin{0.0f};  ///< box of the VPL positions, world space
  glm::vec3 boundsMax{0.0f};
  glm::vec3 coneAxis{0.0f, 0.0f, 1.0f};  ///< unit axis of the orientation cone of the VPLs' shading normals
  float coneCos = 1.0f;                  ///< cosine of the cone's half-angle; -1 = every direction
  glm::vec3 intensity{0.0f};             ///< I_C = sum of the VPLs' intensities (vplIntensity)
  uint32_t representative = 0;           ///< index into the VplSet's VPLs
  uint32_t secondChild = 0;              ///< index of the second child; 0 for a leaf (the first child is this + 1)
  uint32_t count = 0;                    ///< VPLs below this node
  bool leaf() const { return count == 1; }
};
static_assert(sizeof(LightTreeNode) == 64, "the documented node size");

/// fmax of a VPL's BRDF (see above), per channel: baseColor / pi for pure Lambert (exact); otherwise the diffuse lobe
/// plus D_max F_max V_max with D_max = 1 / (pi alpha^2), F_max = (1 - metallic) specular + metallic and the Smith
/// visibility V <= 1 / (2 alpha cos_in) (docs/methods.md "Lightcuts"). 0 when the stored incoming direction lies
/// below the VPL's shading normal (its BRDF is 0 everywhere).
glm::vec3 vplBrdfMax(const BrdfParams& brdf, const glm::vec3& normal, const glm::vec3& incoming);

class LightTree {
 public:
  /// Builds the tree over `vpls` (brdfs[i]: f(x2) parameters of VPL i). Throws std::invalid_argument for a medium
  /// VPL (no orientation cone) or more than 2^31 VPLs. `threads`: build threads (the top levels split in parallel;
  /// the tree does not depend on it).
  LightTree(const std::vector<Vpl>& vpls, const std::vector<BrdfParams>& brdfs, uint32_t seed, int threads);

  const std::vector<LightTreeNode>& nodes() const { return nodes_; }
  /// I_i of each VPL, in VplSet order.
  const std::vector<glm::vec3>& intensities() const { return intensities_; }
  double buildSeconds() const { return buildSeconds_; }
  bool empty() const { return nodes_.empty(); }

 private:
  std::vector<LightTreeNode> nodes_;
  std::vector<glm::vec3> intensities_;
  double buildSeconds_ = 0.0;
};

}  // namespace vplab
