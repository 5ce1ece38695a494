#pragma once
// Which work a change makes stale (never re-do work that a parameter did not invalidate). Pure logic over Settings
// values, no GL: the editor asks it after every edit and re-runs exactly the stages it names, and the GL preview
// (PreviewRenderer::render) asks it for the settings and camera of each frame and runs the passes it names; the tests
// check it against the dependency list below and the preview's passes against it.
//
// Stage dependencies:
//   VPL generation    <- scene, lights, seed, generation, vplCount, vplMaxBounces, rejection (+ the parameters of
//                        the generation method and of rejection while in use; with an importance-driven method also
//                        importancePoints and the image size, since the importance points are pixels)
//   representatives   <- the VPLs, the camera, the image size, previewRepresentatives: the reduced set the preview
//                        gathers when the VPLs outnumber previewRepresentatives (representative_lights.h); else the
//                        VPLs themselves, and the stage does nothing
//   VPL shadow maps   <- the VPLs (the representatives), the visibility technique and its sizes (shadowMapSize;
//                        ismTileSize, ismPointBudget); a new set of representatives redoes the maps of the casters
//                        that moved only, which the technique compares (PreviewRenderer)
//   light shadow maps <- scene, lights, directLightSamples, seed (the light sample points), lightShadowMapSize; not
//                        shadowMapSize
//   G-buffer          <- scene, the camera, image size, indirectDownscale (the indirect light's G-buffer)
//   direct light      <- the G-buffer, the light shadow maps, interleave
//   gather            <- the G-buffer, the VPLs (the representatives) and their shadow maps, clampBound, the VSL
//                        radius, interleave, shadowBias, components
//   SSBC              <- the direct light, the gather, ssbcSteps, ssbcCoarseRings
//   tonemap           <- SSBC, exposure (the view's tonemapping of the read-back linear image, on the CPU; the GL
//                        preview has no pass for it)
//   (media)           <- a scene's media (coefficients, g, boxes) act on the light paths: VPL generation (where
//                        paths scatter, their attenuation) and the offline result; the clamp bound b and the camera
//                        do not touch the VPLs, in media as elsewhere
//   offline result    <- scene, lights, camera, image size, seed, and the parameters of the offline method: the
//                        reference ignores every VPL parameter; the VPL methods read the VPLs, and clampBound when
//                        they clamp (vpl, vpl-kk, vpl-abc); the VSL method reads the VSL parameters (the radius and the
//                        CPU's cone samples); vrl reads vrlSamples, vbl also the beam radius, passes and shrink. Exposure, threads and
//                        the preview-only parameters never touch it (results do not depend on the thread count).

#include <string>
#include <vector>

#include "renderer/scene/medium.h"
#include "renderer/settings.h"

namespace vplab {

struct Staleness {
  bool vpls = false;             ///< VPL generation (and rejection) must run again
  bool representatives = false;  ///< the preview's representative lights must be chosen again for the view
  bool vplShadowMaps = false;    ///< one shadow map per VPL must be re-rendered
  bool lightShadowMaps = false;  ///< the shadow maps of the direct-light samples must be re-rendered
  bool gbuffer = false;          ///< the preview's G-buffer (what the camera sees)
  bool direct = false;           ///< the preview's direct light
  bool gather = false;           ///< per-pixel VPL gather (and the de-interleave of it and the direct light)
  bool ssbc = false;             ///< screen-space bias compensation steps
  bool tonemap = false;          ///< display transform only
  bool offline = false;          ///< the Embree result no longer matches what the preview shows

  bool any() const { return anyPreview() || offline; }
  bool anyPreview() const {
    return vpls || representatives || vplShadowMaps || lightShadowMaps || gbuffer || direct || gather || ssbc ||
           tonemap;
  }
  Staleness& operator|=(const Staleness& o);
  friend Staleness operator|(Staleness a, const Staleness& b) { return a |= b; }
  bool operator==(const Staleness&) const = default;

  /// Everything (a new scene).
  static Staleness all();
  /// Adds the stages downstream of every stage already set (VPLs -> representatives -> gather; VPLs -> VPL shadow maps
  /// -> gather; light shadow maps -> direct light; G-buffer -> direct light and gather; both -> SSBC -> tonemap).
  Staleness propagated() const;
};

/// Human-readable list, e.g. "vpls vplShadowMaps gather ssbc tonemap offline", or "nothing".
std::string toString(const Staleness& staleness);

/// What changing `before` into `after` makes stale, for an offline pass that renders `offlineMethod`. Downstream
/// stages are included (the result is propagated()).
Staleness staleAfterSettingsChange(const Settings& before, const Settings& after, Method offlineMethod);

/// A camera move (orbit, pan, zoom, fly): the G-buffer and what follows it, and the representatives (a reduced set is
/// chosen for the view: the maps of the casters it moved are redone, PreviewRenderer); never the VPLs. With
/// rejection on, the VPLs keep the importance measured from the camera they were generated for; a new camera only
/// changes which VPLs would be preferred, not the correctness of the estimate (rejection stays unbiased for epsilon >
/// 0).
Staleness staleAfterCameraMove();

/// A punctual light moved or changed intensity: the VPLs are regenerated (same seed, so they move coherently), and
/// so is everything downstream, and the light shadow maps; the G-buffer stays.
Staleness staleAfterLightEdit();

/// A scene's media edited (a box added, removed, moved or resized; sigma_a, sigma_s or g changed): the light paths
/// scatter and attenuate elsewhere, so the VPLs are regenerated (same seed) with everything downstream, the direct
/// light (its transmittance) and the offline result; the G-buffer and the shadow maps of surfaces stay. Media that
/// neither absorb nor scatter before and after (vacuum, a renamed medium) change nothing.
Staleness staleAfterMediumEdit(const std::vector<Medium>& before, const std::vector<Medium>& after);

}  // namespace vplab
