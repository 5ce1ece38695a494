#include "app/settings_options.h"

#include "renderer/image/image_io.h"
#include "renderer/settings_json.h"

#include <cctype>

namespace vplab::cli {

std::vector<OptionSpec> imageOptions() {
  return {
      {"settings", "F.json", "settings file (keys as Settings members); other options override it"},
      {"size", "WxH", "image size in pixels (default 256x256)"},
      {"seed", "S", "seed of all random sequences (default 1)"},
      {"threads", "T", "worker threads, 0 = all cores (default 0)"},
      {"exposure", "EV", "PNG exposure in stops (default 0)"},
      {"stage", "auto|none|studio", "studio around the model: ground, backdrop, area light (default auto: only for a "
                                    "scene without lights)"},
  };
}

std::vector<OptionSpec> referenceOptions() {
  return {
      {"spp", "N", "samples per pixel (default 64)"},
      {"max-depth", "D", "maximum path length in bounces (default 32)"},
      {"components", "all|direct|indirect", "radiance components to render (default all)"},
  };
}

std::vector<OptionSpec> manyLightOptions() {
  return {
      {"generation", "light|bidirectional|metropolis", "how VPLs are generated (default light)"},
      {"vpls", "N", "number of VPLs (accepted ones with --reject; default 256)"},
      {"bounces", "K", "maximum VPL bounce (default 31 = max depth - 1)"},
      {"clamp", "b", "clamp bound b on the geometry term, 1/m^2, 'inf' = none (default inf)"},
      {"vsl-radius", "r", "virtual spherical light radius in metres, 0 = point VPLs (default 0)"},
      {"vsl-density", "", "derive each VSL radius from the local VPL density (scaled by --vsl-radius)"},
      {"vsl-samples", "N", "samples per VSL of the exact CPU render (default 2; the GL preview takes none)"},
      {"importance-points", "M", "camera-visible points importance is measured at (default 256)"},
      {"reject", "", "rejection of unimportant VPLs (Georgiev-Slusallek; --generation light only)"},
      {"epsilon", "e", "rejection epsilon in [0,1] (default 0.1)"},
      {"pilot-vpls", "N", "pilot VPLs for rejection (default 1024)"},
      {"max-candidates", "F", "candidate cap as a multiple of --vpls (default 100)"},
      {"bir-candidate-factor", "F", "bidirectional: candidates per kept VPL (default 4)"},
      {"bir-light-share", "s", "bidirectional: share of light-traced candidates in (0,1] (default 0.5)"},
      {"bir-epsilon", "e", "bidirectional: defensive share of the resampling in [0,1] (default 0.1)"},
      {"mir-chains", "C", "metropolis: independent Markov chains (default 16)"},
      {"mir-large-step-probability", "p", "metropolis: probability of a large step in (0,1] (default 0.3)"},
      {"mir-burn-in", "B", "metropolis: states discarded per chain (default 4)"},
      {"mir-bootstrap-paths", "N", "metropolis: paths estimating the normalisation (default 1024)"},
      {"mir-epsilon", "e", "metropolis: defensive share of the target in [0,1] (default 0.1)"},
      {"ssbc", "0|1|2", "screen-space bias compensation steps (GL preview; default 0)"},
      {"ssbc-coarse-rings", "0|1", "SSBC rings >= 4 px away on a 4 px grid, 0 = every pixel (GL preview; default 1)"},
      {"interleave", "k", "interleaved sampling k x k, 1 = off (GL preview; default 1)"},
      {"shadow-map-size", "S", "VPL shadow-map resolution (GL preview; default 256)"},
      {"shadow-bias", "B", "VPL shadow depth bias, fraction of the scene diagonal (default 0.002)"},
      {"direct-samples", "K", "shadow-mapped area-light samples (GL preview; default 64)"},
      {"visibility", "cube|ism", "VPL visibility: cube shadow maps or imperfect shadow maps (GL preview; default cube)"},
      {"ism-tile-size", "T", "imperfect shadow map tile, texels per side, power of two (GL preview; default 64)"},
      {"ism-points", "P", "imperfect shadow maps' surface point budget (GL preview; default 2097152)"},
  };
}

namespace {

// validateSettings() messages start with the Settings member; where the option is that member's name in kebab case
// (mirChains -> --mir-chains), the message names the option too.
std::string withFlagName(const std::string& problem) {
  std::string member = problem.substr(0, problem.find(' '));
  std::string flag;
  for (char c : member) {
    if (std::isupper(static_cast<unsigned char>(c))) {
      flag += '-';
      flag += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    } else {
      flag += c;
    }
  }
  for (const OptionSpec& o : manyLightOptions())
    if (flag == o.name) return "option --" + flag + ": " + problem;
  return problem;
}

}  // namespace

void applySettingsOptions(const CommandLine& cl, Settings& s) {
  if (auto file = cl.value("settings")) {
    try {
      loadSettingsFile(*file, s);
    } catch (const SettingsJsonError& e) {
      throw CliError(std::string("option --settings: ") + e.what());
    }
  }
  cl.getSize("size", s.width, s.height);
  if (cl.has("seed")) {
    int seed = cl.getInt("seed", 1);
    if (seed < 0) throw CliError("option --seed: must be >= 0");
    s.seed = static_cast<uint32_t>(seed);
  }
  s.threads = cl.getInt("threads", s.threads);
  s.exposure = cl.getFloat("exposure", s.exposure);
  if (auto st = cl.value("stage"); st && !parseStage(*st, s.stage))
    throw CliError("option --stage: '" + *st + "' is not auto, none or studio");
  s.samplesPerPixel = cl.getInt("spp", s.samplesPerPixel);
  s.maxDepth = cl.getInt("max-depth", s.maxDepth);
  if (auto c = cl.value("components"); c && !parseComponents(*c, s.components))
    throw CliError("option --components: '" + *c + "' is not all, direct or indirect");
  if (auto g = cl.value("generation"); g && !parseGeneration(*g, s.generation))
    throw CliError("option --generation: '" + *g + "' is not light, bidirectional or metropolis");
  s.vplCount = cl.getInt("vpls", s.vplCount);
  s.vplMaxBounces = cl.getInt("bounces", s.vplMaxBounces);
  s.clampBound = cl.getFloat("clamp", s.clampBound);
  s.vslRadius = cl.getFloat("vsl-radius", s.vslRadius);
  if (cl.has("vsl-density")) s.vslRadiusFromDensity = true;
  s.vslSamples = cl.getInt("vsl-samples", s.vslSamples);
  if (cl.has("reject")) s.rejection = true;
  s.rejectionEpsilon = cl.getFloat("epsilon", s.rejectionEpsilon);
  s.rejectionPilotVpls = cl.getInt("pilot-vpls", s.rejectionPilotVpls);
  s.importancePoints = cl.getInt("importance-points", s.importancePoints);
  s.rejectionMaxCandidateFactor = cl.getInt("max-candidates", s.rejectionMaxCandidateFactor);
  s.birCandidateFactor = cl.getInt("bir-candidate-factor", s.birCandidateFactor);
  s.birLightShare = cl.getFloat("bir-light-share", s.birLightShare);
  s.birEpsilon = cl.getFloat("bir-epsilon", s.birEpsilon);
  s.mirChains = cl.getInt("mir-chains", s.mirChains);
  s.mirLargeStepProbability = cl.getFloat("mir-large-step-probability", s.mirLargeStepProbability);
  s.mirBurnIn = cl.getInt("mir-burn-in", s.mirBurnIn);
  s.mirBootstrapPaths = cl.getInt("mir-bootstrap-paths", s.mirBootstrapPaths);
  s.mirEpsilon = cl.getFloat("mir-epsilon", s.mirEpsilon);
  s.ssbcSteps = cl.getInt("ssbc", s.ssbcSteps);
  s.ssbcCoarseRings = cl.getInt("ssbc-coarse-rings", s.ssbcCoarseRings ? 1 : 0) != 0;
  s.interleave = cl.getInt("interleave", s.interleave);
  s.shadowMapSize = cl.getInt("shadow-map-size", s.shadowMapSize);
  s.shadowBias = cl.getFloat("shadow-bias", s.shadowBias);
  s.directLightSamples = cl.getInt("direct-samples", s.directLightSamples);
  if (auto v = cl.value("visibility"); v && !parseVisibilityMethod(*v, s.visibility))
    throw CliError("option --visibility: '" + *v + "' is not cube or ism");
  s.ismTileSize = cl.getInt("ism-tile-size", s.ismTileSize);
  s.ismPointBudget = cl.getInt("ism-points", s.ismPointBudget);
  std::vector<std::string> problems = validateSettings(s);
  if (!problems.empty()) throw CliError(withFlagName(problems.front()));
}

void checkImageOutputs(const CommandLine& cl) {
  auto out = cl.value("out");
  auto png = cl.value("png");
  if (!out && !png) throw CliError("nothing to write: give --out FILE (and/or --png FILE)");
  if (out) imageFormatFromPath(*out);
  if (png && imageFormatFromPath(*png) != ImageFormat::Png) throw CliError("option --png: '" + *png + "' is not .png");
}

}  // namespace vplab::cli
