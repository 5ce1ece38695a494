#include "ui/presets.h"

#include <functional>

namespace vplab::ui {

namespace {

TeachingPreset make(std::string name, std::string scene, ViewMode view, const std::function<void(Settings&)>& edit,
                    std::string explanation) {
  TeachingPreset p;
  p.name = std::move(name);
  p.scene = std::move(scene);
  p.view = view;
  // Small images keep every preset interactive on software GL.
  p.settings.width = 256;
  p.settings.height = 256;
  edit(p.settings);
  p.explanation = std::move(explanation);
  return p;
}

}  // namespace

const std::vector<TeachingPreset>& teachingPresets() {
  static const std::vector<TeachingPreset> presets = [] {
    std::vector<TeachingPreset> list;
    list.push_back(make(
        "Corner splotches (no bound)", "cornell-box.gltf", ViewMode::Preview,
        [](Settings& s) {
          s.vplCount = 64;
          s.clampBound = kInfinity;
        },
        "Look at the corners and where the blocks meet the floor: bright blotches. A VPL close to a surface has a "
        "geometry term cos1 cos2 / d^2 that grows without bound as d -> 0, so one VPL dominates nearby pixels. "
        "More VPLs only make the splotches smaller, not gone."));
    list.push_back(make(
        "Darkened corners (tight bound)", "cornell-box.gltf", ViewMode::Split,
        [](Settings& s) {
          s.vplCount = 256;
          s.clampBound = 4.0f;
        },
        "The splotches are gone but the corners and the gaps under the blocks are darker than the reference on the "
        "right. G_b = min(G, b) removes every contribution with G > b, which only happens closer than 1/sqrt(b) "
        "(0.5 m here): the missing light is local short-range transport."));
    list.push_back(make(
        "Energy recovered (bound + SSBC)", "cornell-box.gltf", ViewMode::Split,
        [](Settings& s) {
          s.vplCount = 256;
          s.clampBound = 4.0f;
          s.ssbcSteps = 2;
        },
        "Screen-space bias compensation adds back the clamped residual as an image filter over the pixels within "
        "1/sqrt(b) (Novak et al. 2011). Compare the corners with the previous preset and open the SSBC residual "
        "view: the light it adds sits exactly where the bound darkened the image."));
    list.push_back(make(
        "Glossy splotches", "cornell-glossy.gltf", ViewMode::Preview,
        [](Settings& s) {
          s.vplCount = 128;
          s.clampBound = kInfinity;
        },
        "On the glossy surface every VPL shows as a sharp highlight: a GGX lobe times a point light is a point-like "
        "reflection. Clamping would remove the glossy inter-reflection entirely instead of smoothing it."));
    list.push_back(make(
        "Virtual spherical lights", "cornell-glossy.gltf", ViewMode::Split,
        [](Settings& s) {
          s.vplCount = 128;
          s.clampBound = kInfinity;
          s.vslRadius = 0.05f;
        },
        "Each VPL becomes a sphere of radius r whose light is integrated over the cone it subtends (Hasan et al. "
        "2009): the point-like glossy highlights of the previous preset spread into smooth reflections, and no energy "
        "is removed. The preview evaluates the cone integral without random samples, so the reflections are smooth "
        "and stay still; 'Render exact VPL' puts the exact CPU render of the same VSLs beside it. Increase r to see "
        "the price: sharp indirect features blur."));
    list.push_back(make(
        "Wasted VPLs (two rooms)", "two-rooms.gltf", ViewMode::VplOverlay,
        [](Settings& s) {
          s.vplCount = 128;
          s.rejection = false;
        },
        "The light is in the other room: the overlay shows most VPLs where the camera cannot see their light. They "
        "cost shadow maps and shading time but add nothing, so the visible room is lit by a handful of VPLs and is "
        "noisy and splotchy."));
    list.push_back(make(
        "Rejection of unimportant VPLs", "two-rooms.gltf", ViewMode::VplOverlay,
        [](Settings& s) {
          s.vplCount = 128;
          s.rejection = true;
          s.rejectionEpsilon = 0.05f;
        },
        "Georgiev and Slusallek (2010): candidates are kept with probability min(Phi_i/Phi_v + epsilon, 1) and their "
        "flux divided by it, so the same VPL budget now lands where the camera sees it. Watch the acceptance rate in "
        "the many-light panel and the rejected candidates in the overlay."));
    list.push_back(make(
        "Where each method puts its VPLs (two rooms)", "two-rooms.gltf", ViewMode::VplOverlay,
        [](Settings& s) {
          s.vplCount = 256;
          s.clampBound = 100.0f;
          s.rejectionEpsilon = 0.05f;
          s.generation = VplGeneration::Metropolis;
        },
        "Metropolis instant radiosity (Segovia et al. 2007): Markov chains over light paths visit them in proportion "
        "to what they bring to the camera, so the VPLs gather on the door frame, the lit floor seen through the door "
        "and this room's walls. Switch the method in the many-light panel and watch the overlay (the ring colour "
        "is the method's): light tracing leaves most of its VPLs in the far room, rejection thins those out, "
        "bidirectional adds first-bounce VPLs seen from the camera. Each improved method puts a larger share of the "
        "same budget in this room, and at these 256 VPLs its error (4x4-pixel blocks against the path-traced "
        "reference) is about 0.3 to 0.6 times light tracing's (docs/methods.md): render the reference and open the "
        "difference view to see where."));
    {
      TeachingPreset p = make(
          "Flicker from reshuffled VPLs", "cornell-box.gltf", ViewMode::Preview,
          [](Settings& s) {
            s.vplCount = 64;
            s.clampBound = 20.0f;
          },
          "The light moves a little every frame and every frame draws a new VPL seed: the indirect light jumps "
          "although the scene barely changed. Independent random VPL sets differ by their full variance each frame.");
      p.animateLight = true;
      p.reseedEveryFrame = true;
      list.push_back(p);
    }
    {
      TeachingPreset p = make(
          "Coherent QMC VPLs", "cornell-box.gltf", ViewMode::Preview,
          [](Settings& s) {
            s.vplCount = 64;
            s.clampBound = 20.0f;
          },
          "Same light motion, fixed seed: each light path keeps its Halton point, so a small light move moves every "
          "VPL a little and the image changes smoothly. The error is still there, but it no longer flickers.");
      p.animateLight = true;
      list.push_back(p);
    }
    list.push_back(make(
        "Shadow-map leaks", "cornell-box.gltf", ViewMode::Split,
        [](Settings& s) {
          s.vplCount = 128;
          s.clampBound = 20.0f;
          s.shadowMapSize = 16;
          s.shadowBias = 0.05f;
        },
        "Tiny VPL shadow maps with a large depth bias: light leaks under the blocks and along the wall edges, where "
        "the exact render on the right is dark. Raise the shadow-map size and lower the bias to close the leaks; too "
        "small a bias brings back shadow acne."));
    list.push_back(make(
        "Imperfect shadow maps: leaks and over-darkening", "two-rooms.gltf", ViewMode::Difference,
        [](Settings& s) {
          s.vplCount = 256;
          s.clampBound = 20.0f;
          s.visibility = VisibilityMethod::Ism;
          // A small point budget (256 points per VPL) and small tiles make ISM's failures visible at a glance.
          s.ismPointBudget = 1 << 16;
          s.ismTileSize = 32;
        },
        "Each VPL's visibility comes from a few hundred splatted points instead of the triangles (Ritschel et al. "
        "2008). Render the exact VPL render (O): the difference against it is the failure map, brighter where light "
        "leaks through the wall between the rooms, where too few points covered the wall near a VPL, darker where "
        "splats and the depth bias shadow surfaces that meet. Raise the ISM points and the tile size, or "
        "switch the VPL visibility to cube shadow maps, and the map fades."));
    return list;
  }();
  return presets;
}

}  // namespace vplab::ui
