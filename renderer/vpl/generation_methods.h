#pragma once
// The VPL generation methods: the one list that every user of "a way to make VPLs" walks. Settings, JSON and the
// command line spell a method by its name here; vplab bench and the stability suite make their rows from
// generationVariants(); the editor's many-light panel and VPL overlay take labels from it (a method's colour is its
// place in benchMethodNames(), evaluation/sweep.h).
//
// Adding a method (docs/methods.md, "Adding a generation method"): a VplGeneration value in renderer/settings.h, its
// parameters as Settings members (validated in validateSettings, listed in settings_json.cpp and invalidation.cpp),
// a generate function over a GenerationContext that returns a VplSet (renderer/vpl/generation_detail.h), and one row
// in generationMethods() and generationVariants() (generation_methods.cpp). Nothing else names the methods.

#include "renderer/core/parallel.h"
#include "renderer/offline/embree_scene.h"
#include "renderer/offline/light_sampler.h"
#include "renderer/offline/offline_scene.h"
#include "renderer/scene/scene.h"
#include "renderer/settings.h"
#include "renderer/vpl/vpl.h"

#include <cstdint>
#include <string>
#include <vector>

namespace vplab {

/// What a generation method reads.
struct GenerationContext {
  const OfflineScene& offline;
  const Scene& scene;
  const EmbreeScene& embree;
  const LightSampler& lights;
  const Settings& settings;
  RenderControl* control = nullptr;
};

struct GenerationMethod {
  VplGeneration id;
  const char* name;         ///< spelling in Settings JSON, --generation and bench.csv
  const char* label;        ///< for people: the editor, chart legends, reports
  const char* citation;     ///< the paper it follows
  const char* summary;      ///< one sentence: where it puts VPLs
  bool usesImportance;      ///< measures importance at Settings::importancePoints camera points
  VplSet (*generate)(const GenerationContext& context);  ///< VPLs (radii and timing are filled by generateVpls)
};

/// Every generation method, in the order VplGeneration lists them.
const std::vector<GenerationMethod>& generationMethods();
const GenerationMethod& generationMethod(VplGeneration id);

/// A way to generate VPLs as the sweeps list it: a method, with rejection on or off (rejection applies to light
/// tracing only). The bench's and the stability suite's generation rows are exactly these.
struct GenerationVariant {
  const char* name;   ///< row name in bench.csv, flicker.csv and --methods ("vpl" is plain light tracing)
  const char* label;  ///< legend text
  VplGeneration generation;
  bool rejection;
};

const std::vector<GenerationVariant>& generationVariants();
/// The variant `settings` selects (generation and rejection).
const GenerationVariant& generationVariantOf(const Settings& settings);
/// The variant named `name`, or nullptr.
const GenerationVariant* findGenerationVariant(const std::string& name);
/// Sets generation and rejection to `variant`'s.
void applyGenerationVariant(const GenerationVariant& variant, Settings& settings);

/// One line for people: the method, VPLs kept of candidates, acceptance (with rejection also the pilot's prediction
/// and its spread), Metropolis mutation acceptance, generation time. Warnings are not included.
std::string describeVplStats(const VplStats& stats);

/// Whether the settings' VPLs depend on the camera-visible importance points (and so on the view and image size).
bool usesImportancePoints(const Settings& settings);

}  // namespace vplab
