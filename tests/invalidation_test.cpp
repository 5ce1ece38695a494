#include "renderer/invalidation.h"

#include <gtest/gtest.h>

#include <functional>
#include <vector>

namespace vplab {
namespace {

Staleness change(const std::function<void(Settings&)>& edit, Method method = Method::Vpl) {
  Settings before;
  Settings after = before;
  edit(after);
  return staleAfterSettingsChange(before, after, method);
}

TEST(Invalidation, NoChangeInvalidatesNothing) {
  Settings s;
  EXPECT_FALSE(staleAfterSettingsChange(s, s, Method::Vpl).any());
  EXPECT_EQ(toString(Staleness{}), "nothing");
}

TEST(Invalidation, ClampBoundKeepsVplsAndShadowMaps) {
  Staleness s = change([](Settings& x) { x.clampBound = 0.5f; });
  EXPECT_FALSE(s.vpls);
  EXPECT_FALSE(s.vplShadowMaps);
  EXPECT_FALSE(s.lightShadowMaps);
  EXPECT_TRUE(s.gather && s.ssbc && s.tonemap);
  EXPECT_TRUE(s.offline);
  // The path-traced reference does not depend on b, so the chart's errors stay measured against it.
  EXPECT_FALSE(change([](Settings& x) { x.clampBound = 0.5f; }, Method::Reference).offline);
  EXPECT_FALSE(change([](Settings& x) { x.clampBound = 0.5f; }, Method::Vsl).offline);
}

TEST(Invalidation, MediaMethodsGoStaleWithWhatTheyRead) {
  // Approximate compensation clamps; virtual ray lights and beams do not.
  EXPECT_TRUE(change([](Settings& x) { x.clampBound = 0.5f; }, Method::VplAbc).offline);
  EXPECT_FALSE(change([](Settings& x) { x.clampBound = 0.5f; }, Method::Vrl).offline);
  EXPECT_FALSE(change([](Settings& x) { x.clampBound = 0.5f; }, Method::Vbl).offline);
  // Their own parameters stale them and nothing of the preview.
  for (Method m : {Method::Vrl, Method::Vbl}) {
    Staleness s = change([](Settings& x) { x.vrlSamples = 4; }, m);
    EXPECT_TRUE(s.offline) << toString(m);
    EXPECT_FALSE(s.anyPreview()) << toString(m);
  }
  EXPECT_FALSE(change([](Settings& x) { x.vrlSamples = 4; }, Method::Vpl).offline);
  for (const auto& beam : std::vector<std::function<void(Settings&)>>{[](Settings& x) { x.beamRadius = 0.1f; },
                                                                       [](Settings& x) { x.beamPasses = 3; },
                                                                       [](Settings& x) { x.beamShrink = 0.9f; }}) {
    EXPECT_TRUE(change(beam, Method::Vbl).offline);
    EXPECT_FALSE(change(beam, Method::Vrl).any());
  }
}

TEST(Invalidation, VplParametersRegenerateEverythingDownstream) {
  for (auto edit : std::vector<std::function<void(Settings&)>>{
           [](Settings& x) { x.vplCount = 64; }, [](Settings& x) { x.vplMaxBounces = 2; },
           [](Settings& x) { x.seed = 9; }, [](Settings& x) { x.rejection = true; }}) {
    Staleness s = change(edit);
    EXPECT_TRUE(s.vpls && s.vplShadowMaps && s.gather && s.ssbc && s.tonemap && s.offline) << toString(s);
  }
  EXPECT_FALSE(change([](Settings& x) { x.vplCount = 64; }, Method::Reference).offline);
}

TEST(Invalidation, RejectionParametersMatterOnlyWhileRejectionIsOn) {
  EXPECT_FALSE(change([](Settings& x) { x.rejectionEpsilon = 0.3f; }).any());
  Settings on;
  on.rejection = true;
  Settings after = on;
  after.rejectionEpsilon = 0.3f;
  EXPECT_TRUE(staleAfterSettingsChange(on, after, Method::Vpl).vpls);
  // With rejection on the importance is measured at pixels, so a new image size means new VPLs.
  after = on;
  after.width = 128;
  EXPECT_TRUE(staleAfterSettingsChange(on, after, Method::Vpl).vpls);
  EXPECT_FALSE(change([](Settings& x) { x.width = 128; }).vpls);
}

TEST(Invalidation, PreviewOnlyParametersNeverTouchTheOfflineResult) {
  Staleness ssbc = change([](Settings& x) { x.ssbcSteps = 2; });
  EXPECT_EQ(toString(ssbc), "ssbc tonemap");
  Staleness ssbcCoarse = change([](Settings& x) { x.ssbcCoarseRings = false; });
  EXPECT_EQ(toString(ssbcCoarse), "ssbc tonemap");
  Staleness exposure = change([](Settings& x) { x.exposure = 1.0f; });
  EXPECT_EQ(toString(exposure), "tonemap");
  Staleness interleave = change([](Settings& x) { x.interleave = 4; });
  EXPECT_EQ(toString(interleave), "direct gather ssbc tonemap");
  Staleness mapSize = change([](Settings& x) { x.shadowMapSize = 128; });
  EXPECT_EQ(toString(mapSize), "vplShadowMaps gather ssbc tonemap");
  // The VPL visibility technique and its sizes redo the VPL maps only; the lights' maps do not depend on them.
  for (auto edit : {+[](Settings& x) { x.visibility = VisibilityMethod::Ism; },
                    +[](Settings& x) { x.ismTileSize = 128; }, +[](Settings& x) { x.ismPointBudget = 4096; }})
    EXPECT_EQ(toString(change(edit)), "vplShadowMaps gather ssbc tonemap");
  // The indirect light's grid takes its G-buffer from the G-buffer's pass.
  Staleness downscale = change([](Settings& x) { x.indirectDownscale = 2; });
  EXPECT_EQ(toString(downscale), "gbuffer direct gather ssbc tonemap");
  Staleness bias = change([](Settings& x) { x.shadowBias = 0.01f; });
  EXPECT_EQ(toString(bias), "gather ssbc tonemap");
  Staleness direct = change([](Settings& x) { x.directLightSamples = 16; });
  EXPECT_EQ(toString(direct), "lightShadowMaps direct ssbc tonemap");
  EXPECT_EQ(toString(change([](Settings& x) { x.lightShadowMapSize = 256; })), "lightShadowMaps direct ssbc tonemap");
  EXPECT_FALSE(change([](Settings& x) { x.threads = 1; }).any());
}

TEST(Invalidation, VslParametersAffectTheGatherAndTheVslMethodOnly) {
  Staleness s = change([](Settings& x) { x.vslRadius = 0.05f; }, Method::Vsl);
  EXPECT_FALSE(s.vpls);
  EXPECT_TRUE(s.gather && s.offline);
  EXPECT_FALSE(change([](Settings& x) { x.vslRadius = 0.05f; }, Method::Vpl).offline);
  // The cone samples are the CPU estimator's: the preview's integral takes none.
  EXPECT_EQ(toString(change([](Settings& x) { x.vslSamples = 5; }, Method::Vsl)), "offline");
  EXPECT_FALSE(change([](Settings& x) { x.vslSamples = 5; }, Method::Vpl).any());
}

TEST(Invalidation, ReferenceParametersTouchOnlyTheOfflineResult) {
  EXPECT_EQ(toString(change([](Settings& x) { x.samplesPerPixel = 8; }, Method::Reference)), "offline");
  EXPECT_FALSE(change([](Settings& x) { x.exactSamplesPerPixel = 8; }, Method::Reference).any());
  EXPECT_EQ(toString(change([](Settings& x) { x.exactSamplesPerPixel = 8; }, Method::Vsl)), "offline");
  EXPECT_EQ(toString(change([](Settings& x) { x.maxDepth = 3; }, Method::Reference)), "offline");
}

TEST(Invalidation, CameraMoveKeepsVplsAndShadowMaps) {
  Staleness s = staleAfterCameraMove();
  EXPECT_FALSE(s.vpls || s.vplShadowMaps || s.lightShadowMaps);
  EXPECT_TRUE(s.gbuffer && s.direct && s.gather && s.ssbc && s.tonemap && s.offline);
  // A new image size is a new G-buffer too.
  EXPECT_EQ(toString(change([](Settings& x) { x.width = 96; })),
            "representatives gbuffer direct gather ssbc tonemap offline");
}

TEST(Invalidation, CameraMoveChoosesTheRepresentativesAgainWithoutNewVpls) {
  // The preview's reduced set is chosen per view: a camera move re-clusters, the VPLs stay; the maps are redone per
  // caster that moved (the visibility technique compares them), not by the stage.
  EXPECT_TRUE(staleAfterCameraMove().representatives);
  EXPECT_EQ(toString(change([](Settings& x) { x.previewRepresentatives = 256; })),
            "representatives gather ssbc tonemap");
  // The cut's bounds use the importance bound, not b: b keeps the representatives.
  EXPECT_FALSE(change([](Settings& x) { x.clampBound = 0.5f; }).representatives);
  Staleness vpls;
  vpls.vpls = true;
  EXPECT_TRUE(vpls.propagated().representatives);
}

// Moving a density grid between its 3D texture and its NanoVDB buffer redraws what reads the media, nothing else.
TEST(Invalidation, GridStorageRedrawsThePassesThatReadTheMedia) {
  EXPECT_EQ(toString(change([](Settings& x) { x.previewGridInBuffer = true; })), "direct gather ssbc tonemap");
}

TEST(Invalidation, LightEditRegeneratesVplsAndShadowMaps) {
  Staleness s = staleAfterLightEdit();
  Staleness allButTheGbuffer = Staleness::all();
  allButTheGbuffer.gbuffer = false;
  EXPECT_EQ(s, allButTheGbuffer);
}

TEST(Invalidation, PropagationFollowsThePipeline) {
  Staleness s;
  s.vpls = true;
  Staleness p = s.propagated();
  EXPECT_TRUE(p.vplShadowMaps && p.gather && p.ssbc && p.tonemap);
  EXPECT_FALSE(p.lightShadowMaps || p.gbuffer || p.direct || p.offline);
  Staleness lights;
  lights.lightShadowMaps = true;
  EXPECT_EQ(toString(lights.propagated()), "lightShadowMaps direct ssbc tonemap");
  Staleness merged = Staleness{} | staleAfterCameraMove();
  EXPECT_EQ(merged, staleAfterCameraMove());
}

}  // namespace
}  // namespace vplab
