#include "renderer/gl/ssbc_pass.h"

#include <glad/gl.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <string>

#include "renderer/gl/texture_units.h"

namespace vplab {

namespace {
// The levels the taps' buffers index (uTapLevelBase, shaders/common/ssbc_levels.glsl): an image of at most 16384^2
// (Settings) has 15.
constexpr int kSsbcMaxLevels = 16;
}  // namespace

bool ssbcCompensates(const Settings& settings) {
  return settings.ssbcSteps > 0 && std::isfinite(settings.clampBound) && settings.clampBound > 0.0f;
}

std::vector<int> ssbcTapLevelBases(int width, int height) {
  std::vector<int> bases = {0};
  for (int level = 0; (width >> level) > 0 || (height >> level) > 0; ++level)
    bases.push_back(bases.back() + std::max(1, width >> level) * std::max(1, height >> level));
  if (static_cast<int>(bases.size()) - 1 > kSsbcMaxLevels)
    throw GlError("the compensation takes images of at most 16384^2, not " + std::to_string(width) + "x" +
                  std::to_string(height));
  return bases;
}

struct SsbcPass::Targets {
  int width, height;
  // Per mip texel of the G-buffer: x2 with the x of the unit normal, and dA with the code of its y, of a compensation
  // tap (ssbc_taps.frag.glsl); I dA with that code per mip texel of a step's input (ssbc_radiance.frag.glsl). Both are
  // drawn into the mip chain `staging` (one framebuffer per level; the tap factors' dA beside it, in `area`) and every
  // level copied into a buffer texture (common/ssbc_levels.glsl), level l's rows of max(1, width >> l) texels from
  // texel levelBase[l] on: a tap fetches from a buffer for about half of what a fetch from a mip level costs on
  // llvmpipe, and the copies cost a fraction of what that saves.
  std::vector<int> levelBase;
  GlTexture staging, area;
  std::vector<GlFramebuffer> tapLevels, radianceLevels;
  GlBufferTexture taps, radiance;
  // Level l >= 1 (index l) of the G-buffer's position and normal and of a step's input, the means of the level below,
  // which the draw of level l writes beside its factors and the draw of level l + 1 reads (ssbcAverageFiner): no
  // glGenerateMipmap pass over the G-buffer or the input, which cost as much as the factors' own draws.
  std::vector<GlTexture> averagedPosition, averagedNormal, averagedInput;
  GlLinearSampler averaging;
  // The coarse rings of a compensation step at every 4th pixel (ssbc.frag.glsl with SSBC_COARSE_PASS), and their
  // far rings alone (second attachment of coarse.framebuffer).
  Target coarse;
  GlTexture coarseFar;
  // Per coarse block: whether every fine-ring tap of its pixels is coplanar with them (ssbc_flat.frag.glsl), from
  // per-row summaries of the blocks' windows (plane, and state: found, all on it, tolerance).
  Target flat;
  GlTexture flatRowPlanes, flatRowStates;
  GlFramebuffer flatRows;
  // Where the fine and the fallback passes run (ssbc_mask.frag.glsl): depth-only framebuffers that make the masks,
  // and the framebuffers the passes draw through, a step's output with the pass's mask (the fine pass's per step).
  GlTexture fineMask, fallbackMask;
  GlFramebuffer fineMaskDraw, fallbackMaskDraw, fineInto[2], fallbackInto;
  // Whether taps/area, and flat with the masks, were made from the current G-buffer (flat: only made with the coarse
  // rings).
  bool tapsCurrent = false, flatCurrent = false;

  Targets(int w, int h)
      : width(w),
        height(h),
        levelBase(ssbcTapLevelBases(w, h)),
        staging(w, h, TextureFormat::Rgba32F, 0),
        area(w, h, TextureFormat::Rg32F, 0),
        taps(static_cast<std::size_t>(levelBase.back())),
        radiance(static_cast<std::size_t>(levelBase.back())),
        coarse((w + 3) / 4, (h + 3) / 4),
        coarseFar((w + 3) / 4, (h + 3) / 4, TextureFormat::Rgba32F),
        flat((w + 3) / 4, (h + 3) / 4),
        flatRowPlanes((w + 3) / 4, h, TextureFormat::Rgba32F),
        flatRowStates((w + 3) / 4, h, TextureFormat::Rgba32F),
        fineMask(w, h, TextureFormat::Depth32F),
        fallbackMask(w, h, TextureFormat::Depth32F) {
    fineMaskDraw.attachDepth(fineMask);
    fineMaskDraw.finalize(0);
    fallbackMaskDraw.attachDepth(fallbackMask);
    fallbackMaskDraw.finalize(0);
    for (GlFramebuffer& into : fineInto) into.attachDepth(fineMask);
    fallbackInto.attachDepth(fallbackMask);
    flatRows.attachColor(0, flatRowPlanes);
    flatRows.attachColor(1, flatRowStates);
    flatRows.finalize(2);
    // The interpolation of the coarse rings is the bilinear filter's (SSBC_SPLIT).
    coarse.texture.setLinearFiltering(true, false);
    coarse.framebuffer.attachColor(1, coarseFar);
    coarse.framebuffer.finalize(2);
    const auto levels = static_cast<std::size_t>(staging.levels());
    tapLevels.resize(levels);
    radianceLevels.resize(levels);
    averagedPosition.resize(levels);
    averagedNormal.resize(levels);
    averagedInput.resize(levels);
    for (std::size_t level = 0; level < levels; ++level) {
      const int l = static_cast<int>(level);
      GlFramebuffer& tapLevel = tapLevels[level];
      GlFramebuffer& radianceLevel = radianceLevels[level];
      tapLevel.attachColor(0, staging, l);
      tapLevel.attachColor(1, area, l);
      radianceLevel.attachColor(0, staging, l);
      if (level == 0) {
        tapLevel.finalize(2);
        radianceLevel.finalize(1);
        continue;
      }
      const int w = std::max(1, width >> l), h = std::max(1, height >> l);
      averagedPosition[level] = GlTexture(w, h, TextureFormat::Rgba32F);
      averagedNormal[level] = GlTexture(w, h, TextureFormat::Rgba32F);
      averagedInput[level] = GlTexture(w, h, TextureFormat::Rgba32F);
      tapLevel.attachColor(2, averagedPosition[level]);
      tapLevel.attachColor(3, averagedNormal[level]);
      tapLevel.finalize(4);
      radianceLevel.attachColor(1, averagedInput[level]);
      radianceLevel.finalize(2);
    }
  }

  // Copies every level of `staging` into `buffer` as levelBase lays them out.
  void copyStaging(GlBufferTexture& buffer) const {
    for (int level = 0; level < staging.levels(); ++level)
      buffer.copyLevel(staging, level, static_cast<std::size_t>(levelBase[static_cast<std::size_t>(level)]));
  }
};

SsbcPass::SsbcPass()
    : ssbc_("preview/ssbc.frag.glsl"),
      taps_({"preview/fullscreen.vert.glsl", "preview/ssbc_taps.frag.glsl"}),
      coarserTaps_({"preview/fullscreen.vert.glsl", "preview/ssbc_taps.frag.glsl"}, {"SSBC_AVERAGE_FINER 1"}),
      radiance_({"preview/fullscreen.vert.glsl", "preview/ssbc_radiance.frag.glsl"}),
      coarserRadiance_({"preview/fullscreen.vert.glsl", "preview/ssbc_radiance.frag.glsl"}, {"SSBC_AVERAGE_FINER 1"}),
      split_("preview/ssbc.frag.glsl", {"SSBC_SPLIT 1"}),
      coarse_("preview/ssbc.frag.glsl", {"SSBC_COARSE_PASS 1"}),
      fine_("preview/ssbc.frag.glsl", {"SSBC_SPLIT 1", "SSBC_FINE_PASS 1"}),
      flatRows_({"preview/fullscreen.vert.glsl", "preview/ssbc_flat.frag.glsl"}, {"SSBC_FLAT_ROWS 1"}),
      flatColumns_({"preview/fullscreen.vert.glsl", "preview/ssbc_flat.frag.glsl"}, {"SSBC_FLAT_ROWS 0"}),
      fineMask_({"preview/fullscreen.vert.glsl", "preview/ssbc_mask.frag.glsl"}, {"SSBC_MASK_FINE 1"}),
      fallbackMask_({"preview/fullscreen.vert.glsl", "preview/ssbc_mask.frag.glsl"}),
      fallback_("preview/ssbc.frag.glsl", {"SSBC_SPLIT 1", "SSBC_FALLBACK_PASS 1"}),
      upsample_("preview/ssbc.frag.glsl", {"SSBC_SPLIT 1", "SSBC_UPSAMPLE_PASS 1"}) {}

SsbcPass::~SsbcPass() = default;

int SsbcPass::run(bool lambertOnly, const Camera& camera, const Settings& settings, const SsbcImages& images,
                  const GlVertexArray& vao, PassSlices& slices) {
  if (!ssbcCompensates(settings)) return 0;
  const int width = images.i0.texture.width(), height = images.i0.texture.height();
  if (!targets_ || targets_->width != width || targets_->height != height)
    targets_ = std::make_unique<Targets>(width, height);
  Targets& tg = *targets_;
  const bool split = settings.ssbcCoarseRings;
  if (slices.starting()) {
    if (!images.gbufferDerivedCurrent) tg.tapsCurrent = tg.flatCurrent = false;
    images.gbufferDerivedCurrent = true;
    redoFlat_ = split && !tg.flatCurrent;
    redoTaps_ = !tg.tapsCurrent;
  }
  const int steps = std::min(settings.ssbcSteps, 2);
  float focal = 0.5f * static_cast<float>(height) / std::tan(0.5f * camera.yfov);
  ShaderProgram& ssbc = split ? split_[lambertOnly] : ssbc_[lambertOnly];
  ShaderProgram& coarse = coarse_[lambertOnly];
  ShaderProgram& fallback = fallback_[lambertOnly];
  ShaderProgram& fine = fine_[lambertOnly];
  ShaderProgram& upsample = upsample_[lambertOnly];
  // What ssbcReceiver reads.
  auto setReceiver = [&](ShaderProgram& program) {
    program.set("uCameraPosition", camera.position);
    program.set("uCameraForward", camera.forward);
    program.set("uClampBound", settings.clampBound);
    program.set("uFocalPixels", focal);
    program.set("uMaxLevel", tg.staging.levels() - 1);
    program.setArray("uTapLevelBase", tg.levelBase.data(), tg.staging.levels());
  };
  for (ShaderProgram* program : {&ssbc, &coarse, &fallback, &fine, &upsample}) setReceiver(*program);
  ssbc.set("uScale", 1);
  coarse.set("uScale", 4);
  fallback.set("uScale", 1);
  fine.set("uScale", 1);
  upsample.set("uScale", 1);
  // Draws `first` into level 0 and `coarser` into every level above it of a full-resolution mip chain (one framebuffer
  // per level), uLevel set; bindFiner(l) binds what the draw of level l >= 1 averages, which the draw of level l - 1
  // wrote.
  auto drawEveryLevel = [&](std::vector<GlFramebuffer>& levels, ShaderProgram& first, ShaderProgram& coarser,
                            const std::function<void(std::size_t)>& bindFiner) {
    for (std::size_t level = 0; level < levels.size(); ++level) {
      const int l = static_cast<int>(level);
      const int w = std::max(1, width >> l), h = std::max(1, height >> l);
      ShaderProgram& program = level == 0 ? first : coarser;
      levels[level].bind(w, h);
      if (level > 0) bindFiner(level);
      program.set("uLevel", l);
      slices.bands(glm::ivec4(0, 0, w, h), [&] { drawFullscreen(program, vao); });
    }
  };
  // Draws `program` at every pixel of the bound `w` x `h` target.
  auto drawWhole = [&](ShaderProgram& program, int w, int h) {
    slices.bands(glm::ivec4(0, 0, w, h), [&] { drawFullscreen(program, vao); });
  };
  // Multi-resolution rings, each pass through a mask (ssbc_mask.frag.glsl) drawn at a smaller depth: where the fallback
  // mask is 0 (p is no receiver, or every coarse sample its interpolation weighs lies on its surface) the coarse rings
  // bilinear from the coarse grid, where it is 1 `incomplete`, both writing; then the fine rings added (blending) where
  // the fine mask is 1.
  auto drawSplitPasses = [&](Target& output, GlFramebuffer& fineInto, ShaderProgram& incomplete) {
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    tg.fallbackInto.attachColor(0, output.texture);
    tg.fallbackInto.finalize(1);
    tg.fallbackInto.bind(width, height);
    glDepthFunc(GL_GREATER);
    drawWhole(ssbc, width, height);
    glDepthFunc(GL_LESS);
    drawWhole(incomplete, width, height);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    fineInto.attachColor(0, output.texture);
    fineInto.finalize(1);
    fineInto.bind(width, height);
    drawWhole(fine, width, height);
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
    glDisable(GL_DEPTH_TEST);
  };
  if (redoFlat_) {
    // Which coarse blocks lie on one plane: depends on the G-buffer only, once for both steps and every VPL set.
    tg.flatRows.bind(tg.flat.texture.width(), height);
    drawWhole(flatRows_.get(), tg.flat.texture.width(), height);
    tg.flatRowPlanes.bind(unit(TextureUnit::PassInput4));
    tg.flatRowStates.bind(unit(TextureUnit::PassInput6));
    tg.flat.framebuffer.bind(tg.flat.texture.width(), tg.flat.texture.height());
    drawWhole(flatColumns_.get(), tg.flat.texture.width(), tg.flat.texture.height());
    tg.flat.texture.bind(unit(TextureUnit::PassInput7));
    setReceiver(fineMask_.get());
    setReceiver(fallbackMask_.get());
    glEnable(GL_DEPTH_TEST);  // writes depth, which GL does only with the test on
    glDepthFunc(GL_ALWAYS);
    tg.fineMaskDraw.bind(width, height);
    drawWhole(fineMask_.get(), width, height);
    tg.fallbackMaskDraw.bind(width, height);
    drawWhole(fallbackMask_.get(), width, height);
    glDisable(GL_DEPTH_TEST);
    slices.step([&] { tg.flatCurrent = true; });
  }
  if (split) tg.flat.texture.bind(unit(TextureUnit::PassInput7));
  // The tap factors depend on the camera and the G-buffer only (the camera cannot move without the G-buffer being
  // drawn again): once for both steps and every VPL set.
  if (redoTaps_) {
    for (ShaderProgram* program : {&taps_.get(), &coarserTaps_.get()}) {
      program->set("uCameraPosition", camera.position);
      program->set("uFocalPixels", focal);
    }
    tg.averaging.bind(unit(TextureUnit::PassInput1));
    tg.averaging.bind(unit(TextureUnit::PassInput2));
    drawEveryLevel(tg.tapLevels, taps_.get(), coarserTaps_.get(), [&](std::size_t level) {
      (level == 1 ? images.gPosition : tg.averagedPosition[level - 1]).bind(unit(TextureUnit::PassInput1));
      (level == 1 ? images.gNormal : tg.averagedNormal[level - 1]).bind(unit(TextureUnit::PassInput2));
    });
    GlLinearSampler::unbind(unit(TextureUnit::PassInput1));
    GlLinearSampler::unbind(unit(TextureUnit::PassInput2));
    slices.step([&] {
      tg.copyStaging(tg.taps);
      tg.tapsCurrent = true;
    });
  }
  tg.taps.bind(unit(TextureUnit::PassInput3));
  tg.area.bind(unit(TextureUnit::PassInput5));
  Target* input = &images.i0;
  Target* outputs[2] = {&images.r1, &images.r2};
  for (int step = 0; step < steps; ++step) {
    // The radiance factor of the taps, I dA, at every mip level of this step's input.
    input->texture.bind(unit(TextureUnit::PassInput0));
    tg.averaging.bind(unit(TextureUnit::PassInput0));
    drawEveryLevel(tg.radianceLevels, radiance_.get(), coarserRadiance_.get(), [&](std::size_t level) {
      (level == 1 ? input->texture : tg.averagedInput[level - 1]).bind(unit(TextureUnit::PassInput0));
    });
    GlLinearSampler::unbind(unit(TextureUnit::PassInput0));
    slices.step([&] { tg.copyStaging(tg.radiance); });
    tg.radiance.bind(unit(TextureUnit::PassInput0));
    if (split) {
      tg.coarse.framebuffer.bind(tg.coarse.texture.width(), tg.coarse.texture.height());
      drawWhole(coarse, tg.coarse.texture.width(), tg.coarse.texture.height());
      tg.coarse.texture.bind(unit(TextureUnit::PassInput4));
      tg.coarseFar.bind(unit(TextureUnit::PassInput6));
    }
    if (split) {
      // R2 = T_r(R1) carries about a tenth of the compensation: there the coarse rings are extrapolated along p's
      // surface where they cannot be interpolated, instead of being evaluated at those pixels.
      drawSplitPasses(*outputs[step], tg.fineInto[step], step == 0 ? fallback : upsample);
    } else {
      outputs[step]->framebuffer.bind(width, height);
      drawWhole(ssbc, width, height);
    }
    input = outputs[step];
  }
  return steps;
}

}  // namespace vplab
