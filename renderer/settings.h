#pragma once
// Every tunable number of vplab in one place. One Settings value drives the GL preview and the Embree pass, so both
// render the same thing; the editor, the CLI and the tests all go through validateSettings().

#include <cstdint>
#include <limits>
#include <string>
#include <variant>
#include <vector>

namespace vplab {

/// What the offline pass renders.
enum class Method {
  Reference,  ///< path-traced reference (Embree)
  Vpl,        ///< instant radiosity with exact visibility and the bounded geometry term G_b
  VplKK,      ///< Vpl plus Kollig-Keller path-traced bias compensation (unbiased)
  Vsl,        ///< virtual spherical lights of radius vslRadius
  VplAbc,     ///< Vpl plus approximate bias compensation in media (Engelhardt et al. 2012): one residual bounce,
              ///< the medium taken as homogeneous and unoccluded inside the bound's ball
  Vrl,        ///< virtual ray lights (Novak et al. 2012a): the light paths' media segments light the media
  Vbl,        ///< progressive virtual beam lights (Novak et al. 2012b): VRLs of shrinking radius, pass after pass
  Lvl,        ///< bounded global VPLs plus local virtual lights per pixel tile carrying the residual (Davidovic et
              ///< al. 2010): Kollig-Keller's compensation vertices shared by the pixels of a tile
  Lightcuts,  ///< Vpl's bounded sum through a cut of a light tree (Walter et al. 2005): sublinear in the VPLs
  LightcutsKK,  ///< Lightcuts plus vpl-kk's exact Kollig-Keller compensation of the residual
  Mrcs,       ///< Vpl's bounded sum over cluster representatives found by matrix row-column sampling (Hasan et al.
              ///< 2007): a few pixels against every VPL, the VPLs clustered by those rows
};

/// How the GL preview answers the visibility between a VPL and a shading point (docs/methods.md "VPL visibility").
enum class VisibilityMethod {
  Cube,  ///< one rasterised cube shadow map per VPL: sharp, the reference for the others; costs VPLs x triangles
  Ism,   ///< imperfect shadow maps (Ritschel et al. 2008): a point-splatted paraboloid tile per VPL, cost independent
         ///< of the triangle count; leaks light through thin occluders and near the VPL
  Auto,  ///< Cube while triangles x VPLs is at most kAutoCubeTriangleVpls, else Ism (resolveVisibility)
};

/// The largest triangles x VPLs for which `auto` keeps cube maps: there the first preview with cube maps costs about
/// what it costs with ISM, and above it the cube maps' cost, which grows with the product, soon dominates
/// (docs/benchmarks.md "VPL visibility: auto"). VPLAB_AUTO_CUBE_LIMIT is the same number as help texts print it.
inline constexpr double kAutoCubeTriangleVpls = 1 << 23;
#define VPLAB_AUTO_CUBE_LIMIT "2^23"
static_assert([] {
  int exponent = 0;
  for (const char* c = VPLAB_AUTO_CUBE_LIMIT + 2; *c; ++c) exponent = 10 * exponent + (*c - '0');
  return static_cast<double>(1LL << exponent) == kAutoCubeTriangleVpls;
}(), "VPLAB_AUTO_CUBE_LIMIT names kAutoCubeTriangleVpls");

/// The technique the preview uses for `requested` on a scene of `triangles` triangles with `vplCount` VPLs: Cube or
/// Ism as asked, and for Auto the one its rule picks.
VisibilityMethod resolveVisibility(VisibilityMethod requested, std::size_t triangles, std::size_t vplCount);

/// How VPLs are generated (docs/methods.md, "VPL generation"; the list with names, labels and colours is
/// renderer/vpl/generation_methods.h, the one place a new method is added).
enum class VplGeneration {
  Light,          ///< light tracing (Keller 1997), optionally with rejection (Georgiev & Slusallek 2010)
  Bidirectional,  ///< bidirectional instant radiosity (Segovia et al. 2006): camera-side candidates, resampled
  Metropolis,     ///< Metropolis instant radiosity (Segovia et al. 2007): light paths from a Markov chain
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
  /// Samples per pixel of the path-traced reference [1, 1<<20]. Default 64.
  int samplesPerPixel = 64;
  /// Samples per pixel of the exact VPL render (vpl, vpl-kk, vsl), in the editor beside the preview and in
  /// `vplab render` [1, 1<<20]: every sample already sums every VPL with exact visibility, so few suffice (they
  /// anti-alias and average the VSL and Kollig-Keller samples), where the reference needs samplesPerPixel.
  /// Default 4.
  int exactSamplesPerPixel = 4;
  /// Maximum path length in bounces for the reference (1 = direct light only) [1, 1024]. Default 32.
  int maxDepth = 32;
  /// Radiance components written by the offline pass. Default All.
  Components components = Components::All;

  // --- VPL generation (docs/methods.md, "VPL generation") ---------------------------------------------------
  /// How VPLs are generated. Default Light (the plain method, the baseline the others are measured against).
  VplGeneration generation = VplGeneration::Light;
  /// Number of VPLs to generate: the expected count (accepted VPLs with rejection; VPLs kept from the bidirectional
  /// pool; about this many from the Metropolis chains) [0, 1<<20]. Default 256.
  int vplCount = 256;
  /// Maximum VPL bounce index: VPLs are stored at bounces 1..vplMaxBounces [1, 64]. A VPL of bounce k lights x1
  /// through k + 1 reflections, so the default 31 = maxDepth - 1 makes the VPL methods sum the same paths as the
  /// reference (Russian roulette ends most paths long before). Default 31.
  int vplMaxBounces = 31;
  /// Camera-visible points at which a VPL's importance (its contribution to the image) is measured, by rejection,
  /// bidirectional resampling and the Metropolis target [1, 65536]: one primary hit per cell of a grid over the
  /// image. More points = a better importance estimate at a cost linear in the count. Default 256.
  int importancePoints = 256;

  // --- rejection of unimportant VPLs, Georgiev & Slusallek 2010 (light tracing only) ----------------------------
  /// Enables rejection sampling of light-traced VPL candidates. Only with generation = Light: the other methods
  /// already choose their VPLs by the same importance, so rejection would accept nearly all of them. Default off.
  bool rejection = false;
  /// epsilon in p_i = min(Phi_i / Phi_v + epsilon, 1) [0, 1]. 0 rejects VPLs that miss every importance point.
  /// Default 0.1.
  float rejectionEpsilon = 0.1f;
  /// Pilot VPLs that estimate Phi_v [1, 65536]. Phi_v is a mean of a heavy-tailed quantity: its relative error is
  /// about the coefficient of variation of Phi_i / sqrt(this), so a few hundred pilot VPLs keep the acceptance rate
  /// within a few percent across seeds; the pilot costs importancePoints shadow rays per VPL. Default 1024.
  int rejectionPilotVpls = 1024;
  /// Cap on candidates traced, as a multiple of vplCount [1, 10000]; reaching it is reported. Default 100.
  int rejectionMaxCandidateFactor = 100;

  // --- bidirectional instant radiosity, Segovia et al. 2006 -------------------------------------------------
  /// Candidates per VPL kept: the pool (light-traced and camera-side candidates) holds about this times vplCount
  /// candidates, from which exactly vplCount are resampled [1, 256]. A larger pool follows the importance more
  /// closely at a cost linear in the pool (importancePoints shadow rays per candidate); about 1/this of the pool is
  /// kept. Default 4.
  int birCandidateFactor = 4;
  /// Share of the pool's candidates that come from light tracing, in (0, 1]; the rest start from camera points.
  /// Light-traced candidates are the only source of VPLs beyond the first bounce and of light the camera points do
  /// not see; camera-side candidates put first-bounce VPLs where the camera looks. Default 0.5 (Segovia et al.).
  float birLightShare = 0.5f;
  /// Defensive share epsilon of the resampling [0, 1]: a candidate's selection weight is its importance relative to
  /// the mean plus epsilon times its flux relative to the mean, so a VPL that no importance point sees but that
  /// carries light can still be chosen (unbiased for epsilon > 0). Default 0.1.
  float birEpsilon = 0.1f;

  // --- Metropolis instant radiosity, Segovia et al. 2007 ----------------------------------------------------
  /// Independent Markov chains, at most [1, 4096]. Each chain records its start, a bootstrap path drawn in
  /// proportion to the target: independent of the other starts and already distributed as the target, where a
  /// mutation's proposal is a perturbed copy of its chain's state. So as many chains run as the VPL budget holds
  /// start paths, up to this many; mutations take the rest of the budget. Default 256, about the bootstrap's
  /// effective size under the target (195 of 1024 paths on two-rooms, 462 on the Cornell box): more starts than that
  /// repeat bootstrap paths. On two-rooms (320x240, 256 VPLs, 64 seeds, 4 burn-in states) the 4x4-block relMSE
  /// is 0.39x light tracing's with as many chains as the budget holds starts, against 0.60x with 16 chains and
  /// mutations for the rest (docs/methods.md).
  int mirChains = 256;
  /// Probability of a large step (fresh random numbers) instead of a small perturbation, in (0, 1]. Large steps
  /// find new regions; small steps explore around a found path. Default 0.3 (Kelemen et al. 2002).
  float mirLargeStepProbability = 0.3f;
  /// Mutations before each chain records its start [0, 100000]; the state they reach is recorded as the start.
  /// The start path is drawn in proportion to the target among the bootstrap paths, so no burn-in is needed for the
  /// estimate's expectation; a few mutations move each chain off its bootstrap path (chains that drew the same one
  /// part) to a path of its own, still distributed as the target. On two-rooms (320x240, 256 VPLs, 64 seeds) the
  /// 4x4-block relMSE is 0.64x light tracing's with 0 states, 0.48x with 4, 0.46x with 8 and 0.41x with 16, for 62,
  /// 84, 95 and 132 ms of generation against a render of about 1.3 s. Default 8.
  int mirBurnIn = 8;
  /// Independent light paths that estimate the normalisation b = E[f] and seed the chains [16, 1<<20]. b's relative
  /// error is about the target's coefficient of variation / sqrt(this). Default 1024.
  int mirBootstrapPaths = 1024;
  /// Defensive share epsilon of the target [0, 1]: f = importance / mean + epsilon * flux / mean, so paths that light
  /// nothing the importance points see are still visited (unbiased for epsilon > 0). Default 0.1.
  float mirEpsilon = 0.1f;

  // --- bounded geometry term (section 4) and bias compensation (sections 5, 6) ------------------------------
  /// Clamp bound b on G = cos1 cos2 / d^2, in 1/m^2 [0, inf]; inf = no clamp. Default inf.
  float clampBound = kInfinity;
  /// The clamp bound relative to the scene, in units of 1/diagonal^2 [0, inf]: when > 0, b = this / diagonal^2 of
  /// the scene's geometry (its triangles' bounds) replaces clampBound once the scene is known (resolveClampBound). G's unit is 1/m^2, so b = 20
  /// bounds a 1.5 m box and clamps nothing on a model 700 units wide; 20 / diagonal^2 does the same to both. 0 = use
  /// clampBound. Default 0.
  float clampBoundRelative = 0.0f;
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
  /// evaluates the integral without samples. Default 2: one sample from the cone and one from a glossy end's BRDF,
  /// on average, keeps the exact VSL render within 3x the point-VPL render (docs/benchmarks.md).
  int vslSamples = 2;

  // --- local virtual lights, Davidovic et al. 2010 (section 21) --------------------------------------------------
  /// Side of the square pixel tiles whose pixels share local lights [1, 64]; each tile is split further into groups
  /// of pixels with the same material and similar normals. 1 = one pixel per tile: Kollig-Keller's compensation.
  /// Default 8 (docs/benchmarks.md "Local virtual lights").
  int lvlTileSize = 8;
  /// Local lights per tile and camera sample, shared among the tile's groups by their pixel counts (at least one
  /// each) [1, 4096]. Each costs one gather of the global VPLs at its vertex and one shadow ray per pixel of its
  /// group. Default 32 (docs/benchmarks.md "Local virtual lights").
  int lvlLightsPerTile = 32;

  // --- lightcuts, Walter et al. 2005 (section 23) -----------------------------------------------------------------
  /// Relative error threshold of a cut: a light-tree node is refined while its error bound exceeds this times the
  /// luminance of the receiver's current estimate [0, 1]; 0 refines every node that can contribute down to its VPLs
  /// (the exact sum). Default 0.01 (docs/benchmarks.md "Lightcuts": mean per-pixel error about 1 %).
  float lightcutError = 0.01f;
  /// Largest cut, in light-tree nodes per receiver [1, 1<<24]; a cut that reaches it stops refining (counted).
  /// Default 1000 (Walter et al. 2005).
  int lightcutMax = 1000;

  // --- matrix row-column sampling, Hasan et al. 2007 (section 23) --------------------------------------------------
  /// Rows: pixels rendered against every VPL with exact visibility, whose values cluster the VPLs [1, 4096]. Costs
  /// rows x VPLs shadow rays and as many floats of memory. Default 300 (Hasan et al. 2007).
  int mrcsRows = 300;
  /// Clusters of VPLs, each rendered through one representative per pixel sample [1, 1<<20]. Default 900 (Hasan et
  /// al. 2007).
  int mrcsClusters = 900;

  // --- virtual ray lights and progressive virtual beam lights, Novak et al. 2012a, 2012b (sections 19, 20) -----
  /// Samples per VRL and pixel sample of the exact CPU VRL/VBL render (each for the camera ray's media part and
  /// for the surface point) [1, 256]. Default 1: a VRL costs about as much as a VPL then, and more samples per VRL
  /// lower the error less than more light paths in the same time (docs/benchmarks.md "Participating media").
  int vrlSamples = 1;
  /// Radius r_1 of the first pass's virtual beams, in metres [0, inf); 0 = derive: 2 % of the scene diagonal.
  /// Default 0.
  float beamRadius = 0.0f;
  /// Passes of the progressive virtual beam render, each with a fresh VPL/VRL set (seed + pass) [1, 4096].
  /// Default 16.
  int beamPasses = 16;
  /// Radius shrink alpha of the beams: r_i = r_1 (i + 1)^((alpha - 1) / 2), in (0, 1]; 1 keeps the radius.
  /// Default 0.7.
  float beamShrink = 0.7f;

  // --- GL preview (section 8) -------------------------------------------------------------------------------
  /// Shadow-mapped samples on area lights for the preview's direct light [1, 4096]. Default 64.
  int directLightSamples = 64;
  /// Interleaved sampling: VPLs split into k x k subsets, k = 1 is off [1, 8]. Default 1 (4 in `vplab preview` and
  /// the editor: previewDefaultSettings).
  int interleave = 1;
  /// The indirect light (the VPL gather) and its compensation are computed at 1/s of the image's width and height
  /// and upsampled along surfaces (preview/upsample.frag.glsl); the G-buffer, the direct light and emission stay per
  /// pixel [1, 4]. Both passes' work scales with their pixels, so s = 2 does about a quarter of it. Default 1 (2 in
  /// `vplab preview` and the editor: previewDefaultSettings).
  int indirectDownscale = 1;
  /// Resolution of each VPL's shadow map, in texels per side [16, 2048]. Default 256 (128 in `vplab preview` and the
  /// editor: previewDefaultSettings).
  int shadowMapSize = 256;
  /// Texels per side of a point or spot light's shadow-map face in the preview, a power of two [16, 4096]; an
  /// area-light cell's faces have half as many, a directional light's map twice (LightMapSizes,
  /// renderer/gl/direct_pass.h). Default 1024.
  int lightShadowMapSize = 1024;
  /// Depth bias of VPL shadow lookups, as a fraction of the scene diagonal [0, 0.1]. Default 0.002.
  float shadowBias = 0.002f;
  /// VPL visibility technique of the preview. Default Auto: cube maps on small scenes, ISM where they would cost
  /// seconds (resolveVisibility).
  VisibilityMethod visibility = VisibilityMethod::Auto;
  /// Imperfect shadow maps: texels per side of each VPL's paraboloid tile, a power of two [16, 512]. Default 64
  /// (docs/benchmarks.md "Imperfect shadow maps": 32 darkens by 4-12 %; 128 halves the error behind a door but adds
  /// about 100 ms to every VPL change at 256 VPLs).
  int ismTileSize = 64;
  /// Imperfect shadow maps: surface points sampled once per scene and shared among the VPLs (each splats about
  /// ismPointBudget / N of them) [1024, 1<<25]. Default 1<<20, about a point per tile texel at 256 VPLs
  /// (docs/benchmarks.md "Imperfect shadow maps": twice as many cost twice the splatting, 40 ms more per VPL change,
  /// for 10-20 % less error).
  int ismPointBudget = 1 << 20;
  /// The preview gathers at most this many lights [16, 65536]: a larger VPL set is reduced, per view, to a light-tree
  /// cut of this many clusters, each lit by one representative VPL carrying its cluster's power
  /// (renderer/offline/representative_lights.h); a set of at most this many VPLs is gathered as it is. Default 1024.
  int previewRepresentatives = 1024;
  /// The preview reads a density grid from a NanoVDB storage buffer even where a 3D texture would hold it (by
  /// default only a grid no 3D texture of the context holds goes there: renderer/gl/density_grid_storage.h). For
  /// comparing the two; the texture is faster (docs/methods.md "Smoke in the preview"). Default false.
  bool previewGridInBuffer = false;
};

// --- the settings table: one row per member -------------------------------------------------------------------
// Each setting has one name, its member name, which is also its JSON key and editor script verb; its command-line
// flag is that name in kebab case (clampBound -> --clamp-bound). The table below feeds all of them: JSON reading
// and writing, the script verbs, each command's flags and --help, and validateSettings(). Adding a setting is adding
// the member above and one row in settingsTable() (renderer/settings.cpp).

/// The passes a setting acts on, as a bit set: a command offers exactly the settings of the passes it runs.
enum SettingUse : unsigned {
  kUseImage = 1u << 0,       ///< every rendering command: image size, seed, threads, exposure
  kUseReference = 1u << 1,   ///< the path-traced reference
  kUseGeneration = 1u << 2,  ///< VPL generation (render, preview)
  kUseCpuVpl = 1u << 3,      ///< the exact CPU VPL render
  kUseGl = 1u << 4,          ///< the GL preview
};

/// An enum member, seen as the index of its value: names[i] is toString(E(i)).
struct SettingChoice {
  std::vector<std::string> names;
  int (*get)(const Settings&);
  void (*set)(Settings&, int);
};

/// What the range [min, max] of a number means beyond itself.
enum class SettingBound {
  Closed,      ///< min <= value <= max
  AboveMin,    ///< min < value <= max: a share or probability that must be positive
  PowerOfTwo,  ///< min <= value <= max and a power of two
};

/// Where one setting lives in Settings and how it is typed.
using SettingMember =
    std::variant<int Settings::*, uint32_t Settings::*, float Settings::*, bool Settings::*, SettingChoice>;

struct SettingInfo {
  const char* key;       ///< the member name: JSON key, script verb, and (kebab case) the command-line flag
  SettingMember member;  ///< where the value lives
  double min = 0.0;      ///< range of a number, inclusive unless bound says otherwise (ignored for bool and choice)
  double max = 0.0;
  const char* valueName;    ///< what --help shows for the value: "N", "1/m^2"
  const char* help;         ///< one line with the unit; --help appends the command's own default
  unsigned use;             ///< SettingUse bits
  bool commandLine = true;  ///< false: no flag of its own (width and height are set together by --size WxH)
  SettingBound bound = SettingBound::Closed;
};

/// Every setting, in Settings member order.
const std::vector<SettingInfo>& settingsTable();
/// The row of a key (exact, case-sensitive), or nullptr.
const SettingInfo* findSetting(const std::string& key);
/// The command-line flag of a key, without the leading "--": "clampBound" -> "clamp-bound".
std::string settingFlag(const std::string& key);
/// The value as the user writes it: "0.25", "inf", "true", "indirect", "4000000000".
std::string formatSetting(const Settings& settings, const SettingInfo& info);
/// Sets one member from text as the user writes it (numbers, "inf", true/false/on/off/1/0, an enum name). Does not
/// check the range (validateSettings() does). Throws std::invalid_argument saying what was expected.
void parseSetting(Settings& settings, const SettingInfo& info, const std::string& text);

/// How validation messages name a setting: by key ("vplCount") or by flag ("--vpl-count"), whichever the user typed.
enum class SettingSpelling { Key, Flag };

/// Checks every member against its range in the table. Returns one message per problem (name, value, range), the
/// name spelled as asked; an empty list means the settings are usable. Never modifies the settings.
std::vector<std::string> validateSettings(const Settings& settings, SettingSpelling spelling = SettingSpelling::Key);

/// Throws std::invalid_argument with all problems joined when validateSettings() finds any.
void requireValidSettings(const Settings& settings);

/// The settings an offline render of `method` runs with: the reference takes samplesPerPixel, an exact VPL render
/// exactSamplesPerPixel (the editor's exact render and `vplab render` alike).
Settings offlineRenderSettings(const Settings& settings, Method method);

/// The defaults of the commands that show the GL preview (`vplab preview`, the editor) where the command line and a
/// settings file say nothing: the gather interleaved over 4 x 4 subsets and the indirect light on the half-resolution
/// grid. A cold 640x480 `vplab preview` takes about half the time of k = s = 1 and an edit in the editor a third to a
/// tenth (docs/benchmarks.md, "The cold headless preview" and "Editing in the editor"); the accuracy tests pin this
/// configuration against the CPU as they pin k = s = 1. The offline renders, the bench and the presets keep the
/// Settings defaults.
Settings previewDefaultSettings();

const char* toString(Method method);
const char* toString(Components components);
const char* toString(Stage stage);
const char* toString(VisibilityMethod visibility);

/// Sets clampBound from clampBoundRelative for a scene whose bounds' diagonal is `sceneDiagonal` (nothing when
/// clampBoundRelative is 0).
void resolveClampBound(Settings& settings, float sceneDiagonal);
/// Parses "cube", "ism"; returns false on anything else.
bool parseVisibilityMethod(const std::string& text, VisibilityMethod& out);
const char* toString(VplGeneration generation);
/// Parses the names of renderer/vpl/generation_methods.h ("light", "bidirectional", "metropolis").
bool parseGeneration(const std::string& text, VplGeneration& out);
/// Parses "reference", "vpl", "vpl-kk", "vsl"; returns false on anything else.
bool parseMethod(const std::string& text, Method& out);
/// Parses "all", "direct", "indirect"; returns false on anything else.
bool parseComponents(const std::string& text, Components& out);
/// Parses "auto", "none", "studio"; returns false on anything else.
bool parseStage(const std::string& text, Stage& out);

}  // namespace vplab
