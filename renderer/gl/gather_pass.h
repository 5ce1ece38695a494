#pragma once
// Pass 4 of the preview (docs/theory.md §4, §7): every pixel sums the VPLs of its interleaving subset with the bounded
// geometry term G_b, or the cone integral of a virtual spherical light, times the visibility the VPL technique answers
// (vpl_visibility.h). The gather is compiled once per technique, with and without the cone integral.

#include <functional>
#include <memory>

#include "renderer/gl/light_table.h"
#include "renderer/gl/media_shader_layout.h"
#include "renderer/gl/screen_pass.h"
#include "renderer/gl/vpl_visibility.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"
#include "renderer/vpl/vpl.h"

namespace vplab {

/// The order the gather takes the VPLs in (also the order of their maps): medium VPLs, then those on Lambert
/// materials, then the rest, each group in the set's order. For VSLs the first two groups are drawn by a variant
/// without the lobe at the VPL's end, the costlier half of the cone integral (common/vsl.glsl, vslLambertVplTransfer).
/// Returns the indices into vpls.vpls; *lambertCount receives how many VPLs the first two groups hold.
std::vector<uint32_t> gatherOrder(const Scene& scene, const VplSet& vpls, int* lambertCount);

// VPLs a gather draw evaluates per pixel at most (per interleaving subset): the unit a frame budget can stop after.
inline constexpr int kGatherVplsPerDraw = 64;

class VplGatherPass {
 public:
  VplGatherPass();

  /// Compiles the gather for `visibility` (its shader define), with the transmittance of the scene's media and medium
  /// VPLs (common/medium.glsl, docs/theory.md §17; a count of 0: none).
  void useVisibility(const VplVisibility& visibility, const MediaShaderLayout& media = {});
  /// The defines the gather was compiled with: the media pass (media_pass.h) reads the same table and maps.
  const std::vector<std::string>& defines() const { return defines_; }
  /// Draws `program` over the uploaded VPLs, interleaved into `raw` as the point-VPL gather is (same table, chunks and
  /// visibility maps; the program's own uniforms are the caller's), as steps of the caller's `slices`.
  void drawTable(ShaderProgram& program, const VplVisibility& visibility, Target& raw, const InterleavedLayout& layout,
                 const GlVertexArray& vao, PassSlices& slices) const;
  /// Uploads the VPLs with their materials, in gatherOrder().
  void upload(const Scene& scene, const VplSet& vpls, const std::vector<uint32_t>& order, int lambertCount);
  /// The next draw() starts from its first draw: what it sums over changed.
  void restart() { slices_.restart(); }
  /// Draws the gather into the interleaved layout of `raw`, reading the G-buffer bound at its units; far and bias as
  /// the VPL maps were built with. With outOfTime, stops after the draw (or band of one) at which it says so and returns
  /// false; the next call goes on from there. The same draws in the same order either way, so the image is the same.
  bool draw(bool lambertOnly, const Camera& camera, const Settings& settings, float far, float bias,
            const VplVisibility& visibility, Target& raw, const InterleavedLayout& layout, const GlVertexArray& vao,
            const std::function<bool()>& outOfTime = {});

 private:
  std::unique_ptr<BrdfVariants> point_, sphere_;
  /// The VSL gather of VPLs on Lambert materials (VSL_LAMBERT_VPLS), compiled when first needed.
  std::unique_ptr<ShaderProgram> sphereLambertVpls_;
  std::vector<std::string> defines_;
  UniformTableLayout tableLayout_;
  GlBuffer table_;
  /// Whether any uploaded VPL is a VSL (radius > 0): selects the variant with the cone integral.
  bool haveRadius_ = false;
  /// How many of the uploaded VPLs lead with a Lambert material.
  int lambertCount_ = 0;
  /// Where a gather that outOfTime cut short goes on.
  PassSlices slices_;
};

}  // namespace vplab
