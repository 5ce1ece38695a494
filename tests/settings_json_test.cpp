#include "renderer/settings_json.h"
#include "tests/test_tmp.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

namespace vplab {
namespace {

// Every message must name the offending key so that a typo in a file is found without guessing.
void expectErrorNaming(const std::string& json, const std::string& key) {
  Settings s;
  Settings before = s;
  try {
    applySettingsJson(json, s);
    FAIL() << "no error for " << json;
  } catch (const SettingsJsonError& e) {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
  EXPECT_EQ(settingsToJson(s), settingsToJson(before)) << "settings changed although the JSON was rejected";
}

TEST(SettingsJson, RoundTripsEveryMember) {
  Settings s;
  s.width = 97;
  s.height = 33;
  s.seed = 4000000000u;
  s.threads = 3;
  s.exposure = -1.5f;
  s.samplesPerPixel = 17;
  s.exactSamplesPerPixel = 3;
  s.maxDepth = 5;
  s.components = Components::Indirect;
  s.stage = Stage::Studio;
  s.vplCount = 1234;
  s.vplMaxBounces = 7;
  s.generation = VplGeneration::Light;
  s.rejection = true;
  s.rejectionEpsilon = 0.25f;
  s.birCandidateFactor = 3;
  s.birLightShare = 0.75f;
  s.birEpsilon = 0.125f;
  s.mirChains = 5;
  s.mirLargeStepProbability = 0.5f;
  s.mirBurnIn = 9;
  s.mirBootstrapPaths = 333;
  s.mirEpsilon = 0.375f;
  s.rejectionPilotVpls = 11;
  s.importancePoints = 99;
  s.rejectionMaxCandidateFactor = 42;
  s.clampBound = 3.75f;
  s.ssbcSteps = 2;
  s.ssbcCoarseRings = false;
  s.vslRadius = 0.0625f;
  s.vslRadiusFromDensity = true;
  s.vslSamples = 12;
  s.directLightSamples = 31;
  s.interleave = 4;
  s.indirectDownscale = 3;
  s.shadowMapSize = 128;
  s.lightShadowMapSize = 256;
  s.shadowBias = 0.01f;
  s.visibility = VisibilityMethod::Ism;
  s.clampBoundRelative = 12.5f;
  s.ismTileSize = 32;
  s.ismPointBudget = 5000;
  s.lightcutError = 0.125f;
  s.lightcutMax = 77;
  s.mrcsRows = 33;
  s.mrcsClusters = 99;
  s.previewRepresentatives = 300;
  s.previewGridInBuffer = true;

  Settings back;
  applySettingsJson(settingsToJson(s), back);
  EXPECT_EQ(settingsToJson(back), settingsToJson(s));
  EXPECT_EQ(back.seed, 4000000000u);
  EXPECT_EQ(back.components, Components::Indirect);
  EXPECT_EQ(back.stage, Stage::Studio);
  EXPECT_FLOAT_EQ(back.clampBound, 3.75f);
  EXPECT_FLOAT_EQ(back.clampBoundRelative, 12.5f);
  EXPECT_TRUE(back.vslRadiusFromDensity);
  EXPECT_EQ(back.visibility, VisibilityMethod::Ism);
  EXPECT_EQ(back.mirBootstrapPaths, 333);
  // The generation method is written by name and read back.
  s.rejection = false;
  s.generation = VplGeneration::Metropolis;
  std::string json = settingsToJson(s);
  EXPECT_NE(json.find("\"generation\": \"metropolis\""), std::string::npos) << json;
  applySettingsJson(json, back);
  EXPECT_EQ(back.generation, VplGeneration::Metropolis);
  EXPECT_THROW(applySettingsJson("{\"generation\": \"photons\"}", back), SettingsJsonError);
  EXPECT_THROW(applySettingsJson("{\"generation\": \"bidirectional\", \"rejection\": true}", back),
               SettingsJsonError);
  // Every key the writer emits must be one the reader knows, and none may be missing.
  EXPECT_EQ(settingsJsonKeys().size(), 54u);
}

TEST(SettingsJson, InfiniteClampIsWrittenAsStringAndReadBack) {
  Settings s;
  ASSERT_TRUE(std::isinf(s.clampBound));
  std::string json = settingsToJson(s);
  EXPECT_NE(json.find("\"clampBound\": \"inf\""), std::string::npos) << json;
  Settings bounded;
  bounded.clampBound = 1.0f;
  applySettingsJson(json, bounded);
  EXPECT_TRUE(std::isinf(bounded.clampBound));
}

TEST(SettingsJson, PartialObjectKeepsOtherMembers) {
  Settings s;
  s.vplCount = 77;
  applySettingsJson(R"({"clampBound": 0.5, "ssbcSteps": 1})", s);
  EXPECT_FLOAT_EQ(s.clampBound, 0.5f);
  EXPECT_EQ(s.ssbcSteps, 1);
  EXPECT_EQ(s.vplCount, 77);
}

TEST(SettingsJson, UnknownKeyIsAnErrorNamingIt) { expectErrorNaming(R"({"vplCount": 8, "clampBond": 1})", "clampBond"); }

TEST(SettingsJson, OutOfRangeValuesNameTheKey) {
  expectErrorNaming(R"({"ssbcSteps": 3})", "ssbcSteps");
  expectErrorNaming(R"({"clampBound": -1})", "clampBound");
  expectErrorNaming(R"({"interleave": 0})", "interleave");
  expectErrorNaming(R"({"shadowBias": 0.5})", "shadowBias");
}

TEST(SettingsJson, WrongTypesNameTheKey) {
  expectErrorNaming(R"({"vplCount": 3.5})", "vplCount");
  expectErrorNaming(R"({"vplCount": "many"})", "vplCount");
  expectErrorNaming(R"({"rejection": 1})", "rejection");
  expectErrorNaming(R"({"components": "some"})", "components");
  expectErrorNaming(R"({"stage": "garden"})", "stage");
  expectErrorNaming(R"({"seed": -1})", "seed");
  expectErrorNaming(R"({"clampBound": "big"})", "clampBound");
  expectErrorNaming(R"({"width": 1e12})", "width");
}

TEST(SettingsJson, MalformedTextAndNonObjectsAreErrors) {
  Settings s;
  EXPECT_THROW(applySettingsJson("{\"vplCount\": ", s), SettingsJsonError);
  EXPECT_THROW(applySettingsJson("[1, 2]", s), SettingsJsonError);
}

TEST(SettingsJson, SetFromTextParsesScriptValues) {
  Settings s;
  setSettingFromText(s, "clampBound", "0.25");
  EXPECT_FLOAT_EQ(s.clampBound, 0.25f);
  setSettingFromText(s, "clampBound", "inf");
  EXPECT_TRUE(std::isinf(s.clampBound));
  setSettingFromText(s, "rejection", "true");
  EXPECT_TRUE(s.rejection);
  setSettingFromText(s, "components", "direct");
  EXPECT_EQ(s.components, Components::Direct);
  setSettingFromText(s, "vplCount", "64");
  EXPECT_EQ(s.vplCount, 64);
  EXPECT_THROW(setSettingFromText(s, "vplcount", "64"), SettingsJsonError);
  EXPECT_THROW(setSettingFromText(s, "ssbcSteps", "5"), SettingsJsonError);
  EXPECT_EQ(s.ssbcSteps, 0);
}

TEST(SettingsJson, FilesRoundTripAndMissingFilesNameThePath) {
  const std::string path = vplab::test::tmpPath("settings_json_test.json");
  Settings s;
  s.vplCount = 321;
  s.clampBound = 2.0f;
  saveSettingsFile(path, s);
  Settings back;
  loadSettingsFile(path, back);
  EXPECT_EQ(back.vplCount, 321);
  EXPECT_FLOAT_EQ(back.clampBound, 2.0f);

  const std::string missing = vplab::test::tmpPath("no_such_settings.json");
  try {
    loadSettingsFile(missing, back);
    FAIL();
  } catch (const SettingsJsonError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos);
  }
  std::ofstream(path) << R"({"vslRadius": -2})";
  try {
    loadSettingsFile(path, back);
    FAIL();
  } catch (const SettingsJsonError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("vslRadius"), std::string::npos);
  }
}

}  // namespace
}  // namespace vplab
