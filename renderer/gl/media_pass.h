#pragma once
// The preview's participating media (docs/theory.md §16-§18, docs/methods.md "Participating media"): what the media
// do to the image besides the transmittance the surface passes apply themselves (the direct pass toward each light,
// the gather toward each VPL, both through common/medium.glsl):
//   - single scattering of the lights along camera rays (preview/media_lights.frag.glsl), with the direct pass's
//     lights and shadow maps;
//   - in-scattering of the VPLs, surface and medium ones, along camera rays (preview/media_vpls.frag.glsl), with the
//     gather's table, its visibility technique and the bound b;
// both interleaved like the surface passes, on the indirect light's grid, and merged (media_merge.frag.glsl); then
// the composition through the media (media_compose.frag.glsl): T(camera, surface) times the surfaces' image plus the
// scattered light.
// A medium with a density grid (smoke, docs/theory.md §22) has it uploaded as a 3D texture of its own, or as a NanoVDB
// grid in a storage buffer where no 3D texture holds it (density_grids_gpu.h); the shaders compiled with
// PREVIEW_MEDIA_GRIDS (media_shader_layout.h) integrate each grid's optical depth by ray marching and scale sigma_s by
// its density where they scatter (common/medium.glsl).

#include <memory>
#include <string>
#include <vector>

#include "renderer/gl/density_grids_gpu.h"
#include "renderer/gl/direct_pass.h"
#include "renderer/gl/gather_pass.h"
#include "renderer/gl/media_shader_layout.h"
#include "renderer/gl/resources.h"
#include "renderer/gl/screen_pass.h"
#include "renderer/gl/shader.h"
#include "renderer/gl/texture_units.h"
#include "renderer/gl/vpl_visibility.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"

namespace vplab {

/// The most media one scene may hold in the preview (MEDIA_MAX of common/medium.glsl).
inline constexpr int kPreviewMaxMedia = 8;
/// The most media with a density grid one scene may hold in the preview (MEDIA_GRID_MAX of common/medium.glsl): each
/// grid takes a texture unit (TextureUnit::MediaDensity + g) and a row of the media table, its medium is a shader
/// define (PREVIEW_MEDIA_GRID_MEDIA), and every transmittance marches each grid its segment crosses, the lights'
/// scattering once per light and grid along a camera ray (preview/media_lights.frag.glsl).
inline constexpr int kPreviewMaxDensityGrids = 4;
static_assert(unit(TextureUnit::MediaDensity) + kPreviewMaxDensityGrids <= unit(TextureUnit::GSurface),
              "the density grids' texture units must end before the next unit in use");
/// Distances per light and pixel along a camera ray for the lights' single scattering (an area light's samples share
/// them: areaLightSteps): with equiangular sampling and the k x k merge, 4 keep the shafts of the bundled fog scenes
/// within 2 % of the CPU's (tests/gl_media_test.cpp).
inline constexpr int kMediaLightSteps = 4;

/// Distances per area-light sample and pixel in the lights' single scattering: kMediaLightSteps spread over the
/// `areaSamples / subsets` samples a pixel of the k^2 = `subsets` interleaving subsets takes, at least one each.
int areaLightSteps(int areaSamples, int subsets);

/// One sentence when the scene holds more media, or more media with a density grid, than the preview draws, else
/// empty.
std::string mediaFitProblem(const Scene& scene);

/// The approximate bias compensation in a medium (Engelhardt et al. 2012, docs/theory.md §18), "GPU friendly": the
/// bound b removes from a medium point x the transfer from the ball |y - x| < r = 1/sqrt(b), where G = 1/d^2 > b, the
/// part (1 - b/G) of it. Taking the medium homogeneous and unbounded over the ball (as the CPU's vpl-abc does: no
/// surfaces, no visibility inside it) and the bounded radiance leaving the points y toward x equal to the one leaving
/// x itself (the local smoothness the method rests on), the residual is that radiance times, per channel,
///   C = sigma_s integral over [0, r] of e^(-sigma_t t) (1 - b t^2) dt       (the phase function integrates to 1),
/// in closed form; so the compensation along a camera ray is C times the light the medium scatters into it under the
/// bound (the lights' and the VPLs'), with no pass of its own. 0 without a bound.
/// `density` multiplies the medium's coefficients (a grid's are per unit density): 1 for a homogeneous medium. For a
/// grid the CPU's vpl-abc takes the medium locally homogeneous at each scattering point (Engelhardt et al. 2012);
/// the preview applies one factor to a whole camera ray's scattered light, so it takes the grid homogeneous with
/// densityScale times scatteringWeightedDensity(): an approximation, exact only where the density is uniform.
glm::vec3 approximateCompensationFactor(const Medium& medium, float clampBound, float density = 1.0f);
/// The density a grid's scattering events see on average: sum d^2 / sum d over its voxels, the mean of the density
/// weighted by itself (light scatters in proportion to the density, in an optically thin, evenly lit medium).
float scatteringWeightedDensity(const DensityGrid& grid);

class MediaPass {
 public:
  MediaPass();

  /// Uploads the scene's media (at most kPreviewMaxMedia, mediaFitProblem()) with their compensation factors for the
  /// bound b; active() tells whether it has any that absorb or scatter.
  /// Each grid medium's density is uploaded, as densityGridStorage() picks for this context (`gridInBuffer`:
  /// Settings::previewGridInBuffer), when its grid or its storage is not one already uploaded: a change of one grid
  /// uploads that grid only, a change of its densityScale none (the scale is in the table). Throws
  /// std::runtime_error when the NanoVDB grids exceed the context's largest storage block.
  void upload(const Scene& scene, float clampBound, bool gridInBuffer);
  /// The bound the last upload() computed the compensation factors for.
  float uploadedBound() const { return uploadedBound_; }
  bool active() const { return layout_.count > 0; }
  /// What the passes that read the media are compiled for (the direct pass and the gather too).
  const MediaShaderLayout& layout() const { return layout_; }
  /// Per grid medium, its name, where its density is and what it takes, e.g. "smoke: 3D texture, 34x50x34 voxels,
  /// 0.22 MiB"; empty without a grid.
  std::vector<std::string> gridSummary() const;
  /// The grids as uploaded (a test's view of what an upload re-uploads).
  const DensityGridsGpu& grids() const { return grids_; }
  /// Binds the media's table, and the grids' textures or buffer, for every pass compiled with PREVIEW_MEDIA.
  void bind() const;
  /// Compiles the VPLs' in-scattering for the gather's table, visibility technique and media
  /// (VplGatherPass::defines()).
  void useGatherDefines(const std::vector<std::string>& gatherDefines);

  struct Frame {
    bool lambertOnly;
    const Camera& camera;
    glm::mat4 invViewProj;
    glm::vec3 sceneCentre;
    float sceneDiagonal, sceneRadius, far, bias;
  };
  /// Draws the scattering passes asked for on the grid whose G-buffer is bound (layout: its size and k) and merges
  /// them with the other's last result: the lights' does not depend on the VPLs, so a new VPL set redoes the VPLs'
  /// only. With outOfTime, stops after the draw (or band of one) at which it says so and returns false; the next call
  /// goes on from there with the same `lights` and `vpls`, and the result is the same as one call's.
  bool draw(const Frame& frame, const Settings& settings, const InterleavedLayout& layout,
            const DirectLightPass& direct, const VplGatherPass& gather, const VplVisibility& visibility,
            const GlVertexArray& vao, bool lights, bool vpls, const std::function<bool()>& outOfTime = {});
  /// The next draw() starts from its first draw (what it reads changed while it was under way).
  void restartDraw() { slices_.restart(); }
  /// Draws into `out` (width x height, the full G-buffer bound) weights.x T(camera, surface) `surface` + weights.y the
  /// lights' single scattering + weights.z the VPLs' in-scattering of the last draw() + weights.w the approximate
  /// compensation of both (approximateCompensationFactor, of the first medium the ray meets), as steps of `slices`.
  /// `surface` may be out's own texture: it is copied.
  void compose(const Frame& frame, const GlTexture& surface, glm::vec4 weights, int width, int height,
               GlFramebuffer& out, const GlVertexArray& vao, PassSlices& slices);

 private:
  void ensureTargets(const InterleavedLayout& layout);

  GlBuffer table_;
  MediaShaderLayout layout_;
  float uploadedBound_ = 0.0f;
  DensityGridsGpu grids_;
  std::vector<std::string> gridMediumNames_;  // grid g's medium's name
  std::unique_ptr<ShaderProgram> lights_;
  int lightsLayoutCapacity_ = 0;
  std::unique_ptr<BrdfVariants> vpls_;
  DeferredProgram merge_;
  std::unique_ptr<ShaderProgram> compose_;
  // The media the programs were compiled for.
  MediaShaderLayout lightsMedia_, composeMedia_;
  // The interleaved results (block layout), their merge (lights in colour 0, VPLs in colour 1) and a copy of the
  // surfaces' image that compose() reads.
  std::unique_ptr<Target> lightsRaw_, vplsRaw_, merged_, surfaceCopy_;
  std::unique_ptr<GlTexture> mergedVpls_;
  int rawWidth_ = 0, rawHeight_ = 0, gridWidth_ = 0, gridHeight_ = 0;
  // Where a draw() cut short goes on.
  PassSlices slices_;
};

}  // namespace vplab
