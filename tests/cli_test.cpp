// The vplab command line as scripts and CI use it: compare thresholds and exit codes, outputs that are checked
// before work and never written over inputs, writes that fail cleanly on a full disk or a read-only folder, the
// flag vocabulary derived from the settings table, and image information recorded with linear outputs.

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "evaluation/csv_log.h"
#include "evaluation/harness.h"
#include "evaluation/sweep.h"
#include "renderer/core/atomic_file.h"
#include "renderer/image/image_io.h"
#include "renderer/offline/render_methods.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/settings.h"
#include "renderer/settings_json.h"
#include "tests/test_tmp.h"

namespace vplab {
namespace {

namespace fs = std::filesystem;

const std::string kScene = std::string(VPLAB_TEST_ASSETS) + "/scenes/cornell-box.gltf";

struct CliRun {
  int status = -1;
  std::string out;  ///< stdout and stderr together
};

/// Runs `prefix vplab arguments` in sh (prefix: e.g. "ulimit -f 4;") and collects its output and exit status.
CliRun vplab(const std::string& arguments, const std::string& prefix = "") {
  std::string command = prefix + " " + std::string(VPLAB_BINARY) + " " + arguments + " 2>&1";
  CliRun r;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe)) r.out += buffer;
  int status = pclose(pipe);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::size_t temporariesIn(const std::string& folder) {
  std::size_t n = 0;
  for (const auto& e : fs::directory_iterator(folder))
    if (contains(e.path().filename().string(), ".tmp-")) ++n;
  return n;
}

// --- compare for CI --------------------------------------------------------------------------------------------

TEST(CliCompare, ThresholdsPassOrFailWithOneLineNamingWhatFailed) {
  std::string image = test::tmpPath("cmp_image.exr"), ref = test::tmpPath("cmp_ref.exr");
  writeImage(ref, Image(8, 8, glm::vec3(0.5f)));
  writeImage(image, Image(8, 8, glm::vec3(0.55f)));  // energy ratio 1.1, relmse 0.0025 / 0.26

  CliRun pass = vplab("compare " + image + " " + ref + " --max-relmse 0.05 --max-energy-error 0.2 --max-bad-pixels 0");
  EXPECT_EQ(pass.status, 0) << pass.out;
  EXPECT_TRUE(contains(pass.out, "\nPASS\n")) << pass.out;

  CliRun fail = vplab("compare " + image + " " + ref + " --max-relmse 0.05 --max-energy-error 0.05");
  EXPECT_EQ(fail.status, 1) << fail.out;
  std::string verdict = fail.out.substr(fail.out.rfind("FAIL"));
  EXPECT_TRUE(contains(verdict, "FAIL: energy error |1.1")) << fail.out;
  EXPECT_FALSE(contains(verdict, "relmse")) << "relmse passed and must not be named: " << verdict;

  CliRun tight = vplab("compare " + image + " " + ref + " --max-relmse 0.001");
  EXPECT_EQ(tight.status, 1);
  EXPECT_TRUE(contains(tight.out, "FAIL: relmse")) << tight.out;

  // Without thresholds: metrics only, exit 0, no verdict.
  CliRun plain = vplab("compare " + image + " " + ref);
  EXPECT_EQ(plain.status, 0);
  EXPECT_FALSE(contains(plain.out, "PASS"));
}

TEST(CliCompare, NonFinitePixelsFailTheBadPixelThreshold) {
  std::string image = test::tmpPath("cmp_nan.exr"), ref = test::tmpPath("cmp_nan_ref.exr");
  Image bad(4, 4, glm::vec3(0.5f));
  bad.at(1, 2) = glm::vec3(std::nanf(""));
  writeImage(image, bad);
  writeImage(ref, Image(4, 4, glm::vec3(0.5f)));
  CliRun r = vplab("compare " + image + " " + ref + " --max-bad-pixels 0");
  EXPECT_EQ(r.status, 1) << r.out;
  EXPECT_TRUE(contains(r.out, "FAIL: bad pixels 1 > 0")) << r.out;
}

TEST(CliCompare, RefusesTonemappedAgainstLinearUnlessAsked) {
  std::string png = test::tmpPath("cmp_tm.png"), ref = test::tmpPath("cmp_tm_ref.exr");
  writeImage(png, Image(8, 8, glm::vec3(0.5f)));
  writeImage(ref, Image(8, 8, glm::vec3(0.5f)));
  CliRun refused = vplab("compare " + png + " " + ref);
  EXPECT_EQ(refused.status, 2);
  EXPECT_TRUE(contains(refused.out, "tonemapped")) << refused.out;
  EXPECT_EQ(vplab("compare " + png + " " + ref + " --allow-tonemapped").status, 0);
}

TEST(CliCompare, WarnsWhenTheRecordedComponentsDiffer) {
  std::string image = test::tmpPath("cmp_all.exr"), ref = test::tmpPath("cmp_indirect.pfm");
  writeImage(image, Image(8, 8, glm::vec3(0.5f)), 0.0f, {{"components", "all"}});
  writeImage(ref, Image(8, 8, glm::vec3(0.5f)), 0.0f, {{"components", "indirect"}});
  CliRun r = vplab("compare " + image + " " + ref);
  EXPECT_EQ(r.status, 0);
  EXPECT_TRUE(contains(r.out, "warning: the image holds all light but the reference holds indirect light")) << r.out;
}

// --- image information ------------------------------------------------------------------------------------------

TEST(ImageInfo, RoundTripsThroughExrAttributesAndThePfmSidecar) {
  ImageInfo info = {{"components", "indirect"}, {"method", "vpl"}, {"spp", "4"}, {"settings", "{\"a\": 1}"}};
  for (const char* name : {"info.exr", "info.pfm"}) {
    std::string path = test::tmpPath(name);
    writeImage(path, Image(5, 3, glm::vec3(1.0f)), 0.0f, info);
    EXPECT_EQ(readImageInfo(path), info) << name;
    EXPECT_EQ(readImage(path).width, 5);
  }
  EXPECT_TRUE(fs::exists(pfmSidecarPath(test::tmpPath("info.pfm"))));
  // A PFM written again without information loses the old sidecar: it must not describe the new image.
  writeImage(test::tmpPath("info.pfm"), Image(5, 3));
  EXPECT_TRUE(readImageInfo(test::tmpPath("info.pfm")).empty());
  EXPECT_TRUE(readImageInfo(test::tmpPath("info.png")).empty());
}

TEST(CliRender, LinearOutputsRecordWhatTheyHold) {
  std::string out = test::tmpPath("render_info.exr");
  CliRun r = vplab("reference " + kScene + " --size 8x8 --samples-per-pixel 2 --components indirect -o " + out);
  ASSERT_EQ(r.status, 0) << r.out;
  ImageInfo info = readImageInfo(out);
  EXPECT_EQ(info["components"], "indirect");
  EXPECT_EQ(info["method"], "reference");
  EXPECT_EQ(info["spp"], "2");
  EXPECT_EQ(info["nonFiniteSamples"], "0");
  EXPECT_TRUE(contains(r.out, "2 spp, 0 NaN/Inf samples")) << r.out;
  Settings s;
  applySettingsJson(info["settings"], s);
  EXPECT_EQ(s.width, 8);
  EXPECT_EQ(s.components, Components::Indirect);
}

// --- writes that never lie or destroy ---------------------------------------------------------------------------

TEST(AtomicWrite, AFullDiskLeavesTheOldFileAndNoTemporary) {
  // RLIMIT_FSIZE makes write() fail with EFBIG past the limit, as a full disk makes it fail with ENOSPC.
  std::string folder = test::tmpPath("full");
  fs::create_directories(folder);
  std::string path = folder + "/image.pfm";
  writeImage(path, Image(4, 4, glm::vec3(0.25f)));
  std::string before = readFile(path);

  auto previous = std::signal(SIGXFSZ, SIG_IGN);
  rlimit old{};
  getrlimit(RLIMIT_FSIZE, &old);
  rlimit small = old;
  small.rlim_cur = 1000;
  ASSERT_EQ(setrlimit(RLIMIT_FSIZE, &small), 0);
  bool threw = false;
  try {
    writeImage(path, Image(64, 64, glm::vec3(0.75f)));  // 49 KB
  } catch (const ImageIoError& e) {
    threw = true;
    EXPECT_TRUE(contains(e.what(), path)) << e.what();
  }
  setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, previous);
  EXPECT_TRUE(threw) << "a cut write must be reported";
  EXPECT_EQ(readFile(path), before) << "the old file must survive a failed write";
  EXPECT_EQ(temporariesIn(folder), 0u);
}

TEST(CliRender, LightcutsPrintsItsCutAndRefusesBadThresholdsVslsAndMedia) {
  const std::string base = "render " + kScene + " --size 8x8 --vpl-count 64 --method lightcuts -o " +
                           test::tmpPath("lc.exr");
  CliRun ok = vplab(base + " --clamp-bound 10 --lightcut-error 0.02 --lightcut-max 50");
  EXPECT_EQ(ok.status, 0) << ok.out;
  EXPECT_TRUE(contains(ok.out, "mean cut")) << ok.out;
  EXPECT_TRUE(contains(ok.out, "B per node")) << ok.out;
  for (const char* bad : {"--lightcut-error -0.1", "--lightcut-error nan", "--lightcut-error 2",
                          "--lightcut-max 0", "--lightcut-max 100000000", "--lightcut-max 1e99"}) {
    CliRun r = vplab(base + " " + bad);
    EXPECT_EQ(r.status, 2) << bad << ": " << r.out;
    EXPECT_TRUE(contains(r.out, std::string(bad).substr(0, std::string(bad).find(' ')))) << r.out;
  }
  CliRun vsl = vplab(base + " --vsl-radius 0.05");
  EXPECT_EQ(vsl.status, 2) << vsl.out;
  EXPECT_TRUE(contains(vsl.out, "lights point VPLs")) << vsl.out;
  CliRun fog = vplab("render " + std::string(VPLAB_TEST_ASSETS) + "/scenes/cornell-fog.gltf --size 8x8 --vpl-count 16 "
                     "--method lightcuts -o " + test::tmpPath("lc-fog.exr"));
  EXPECT_NE(fog.status, 0) << fog.out;
  EXPECT_TRUE(contains(fog.out, "participating media")) << fog.out;
}

TEST(CliRender, AFullDiskIsAnErrorNotAWroteAndTheOldFileSurvives) {
  std::string out = test::tmpPath("full_render.png");
  writeImage(out, Image(2, 2, glm::vec3(0.5f)));
  std::string before = readFile(out);
  // ulimit -f counts 1024-byte blocks in dash and bash: a 64x64 noisy PNG does not fit in 1 KiB.
  CliRun r = vplab("render " + kScene + " --size 64x64 --vpl-count 16 -o " + out, "ulimit -f 1;");
  EXPECT_NE(r.status, 0) << r.out;
  EXPECT_FALSE(contains(r.out, "wrote")) << r.out;
  EXPECT_EQ(readFile(out), before);
  EXPECT_EQ(temporariesIn(vplab::test::tmpDir()), 0u);
}

TEST(CliRender, AnUnwritableFolderFailsBeforeAnyWork) {
  // /proc takes no new files, not even from root: a read-only folder whatever user runs the tests.
  CliRun r = vplab("reference " + kScene + " --size 8x8 -o /proc/vplab-test.exr");
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_TRUE(contains(r.out, "option --out")) << r.out;
  EXPECT_FALSE(contains(r.out, "%")) << "no progress: the check comes before the render\n" << r.out;
  CliRun missing = vplab("render " + kScene + " --size 8x8 -o " + test::tmpPath("no-such-folder/x.exr"));
  EXPECT_EQ(missing.status, 2);
  EXPECT_TRUE(contains(missing.out, "does not exist")) << missing.out;
}

TEST(CliRender, NoCommandWritesOverItsOwnInputs) {
  std::string scene = test::tmpPath("input_scene.gltf");
  fs::copy_file(kScene, scene, fs::copy_options::overwrite_existing);
  std::string sceneBefore = readFile(scene);
  CliRun r = vplab("render " + scene + " --size 8x8 -o " + test::tmpPath("x.exr") + " --save-vpls " + scene);
  EXPECT_EQ(r.status, 2);
  // A VPL set is JSON: the scene's name is refused for its extension before anything is written.
  EXPECT_TRUE(contains(r.out, "option --save-vpls: '" + scene + "' is not .json")) << r.out;
  EXPECT_EQ(readFile(scene), sceneBefore);
  std::string json = test::tmpPath("input_vpls.json");
  fs::copy_file(kScene, json, fs::copy_options::overwrite_existing);
  r = vplab("render " + json + " --size 8x8 -o " + test::tmpPath("x.exr") + " --save-vpls " + json);
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.out, "is an input")) << r.out;

  std::string a = test::tmpPath("in_a.png"), b = test::tmpPath("in_b.png");
  writeImage(a, Image(4, 4, glm::vec3(0.2f)));
  writeImage(b, Image(4, 4, glm::vec3(0.4f)));
  std::string refBefore = readFile(b);
  CliRun heat = vplab("compare " + a + " " + b + " --heatmap " + b);
  EXPECT_EQ(heat.status, 2);
  EXPECT_EQ(readFile(b), refBefore);

  CliRun same = vplab("render " + kScene + " --size 8x8 -o " + test::tmpPath("twice.png") + " --png " +
                      test::tmpPath("twice.png"));
  EXPECT_EQ(same.status, 2);
  EXPECT_TRUE(contains(same.out, "also the file of --out")) << same.out;
}

// --- one vocabulary ---------------------------------------------------------------------------------------------

TEST(SettingsTable, EveryKeyHasOneFlagAndTheTableCoversEveryJsonKey) {
  std::vector<std::string> keys;
  for (const SettingInfo& info : settingsTable()) {
    keys.emplace_back(info.key);
    EXPECT_EQ(findSetting(info.key), &info);
    std::string flag = settingFlag(info.key);
    for (char c : flag) EXPECT_TRUE(std::islower(static_cast<unsigned char>(c)) || std::isdigit(c) || c == '-') << flag;
    // The value as formatted parses back to the same value.
    Settings s, back;
    parseSetting(back, info, formatSetting(s, info));
    EXPECT_EQ(formatSetting(back, info), formatSetting(s, info)) << info.key;
  }
  EXPECT_EQ(keys, settingsJsonKeys());
  EXPECT_EQ(settingFlag("rejectionMaxCandidateFactor"), "rejection-max-candidate-factor");
}

TEST(SettingsTable, ValidationNamesTheSpellingTheUserTyped) {
  Settings s;
  s.vplCount = -3;
  ASSERT_EQ(validateSettings(s).size(), 1u);
  EXPECT_EQ(validateSettings(s)[0], "vplCount = -3 is outside [0, 1048576]");
  EXPECT_EQ(validateSettings(s, SettingSpelling::Flag)[0], "--vpl-count = -3 is outside [0, 1048576]");
  // A share that must be positive, a power of two, and a rule between two settings.
  Settings t;
  t.birLightShare = 0.0f;
  t.ismTileSize = 48;
  t.rejection = true;
  t.generation = VplGeneration::Metropolis;
  std::vector<std::string> problems = validateSettings(t, SettingSpelling::Flag);
  ASSERT_EQ(problems.size(), 3u);
  EXPECT_EQ(problems[0], "--bir-light-share = 0 is outside (0, 1]");
  EXPECT_EQ(problems[1], "--ism-tile-size = 48 is not a power of two");
  EXPECT_EQ(problems[2], "--rejection = true needs --generation = light (metropolis already chooses its VPLs by "
                         "importance)");
  t = Settings{};
  t.birLightShare = 1.0f;
  t.ismTileSize = 128;
  EXPECT_TRUE(validateSettings(t).empty());
}

TEST(CliFlags, ErrorsNameTheFlagTyped) {
  CliRun r = vplab("render " + kScene + " --size 8x8 -o " + test::tmpPath("f.exr") + " --vpl-count -3");
  EXPECT_EQ(r.status, 2);
  EXPECT_TRUE(contains(r.out, "--vpl-count = -3 is outside")) << r.out;
  CliRun rule =
      vplab("render " + kScene + " --size 8x8 -o " + test::tmpPath("f.exr") + " --generation metropolis --rejection");
  EXPECT_EQ(rule.status, 2);
  EXPECT_TRUE(contains(rule.out, "--rejection = true needs --generation = light")) << rule.out;
  CliRun choice = vplab("preview " + kScene + " --size 8x8 -o " + test::tmpPath("f.png") + " --visibility rays");
  EXPECT_EQ(choice.status, 2);
  EXPECT_TRUE(contains(choice.out, "option --visibility: 'rays': expected one of cube, ism")) << choice.out;
  CliRun old = vplab("render " + kScene + " -o " + test::tmpPath("f.exr") + " --clamp 3");
  EXPECT_EQ(old.status, 2);
  EXPECT_TRUE(contains(old.out, "did you mean --clamp-bound or --clamp-bound-relative?")) << old.out;
  CliRun bool7 = vplab("preview " + kScene + " -o " + test::tmpPath("f.png") + " --ssbc-coarse-rings=7");
  EXPECT_EQ(bool7.status, 2);
  EXPECT_TRUE(contains(bool7.out, "--ssbc-coarse-rings")) << bool7.out;
  // The whole unsigned range the JSON accepts.
  CliRun seed =
      vplab("render " + kScene + " --size 4x4 --vpl-count 4 --seed 4000000000 -o " + test::tmpPath("seed.exr"));
  EXPECT_EQ(seed.status, 0) << seed.out;
  EXPECT_TRUE(contains(seed.out, "seed 4000000000")) << seed.out;
}

TEST(CliFlags, HelpListsOnlyWhatActsOnTheCommandWithItsOwnDefaults) {
  CliRun render = vplab("render --help");
  EXPECT_EQ(render.status, 0);
  EXPECT_TRUE(contains(render.out, "--exact-samples-per-pixel <N>")) << render.out;
  EXPECT_TRUE(contains(render.out, "every VPL) (default 4)")) << render.out;
  EXPECT_FALSE(contains(render.out, "  --samples-per-pixel")) << "the reference's sample count does nothing in render";
  EXPECT_TRUE(contains(render.out, "--generation <light|bidirectional|metropolis>")) << render.out;
  EXPECT_FALSE(contains(render.out, "--ssbc-steps")) << "a GL-only setting does nothing in render";
  EXPECT_FALSE(contains(render.out, "--interleave"));
  CliRun preview = vplab("preview --help");
  EXPECT_TRUE(contains(preview.out, "--ssbc-steps"));
  EXPECT_TRUE(contains(preview.out, "--ref <FILE>"));
  EXPECT_TRUE(contains(preview.out, "--components"));
  EXPECT_FALSE(contains(preview.out, "--samples-per-pixel"));
  // The preview's own defaults (previewDefaultSettings), not the Settings struct's k = s = 1.
  EXPECT_TRUE(contains(preview.out, "1 = off (default 4)")) << preview.out;
  EXPECT_TRUE(contains(preview.out, "upsampled along surfaces (default 2)")) << preview.out;
  EXPECT_TRUE(contains(preview.out, "VPL shadow-map resolution in texels (default 128)")) << preview.out;
  CliRun reference = vplab("reference --help");
  EXPECT_TRUE(contains(reference.out, "(default 64)"));
  EXPECT_FALSE(contains(reference.out, "--vpl-count"));
  CliRun version = vplab("--version");
  EXPECT_EQ(version.status, 0);
  EXPECT_TRUE(contains(version.out, "vplab ")) << version.out;
  // The commands' list names every offline method of the method table on the render line.
  CliRun top = vplab("--help");
  const std::size_t line = top.out.find("\n  render ");
  ASSERT_NE(line, std::string::npos) << top.out;
  const std::string renderLine = top.out.substr(line + 1, top.out.find('\n', line + 1) - line - 1);
  for (const RenderMethod& m : renderMethods()) {
    const std::string name = toString(m.id);
    if (m.id != Method::Reference) {
      EXPECT_TRUE(contains(renderLine, name + ",") || contains(renderLine, name + ")")) << name << ": " << renderLine;
    }
  }
}

TEST(CliFlags, OutDecidesTheFormatByItsExtensionEverywhere) {
  for (const char* ext : {"exr", "pfm", "png"}) {
    std::string out = test::tmpPath(std::string("ext.") + ext);
    fs::remove(out);
    CliRun r = vplab("render " + kScene + " --size 4x4 --vpl-count 4 -o " + out);
    EXPECT_EQ(r.status, 0) << r.out;
    EXPECT_EQ(readImage(out).width, 4) << out;
  }
  CliRun bad = vplab("reference " + kScene + " --size 4x4 -o " + test::tmpPath("ext.tiff"));
  EXPECT_EQ(bad.status, 2);
  EXPECT_TRUE(contains(bad.out, "unknown image extension")) << bad.out;
}

// --- settings files ---------------------------------------------------------------------------------------------

TEST(SettingsJsonLimits, DeepNestingAndHugeKeysGiveShortErrors) {
  std::string deep(100000, '[');
  try {
    Settings s;
    applySettingsJson("{\"width\": " + deep + "}", s);
    FAIL() << "no error";
  } catch (const SettingsJsonError& e) {
    EXPECT_TRUE(contains(e.what(), "nested deeper")) << e.what();
  }
  std::string key(5'000'000, 'k');
  try {
    Settings s;
    applySettingsJson("{\"" + key + "\": 1}", s);
    FAIL() << "no error";
  } catch (const SettingsJsonError& e) {
    EXPECT_LT(std::string(e.what()).size(), 200u);
  }
  try {
    Settings s;
    applySettingsJson("{\"width\": \"" + key + "\"}", s);
    FAIL() << "no error";
  } catch (const SettingsJsonError& e) {
    EXPECT_LT(std::string(e.what()).size(), 200u);
  }
}

// --- sweeps across machines -----------------------------------------------------------------------------------

/// bench.csv as key -> every column that does not measure time (times differ from run to run, the rest must not).
std::map<std::string, std::string> benchRows(const std::string& csv) {
  std::map<std::string, std::string> rows;
  std::vector<std::string> header;
  std::vector<CsvRow> all = readCsv(csv, &header);
  for (const CsvRow& r : all) {
    std::string key, rest;
    for (std::size_t i = 0; i < header.size(); ++i) {
      const std::string& c = header[i];
      if (c == "gen_ms" || c == "render_ms" || c == "time_ms") continue;
      (i < benchCsvKeyColumns() ? key : rest) += r.at(c) + ",";
    }
    EXPECT_EQ(rows.count(key), 0u) << "a run appears twice in " << csv << ": " << key;
    rows[key] = rest;
  }
  return rows;
}

TEST(BenchShards, FourShardsThroughGnuParallelMergeToTheUnshardedSweep) {
  ASSERT_EQ(std::system("parallel --version > /dev/null 2>&1"), 0)
      << "GNU parallel is missing (Debian package 'parallel', installed by scripts/install-deps.sh)";
  const std::string dir = test::tmpPath("shards");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string sweep = kScene + " --quick --size 12x12 --ref-spp 8 --exact-samples-per-pixel 1 --methods vpl,clamp,vsl,reject"
                            " --gl off --threads 1";
  CliRun full = vplab("bench " + sweep + " --out " + dir + "/full");
  ASSERT_EQ(full.status, 0) << full.out;
  // One shard per job slot, as over ssh hosts or a Slurm array: each shard its own process and folder.
  std::string command = "cd " + dir + " && parallel -j 2 --halt now,fail=1 " + std::string(VPLAB_BINARY) + " bench " +
                        sweep + " --shard {}/4 --out shard-{} ::: 1 2 3 4 > parallel.log 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << readFile(dir + "/parallel.log");
  CliRun merge = vplab("bench --merge " + dir + "/shard-1 " + dir + "/shard-2 " + dir + "/shard-3 " + dir +
                       "/shard-4 --out " + dir + "/merged");
  ASSERT_EQ(merge.status, 0) << merge.out;

  std::map<std::string, std::string> whole = benchRows(dir + "/full/bench.csv");
  std::map<std::string, std::string> merged = benchRows(dir + "/merged/bench.csv");
  EXPECT_GE(whole.size(), 8u) << "a sweep long enough that every shard has runs";
  EXPECT_EQ(merged, whole) << "the merged shards must hold exactly the unsharded sweep's runs and results";
  std::size_t shardRows = 0;
  for (int i = 1; i <= 4; ++i) {
    std::size_t n = benchRows(dir + "/shard-" + std::to_string(i) + "/bench.csv").size();
    EXPECT_GT(n, 0u) << "shard " << i << " ran nothing";
    shardRows += n;
  }
  EXPECT_EQ(shardRows, whole.size()) << "the shards split the runs: none twice, none missing";
  EXPECT_TRUE(fs::exists(dir + "/merged/report.md"));

  // Idempotent: merging again, or into the unsharded folder, adds nothing.
  CliRun again = vplab("bench --merge " + dir + "/shard-1 " + dir + "/shard-3 --out " + dir + "/merged");
  EXPECT_EQ(again.status, 0);
  EXPECT_TRUE(contains(again.out, "0 merged")) << again.out;
  EXPECT_EQ(benchRows(dir + "/merged/bench.csv"), whole);
  CliRun intoFull = vplab("bench --merge " + dir + "/shard-2 --out " + dir + "/full");
  EXPECT_TRUE(contains(intoFull.out, "0 merged")) << intoFull.out;
}

// --- caches ----------------------------------------------------------------------------------------------------

TEST(CachedReference, AFileThatDoesNotReadBackIsRenderedAgainNotTrusted) {
  OfflineScene offline(loadScene(kScene));
  Settings s;
  s.width = s.height = 8;
  s.samplesPerPixel = 2;
  std::string dir = test::tmpPath("refcache");
  fs::remove_all(dir);
  bool cached = true;
  MeasuredImage first = cachedReference(offline, "cornell-box", s, dir, &cached);
  EXPECT_FALSE(cached);
  std::size_t files = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::ofstream(e.path(), std::ios::trunc).flush();  // what a full disk used to leave behind
    ++files;
  }
  ASSERT_EQ(files, 1u);
  MeasuredImage again = cachedReference(offline, "cornell-box", s, dir, &cached);
  EXPECT_FALSE(cached) << "a 0-byte cache file must not be used";
  EXPECT_EQ(again.image.pixels, first.image.pixels);
  MeasuredImage reused = cachedReference(offline, "cornell-box", s, dir, &cached);
  EXPECT_TRUE(cached);
  EXPECT_EQ(reused.image.pixels, first.image.pixels);
}

}  // namespace
}  // namespace vplab
