#pragma once
// Every tunable number of vplab in one place. One Settings value drives the GL preview and the Embree pass, so both
// render the same thing; the editor, the CLI and the tests all go through validateSettings().

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace vplab {

/// What the offline pass renders.
enum class Method {
  Reference,  ///< path-traced reference (Embree)
  Vpl,        ///< instant radiosity with exact visibility and the bounded geometry term G_b
  VplKK,      ///< Vpl plus Kollig-Keller path-traced bias compensation (unbiased)
  Vsl,        ///< virtual spherical lights of radius vslRadius
};

/// How the GL preview answers the visibility between a VPL and a shading point (docs/methods.md "VPL visibility").
enum class VisibilityMethod {
  Cube,  ///< one rasterised cube shadow map per VPL: sharp, the reference for the others; costs VPLs x triangles
  Ism,   ///< imperfect shadow maps (Ritschel et al. 2008): a point-splatted paraboloid tile per VPL, cost independent
         ///< of the triangle count; leaks light through thin occluders and near the VPL
};

/// Which part of the radiance an image holds. VPL methods approximate only the indirect part.
enum class Components { All, Direct, Indirect };

/// What is added around a loaded scene before rendering (renderer/scene/staging.h).
enum class Stage {
  Auto,    ///< the studio for a scene without lights, nothing otherwise
  None,    ///< the scene as loaded (one without lights renders black, with a warning)
  Studio,  ///< the studio always: ground, backdrop, an area light sized from the bounds, camera framed on the model
};

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();

struct Settings {
  // --- image and sampling ----------------------------------------------------------------------------------
  /// Image width in pixels [1, 16384]. Default 256.
  int width = 256;
  /// Image height in pixels [1, 16384]. Default 256.
  int height = 256;
  /// Seed of every random and quasi-random sequence. Same seed, scene and settings => same image. Default 1.
  uint32_t seed = 1;
  /// Worker threads for CPU passes; 0 = all cores. [0, 1024]. Default 0.
  int threads = 0;
  /// Display exposure in stops (PNG and preview tonemapping only, never the linear images). [-20, 20]. Default 0.
  float exposure = 0.0f;

  /// Staging of the loaded scene: Auto, None or Studio (see Stage). Both passes and the editor apply it the same
  /// way. Default Auto.
  Stage stage = Stage::Auto;

  // --- path-traced reference ---------------------------------------------------------------------------------
  /// Samples per pixel of the reference and of the stochastic VPL variants [1, 1<<20]. Default 64.
  int samplesPerPixel = 64;
  /// Maximum path length in bounces for the reference (1 = direct light only) [1, 1024]. Default 32.
  int maxDepth = 32;
  /// Radiance components written by the offline pass. Default All.
  Components components = Components::All;

  // --- VPL generation (MANYLIGHTS.md section 2) -------------------------------------------------------------
  /// Number of VPLs to generate (accepted VPLs when rejection is on) [0, 1<<20]. Default 256.
  int vplCount = 256;
  /// Maximum VPL bounce index: VPLs are stored at bounces 1..vplMaxBounces [1, 64]. A VPL of bounce k lights x1
  /// through k + 1 reflections, so the default 31 = maxDepth - 1 makes the VPL methods sum the same paths as the
  /// reference (Russian roulette ends most paths long before). Default 31.
  int vplMaxBounces = 31;

  // --- rejection of unimportant VPLs, Georgiev & Slusallek 2010 (section 3) --------------------------------
  /// Enables rejection sampling of VPL candidates. Default off.
  bool rejection = false;
  /// epsilon in p_i = min(Phi_i / Phi_v + epsilon, 1) [0, 1]. 0 rejects VPLs that miss every sample point.
  /// Default 0.1.
  float rejectionEpsilon = 0.1f;
  /// Pilot VPLs that estimate Phi_v [1, 65536]. Default 64.
  int rejectionPilotVpls = 64;
  /// Camera-visible sample points the importance is measured at [1, 65536]. Default 256.
  int rejectionSamplePoints = 256;
  /// Cap on candidates traced, as a multiple of vplCount [1, 10000]; reaching it is reported. Default 100.
  int rejectionMaxCandidateFactor = 100;

  // --- bounded geometry term (section 4) and bias compensation (sections 5, 6) ------------------------------
  /// Clamp bound b on G = cos1 cos2 / d^2, in 1/m^2 [0, inf]; inf = no clamp. Default inf.
  float clampBound = kInfinity;
  /// Screen-space bias compensation steps in the GL preview (Novak et al. 2011) [0, 2]. Default 0.
  int ssbcSteps = 0;
  /// Multi-resolution rings: the compensation's rings at least 4 px away from a pixel are evaluated at every 4th pixel
  /// in x and y and interpolated along surfaces (pixels at creases and silhouettes evaluate them themselves); the
  /// nearer rings, where the residual is largest, stay per pixel. About 2.4x cheaper at 640x480 for 0.8 percentage
  /// points less recovered energy on the Cornell box (tests/gl_accuracy_test.cpp compares both). Default on.
  bool ssbcCoarseRings = true;

  // --- virtual spherical lights, Hasan et al. 2009 (section 7) ----------------------------------------------
  /// VSL radius r in scene units (metres) [0, inf); 0 = point VPLs. Default 0.
  float vslRadius = 0.0f;
  /// When on, each VSL's radius is derived from the local VPL density (vslRadius then scales it). Default off.
  bool vslRadiusFromDensity = false;
  /// Samples per VSL and shading point of the exact CPU estimator: one-sample MIS over the cone and the BRDFs of the
  /// glossy ends (pure-Lambert pairs whose cone no surface cuts take none: closed form) [1, 256]. The GL preview
  /// evaluates the integral without samples. Default 4.
  int vslSamples = 4;

  // --- GL preview (section 8) -------------------------------------------------------------------------------
  /// Shadow-mapped samples on area lights for the preview's direct light [1, 4096]. Default 64.
  int directLightSamples = 64;
  /// Interleaved sampling: VPLs split into k x k subsets, k = 1 is off [1, 8]. Default 1.
  int interleave = 1;
  /// Resolution of each VPL's shadow map, in texels per side [16, 2048]. Default 256.
  int shadowMapSize = 256;
  /// Depth bias of VPL shadow lookups, as a fraction of the scene diagonal [0, 0.1]. Default 0.002.
  float shadowBias = 0.002f;
  /// VPL visibility technique of the preview. Default Cube.
  VisibilityMethod visibility = VisibilityMethod::Cube;
  /// Imperfect shadow maps: texels per side of each VPL's paraboloid tile, a power of two [16, 512]. Default 64
  /// (docs/benchmarks.md "Imperfect shadow maps": 128 costs 4x the tile work for little accuracy at 256 VPLs).
  int ismTileSize = 64;
  /// Imperfect shadow maps: surface points sampled once per scene and shared among the VPLs (each splats about
  /// ismPointBudget / N of them) [1024, 1<<25]. Default 1<<21 (docs/benchmarks.md "Imperfect shadow maps").
  int ismPointBudget = 1 << 21;
};

/// Checks every field against its documented range. Returns one message per problem (field name, value, range);
/// an empty list means the settings are usable. Never modifies the settings.
std::vector<std::string> validateSettings(const Settings& settings);

/// Throws std::invalid_argument with all problems joined when validateSettings() finds any.
void requireValidSettings(const Settings& settings);

const char* toString(Method method);
const char* toString(Components components);
const char* toString(Stage stage);
const char* toString(VisibilityMethod visibility);
/// Parses "cube", "ism"; returns false on anything else.
bool parseVisibilityMethod(const std::string& text, VisibilityMethod& out);
/// Parses "reference", "vpl", "vpl-kk", "vsl"; returns false on anything else.
bool parseMethod(const std::string& text, Method& out);
/// Parses "all", "direct", "indirect"; returns false on anything else.
bool parseComponents(const std::string& text, Components& out);
/// Parses "auto", "none", "studio"; returns false on anything else.
bool parseStage(const std::string& text, Stage& out);

}  // namespace vplab
