#include "ui/presets.h"

#include "renderer/core/text.h"
#include "renderer/offline/render_methods.h"

#include <cmath>
#include <functional>

namespace vplab::ui {

namespace {

struct PresetSpec {
  std::string name, scene;
  ViewMode view = ViewMode::Preview;
  PresetOffline offline = PresetOffline::None;
  bool signedDifference = false, showRejected = false, animateLight = false, reseedEveryFrame = false;
  Method offlineMethod = Method::Vrl;  ///< with offline = Chosen
  float divider = 0.5f;                ///< with view = Split
};

TeachingPreset make(const PresetSpec& spec, const std::function<void(Settings&)>& edit, std::string explanation) {
  TeachingPreset p;
  p.name = spec.name;
  p.scene = spec.scene;
  p.view = spec.view;
  p.offline = spec.offline;
  p.signedDifference = spec.signedDifference;
  p.showRejected = spec.showRejected;
  p.animateLight = spec.animateLight;
  p.reseedEveryFrame = spec.reseedEveryFrame;
  p.offlineMethod = spec.offlineMethod;
  p.divider = spec.divider;
  p.settings = presetBaseline();
  edit(p.settings);
  p.explanation = std::move(explanation);
  return p;
}

/// The smoke stands left of the image's centre (seen from the scene camera): a divider there splits the plume between
/// the two renders.
constexpr float kSmokeDivider = 0.3f;

}  // namespace

Settings presetBaseline() {
  Settings s;
  s.width = 256;
  s.height = 256;
  return s;
}

const std::vector<TeachingPreset>& teachingPresets() {
  static const std::vector<TeachingPreset> presets = [] {
    std::vector<TeachingPreset> list;
    list.push_back(make(
        {"Corner splotches (no bound)", "cornell-box.gltf"},
        [](Settings& s) {
          s.vplCount = 64;
          s.clampBound = kInfinity;
        },
        "Look at the corners and where the blocks meet the floor: bright blotches. A VPL close to a surface has a "
        "geometry term cos1 cos2 / d^2 that grows without bound as d -> 0, so one VPL dominates nearby pixels. "
        "More VPLs only make the splotches smaller, not gone."));
    list.push_back(make(
        {"Darkened corners (tight bound)", "cornell-box.gltf", ViewMode::Difference, PresetOffline::Reference, true},
        [](Settings& s) {
          s.vplCount = 256;
          s.clampBound = 15.0f;
        },
        "The splotches are gone, but the signed difference against the path-traced reference is blue (too dark) in "
        "the corners and the gaps under the blocks, and near zero elsewhere. G_b = min(G, b) removes every "
        "contribution with G > b, which only happens closer than 1/sqrt(b) (0.26 m in this 0.55 m box): the missing light is local "
        "short-range transport."));
    list.push_back(make(
        {"Energy recovered (bound + SSBC)", "cornell-box.gltf", ViewMode::Difference, PresetOffline::Reference, true},
        [](Settings& s) {
          s.vplCount = 256;
          s.clampBound = 15.0f;
          s.ssbcSteps = 2;
        },
        "Screen-space bias compensation adds back the clamped residual as an image filter over the pixels within "
        "1/sqrt(b) (Novak et al. 2011). The same signed difference as the previous preset: the blue corners are "
        "much fainter. The SSBC residual view (5) shows the light it adds, exactly where the bound darkened the "
        "image; what stays blue is light from surfaces the camera does not see."));
    list.push_back(make(
        {"Glossy splotches", "cornell-glossy.gltf"},
        [](Settings& s) {
          s.vplCount = 128;
          s.clampBound = kInfinity;
        },
        "On the glossy surface every VPL shows as a sharp highlight: a GGX lobe times a point light is a point-like "
        "reflection. Clamping would remove the glossy inter-reflection entirely instead of smoothing it."));
    list.push_back(make(
        {"Virtual spherical lights", "cornell-glossy.gltf", ViewMode::Split, PresetOffline::ExactVpl},
        [](Settings& s) {
          s.vplCount = 128;
          s.clampBound = kInfinity;
          s.vslRadius = 0.05f;
          // Enough samples that the exact render's cone sampling noise does not hide how smooth the VSLs are.
          s.exactSamplesPerPixel = 16;
        },
        "Each VPL becomes a sphere of radius r whose light is integrated over the cone it subtends (Hasan et al. "
        "2009): the point-like glossy highlights of the previous preset spread into smooth reflections, and no energy "
        "is removed. The preview evaluates the cone integral without random samples, so its reflections are smooth "
        "and stay still; on the right is the exact CPU render of the same VSLs. Increase r to see the price: sharp "
        "indirect features blur."));
    list.push_back(make(
        {"Glossy contact reflections", "glossy-counter.gltf", ViewMode::Split, PresetOffline::Chosen, false, false,
         false, false, Method::Lvl},
        [](Settings& s) {
          s.vplCount = 256;
          s.clampBound = 2.0f;
        },
        "The counter is brushed metal: near each box's foot it reflects the box, light that travels a few "
        "centimetres, where G = cos cos / d^2 exceeds the bound b = 2. On the left the preview with bounded VPLs: "
        "those reflections go dark. On the right local virtual lights (Davidovic et al. 2010, lvl): per tile of "
        "pixels, BRDF samples from the tile's pixels find points on the boxes, which are lit by the light and the "
        "VPLs and then light every pixel of the tile with the residual (1 - b/G): the reflections come back, without "
        "bias. Choose vsl in the offline panel (with a VSL radius) to see spheres blur the reflections instead, or "
        "vpl-kk for the same residual path-traced pixel by pixel."));
    list.push_back(make(
        {"Wasted VPLs (two rooms)", "two-rooms.gltf", ViewMode::VplOverlay},
        [](Settings& s) {
          s.vplCount = 128;
          s.rejection = false;
        },
        "The light is in the other room, and so are most VPLs: filled dots are VPLs the camera sees, hollow grey rings "
        "are hidden behind the wall (the count is above the image). The hidden ones light only the other room and "
        "the strip of it seen through the door: they cost shadow maps and shading time, and the room the camera is in "
        "is lit by the handful of VPLs in it, so it is noisy and splotchy."));
    list.push_back(make(
        {"Rejection of unimportant VPLs", "two-rooms.gltf", ViewMode::VplOverlay, PresetOffline::None, false, true},
        [](Settings& s) {
          s.vplCount = 128;
          s.rejection = true;
          s.rejectionEpsilon = 0.05f;
        },
        "Georgiev and Slusallek (2010): candidates are kept with probability min(Phi_i/Phi_v + epsilon, 1) and their "
        "flux divided by it, so the same VPL budget now lands where it lights what the camera sees: more dots are filled. "
        "The grey crosses are the rejected candidates, mostly in the other room; the acceptance rate is in the "
        "many-light panel."));
    list.push_back(make(
        {"Where each method puts its VPLs (two rooms)", "two-rooms.gltf", ViewMode::VplOverlay,
         PresetOffline::Reference},
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
        "reference) is about 0.3 to 0.6 times light tracing's (docs/methods.md): the preset starts that reference, so "
        "open the difference view to see where."));
    list.push_back(make(
        {"Flicker from reshuffled VPLs", "cornell-box.gltf", ViewMode::Preview, PresetOffline::None, false, false,
         true, true},
        [](Settings& s) {
          s.vplCount = 64;
          s.clampBound = 20.0f;
        },
        "The light moves a little every frame and every frame draws a new VPL seed: the indirect light jumps "
        "although the scene barely changed. Independent random VPL sets differ by their full variance each frame."));
    list.push_back(make(
        {"Coherent QMC VPLs", "cornell-box.gltf", ViewMode::Preview, PresetOffline::None, false, false, true},
        [](Settings& s) {
          s.vplCount = 64;
          s.clampBound = 20.0f;
        },
        "Same light motion, fixed seed: each light path keeps its Halton point, so a small light move moves every "
        "VPL a little and the image changes smoothly. The error is still there, but it no longer flickers."));
    list.push_back(make(
        {"Shadow-map leaks", "cornell-box.gltf", ViewMode::Difference, PresetOffline::ExactVpl, true},
        [](Settings& s) {
          s.vplCount = 128;
          s.clampBound = 20.0f;
          s.shadowMapSize = 16;
          s.shadowBias = 0.05f;
        },
        "Tiny VPL shadow maps (16 x 16 per cube face) with a large depth bias, against the exact render of the same "
        "VPLs: red where light leaks past the blocks and along the wall edges, blue where a coarse texel that covers "
        "both an occluder and the surface behind it spreads the shadow. Raise the shadow-map size and lower the bias "
        "and both fade; too small a bias brings back shadow acne."));
    list.push_back(make(
        {"Imperfect shadow maps: leaks and over-darkening", "two-rooms.gltf", ViewMode::Difference,
         PresetOffline::ExactVpl, true},
        [](Settings& s) {
          s.vplCount = 256;
          s.clampBound = 20.0f;
          s.visibility = VisibilityMethod::Ism;
          // A small point budget (256 points per VPL) and small tiles make ISM's failures visible at a glance.
          s.ismPointBudget = 1 << 16;
          s.ismTileSize = 32;
        },
        "Each VPL's visibility comes from a few hundred splatted points instead of the triangles (Ritschel et al. "
        "2008). The signed difference against the exact render of the same VPLs is the failure map: red where light "
        "leaks through the wall between the rooms, where too few points covered the wall near a VPL, blue where "
        "splats and the depth bias shadow surfaces that meet. Raise the ISM points and the tile size, or switch the "
        "VPL visibility to cube shadow maps, and the map fades."));
    // --- really many lights (docs/methods.md "Lightcuts", "The preview at many VPLs") -----------------------------
    list.push_back(make(
        {"Many VPLs at the cost of a few (lightcuts)", "cornell-box.gltf", ViewMode::Reference, PresetOffline::Chosen,
         false, false, false, false, Method::Lightcuts},
        [](Settings& s) {
          s.vplCount = 1000;
          s.clampBound = kInfinity;
          // The preview's cost stays that of 256 lights whatever N (a per-view cut, representative_lights.h).
          s.previewRepresentatives = 256;
        },
        "The offline pass renders lightcuts (Walter et al. 2005) over 1000 unbounded VPLs: splotches in the corners, "
        "as with plain VPLs. Raise the VPL count to 10000, then 100000, and render again: the splotches fade, since "
        "each VPL carries less power, while the time hardly grows: each pixel sums a cut of the light tree, a few "
        "hundred clusters whatever N (the cut-size view, key 7, maps it; the cut statistics are under the timings). "
        "The preview gathers 256 representatives of a per-view cut of the same tree, so it keeps its cost too."));
    // --- participating media (cornell-fog: the Cornell box filled with bluish haze, docs/scenes.md) --------------
    list.push_back(make(
        {"Splotches in fog", "cornell-fog.gltf", ViewMode::Split, PresetOffline::ExactVpl},
        [](Settings& s) {
          s.vplCount = 64;
          s.clampBound = kInfinity;
        },
        "Light paths scatter in the fog and leave medium VPLs there, each lighting the air and the walls around it "
        "with 1/d^2 and no cosine to soften it (the phase function is all there is). The preview (left) and the "
        "exact render of the same VPLs (right) agree: bright blobs float in the haze where a medium VPL sits close "
        "to what the camera sees, besides the corner splotches of the surface VPLs. More VPLs make the blobs "
        "smaller, not gone."));
    list.push_back(make(
        {"Bounded fog darkens", "cornell-fog.gltf", ViewMode::Difference, PresetOffline::Reference, true},
        [](Settings& s) {
          s.vplCount = 256;
          s.clampBound = 25.0f;
        },
        "The bound b = 25 clamps 1/d^2 in the fog as on surfaces: every VPL closer than 1/sqrt(b) = 0.2 m to a lit "
        "point gives less than it should. The signed difference against the path-traced reference is blue (too "
        "dark) all through the haze, not only in the corners: in a medium every point has VPLs all around it, so "
        "the bound takes a share of the light everywhere. Rendered exactly (Render exact VPL in the offline panel), "
        "the same VPLs report the share of the energy the bound removed."));
    list.push_back(make(
        {"Approximate compensation", "cornell-fog.gltf", ViewMode::Split, PresetOffline::Chosen, false, false, false,
         false, Method::VplAbc},
        [](Settings& s) {
          s.vplCount = 256;
          s.clampBound = 25.0f;
        },
        "Engelhardt et al. 2012 add back what the bound removed with one extra bounce per shading point: a point "
        "sampled inside the bound's ball, the medium there taken as homogeneous and unoccluded, lit by the VPLs "
        "with the residual max(0, G - b). Left, the preview with the bound alone; right, the exact render with that "
        "compensation (vpl-abc): most of the missing haze comes back, without Kollig-Keller's recursive paths. "
        "What it misses is light that needs more than one bounce inside 1/sqrt(b), or a wall inside the ball."));
    list.push_back(make(
        {"Ray lights", "cornell-fog.gltf", ViewMode::Split, PresetOffline::Chosen, false, false, false, false,
         Method::Vrl},
        [](Settings& s) {
          s.vplCount = 64;
          s.clampBound = kInfinity;
        },
        "Virtual ray lights (Novak et al. 2012a): instead of points where light scattered, each light path's "
        "segment through the fog lights the medium all along its length. Integrating along a ray and a camera "
        "ray turns the medium VPLs' 1/d^2 into a far weaker singularity, so the floating blobs of 'Splotches in "
        "fog' (still in the preview on the left) are gone at the same number of light paths, without a bound. On "
        "the right, the CPU VRL render (vrl, pass by pass); the surfaces are still lit by unbounded surface VPLs, so "
        "their corner splotches stay. The offline panel also offers vbl: beams that shrink pass after pass."));
    // --- heterogeneous media (cornell-smoke: a plume from an OpenVDB grid in the Cornell box, scripts/make_smoke.py) -
    list.push_back(make(
        {"Smoke: bounded versus compensated", "cornell-smoke.gltf", ViewMode::Split, PresetOffline::Chosen, false,
         false, false, false, Method::VplAbc, kSmokeDivider},
        [](Settings& s) {
          s.vplCount = 256;
          s.clampBound = 25.0f;
        },
        "The fog presets' bound b = 25 in smoke whose density varies, read from an OpenVDB grid (its box is outlined "
        "in the view; the divider crosses it). Left, the preview with the bound alone; right, the exact render with "
        "approximate compensation (vpl-abc). In the plume light scatters again within centimetres, so the VPLs it "
        "holds sit close to the points they light: the bound takes about half of the plume's indirect light (close to "
        "a fifth of the whole image's), so the plume is darker than it should be. vpl-abc's one extra bounce takes the "
        "medium inside the bound's ball, 1/sqrt(b) = 0.2 m, as homogeneous with the density at the shading point "
        "(Engelhardt et al. 2012) and returns that light. The media panel's density scale thickens or thins the smoke; "
        "both sides follow."));
    return list;
  }();
  return presets;
}

const TeachingPreset* findPreset(const std::string& name) {
  for (const TeachingPreset& p : teachingPresets())
    if (p.name == name) return &p;
  return nullptr;
}

std::string unknownPresetMessage(const std::string& name) {
  std::string message = "no preset named '" + printable(name) + "'; the presets are:";
  for (const TeachingPreset& p : teachingPresets()) message += "\n  " + p.name;
  return message;
}

std::string presetDescription(const TeachingPreset& p) {
  std::string started;
  if (p.offline == PresetOffline::Reference) started = "renders the path-traced reference";
  if (p.offline == PresetOffline::ExactVpl) started = "renders the exact VPL render";
  if (p.offline == PresetOffline::Chosen)
    started = "renders " + std::string(renderMethod(p.offlineMethod).label) + " (" + toString(p.offlineMethod) + ")";
  if (p.animateLight) started += std::string(started.empty() ? "" : ", ") + "animates the light";
  std::string text = "Preset: " + p.name + " (" + p.scene + ", " + toString(p.view) + " view";
  if (!started.empty()) text += "; " + started;
  return text + ")\n" + p.explanation;
}

glm::vec3 lightAnimationStep(float& phase, float sceneDiagonal) {
  const float radius = 0.02f * sceneDiagonal;
  const float before = phase;
  phase += 6.2831853f / static_cast<float>(kLightAnimationFrames);
  return radius * glm::vec3(std::cos(phase) - std::cos(before), 0.0f, std::sin(phase) - std::sin(before));
}

}  // namespace vplab::ui
