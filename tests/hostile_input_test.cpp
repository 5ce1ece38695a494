// What a hostile or careless user can type: outputs that are devices or FIFOs are written in place, never
// replaced; inputs are read only from regular files, bounded; every error names what was typed and what was expected,
// in the project's words, with one exit status per kind of error; invalid glTF values are errors, not silent
// defaults; text from files is printed escaped. HostileFuzz runs a small mutator over the bundled scenes and settings.

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <fstream>
#include <sstream>
#include <string>

#include "renderer/core/atomic_file.h"
#include "renderer/core/text.h"
#include "renderer/gl/gl_limits.h"
#include "renderer/gl/preview_renderer.h"
#include "renderer/image/image_io.h"
#include "renderer/scene/gltf_loader.h"
#include "renderer/scene/lights_json.h"
#include "renderer/settings.h"
#include "renderer/settings_json.h"
#include "tests/test_tmp.h"

namespace vplab {
namespace {

namespace fs = std::filesystem;

const std::string kAssets = VPLAB_TEST_ASSETS;
const std::string kScene = kAssets + "/scenes/cornell-box.gltf";

struct CliRun {
  int status = -1;
  std::string out;  ///< stdout and stderr together
};

CliRun vplab(const std::string& arguments) {
  std::string command = "timeout 60 " + std::string(VPLAB_BINARY) + " " + arguments + " 2>&1 </dev/null";
  CliRun r;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return r;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) r.out += buffer;
  int status = pclose(pipe);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A character device like /dev/null made in the test's folder (root only; empty otherwise).
std::string makeNullDevice(const std::string& name) {
  std::string path = test::tmpPath(name);
  fs::remove(path);
  if (::mknod(path.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) return {};
  return path;
}

std::string makeFifo(const std::string& name) {
  std::string path = test::tmpPath(name);
  fs::remove(path);
  EXPECT_EQ(::mkfifo(path.c_str(), 0644), 0);
  return path;
}

// --- outputs -----------------------------------------------------------------------------------------------------

TEST(HostileOutputs, ADeviceIsWrittenInPlaceNeverReplaced) {
  std::string dev = makeNullDevice("nulldev");
  if (dev.empty()) GTEST_SKIP() << "mknod needs root";
  CliRun r = vplab("render " + kScene + " --size 8x8 --vpl-count 16 -o " + test::tmpPath("a.pfm") + " --save-vpls " +
                   dev);
  EXPECT_EQ(r.status, 0) << r.out;
  struct stat st {};
  ASSERT_EQ(::stat(dev.c_str(), &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode)) << "the device was replaced by a regular file";
  // An image into a device named like an image: the PFM goes into the device, its sidecar beside it.
  std::string devPfm = makeNullDevice("nulldev.pfm");
  CliRun ref = vplab("reference " + kScene + " --size 8x8 --samples-per-pixel 1 -o " + devPfm);
  EXPECT_EQ(ref.status, 0) << ref.out;
  ASSERT_EQ(::stat(devPfm.c_str(), &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
  // compare --heatmap into a device named like a PNG.
  std::string devPng = makeNullDevice("heat.png");
  const std::string refExr = kAssets + "/references/cornell-box-64.exr";
  CliRun heat = vplab("compare " + refExr + " " + refExr + " --heatmap " + devPng);
  EXPECT_EQ(heat.status, 0) << heat.out;
  ASSERT_EQ(::stat(devPng.c_str(), &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
  // Straight through the library too.
  writeFileAtomically(dev, "bytes");
  ASSERT_EQ(::stat(dev.c_str(), &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode));
}

TEST(HostileOutputs, AFifoWithAReaderGetsTheBytesOneWithoutIsRefused) {
  std::string fifo = makeFifo("out.fifo");
  // No reader: refused with a message naming the FIFO, not a hang and not a replaced FIFO.
  try {
    writeFileAtomically(fifo, "{}");
    ADD_FAILURE() << "a FIFO without a reader must be refused";
  } catch (const FileWriteError& e) {
    EXPECT_TRUE(contains(e.what(), fifo)) << e.what();
    EXPECT_TRUE(contains(e.what(), "no program reads")) << e.what();
  }
  // Through the command line the refusal comes before the work (the FIFO is opened by the output check and held).
  CliRun early = vplab("render " + kScene + " --size 8x8 --vpl-count 16 -o " + test::tmpPath("a.pfm") +
                       " --save-vpls " + fifo);
  EXPECT_EQ(early.status, 2) << early.out;
  EXPECT_TRUE(contains(early.out, "option --save-vpls: " + fifo + ": is a FIFO that no program reads")) << early.out;
  EXPECT_FALSE(contains(early.out, "%")) << "no progress: the check comes before the render\n" << early.out;
  std::string got = test::tmpPath("from-fifo.txt");
  FILE* reader = popen(("cat " + fifo + " > " + got).c_str(), "w");
  ASSERT_NE(reader, nullptr);
  // The reader opens the FIFO asynchronously: retry the write for a moment.
  bool written = false;
  for (int i = 0; i < 100 && !written; ++i) {
    try {
      writeFileAtomically(fifo, "through the fifo");
      written = true;
    } catch (const FileWriteError&) {
      ::usleep(20000);
    }
  }
  pclose(reader);
  EXPECT_TRUE(written);
  EXPECT_EQ(readText(got), "through the fifo");
  // The command line holds the FIFO open from the check to the write: the reader gets the whole VPL file.
  FILE* vplReader = popen(("cat " + fifo + " > " + got).c_str(), "w");
  ASSERT_NE(vplReader, nullptr);
  CliRun piped;
  for (int i = 0; i < 100; ++i) {
    piped = vplab("render " + kScene + " --size 8x8 --vpl-count 16 -o " + test::tmpPath("b.pfm") + " --save-vpls " +
                  fifo);
    if (piped.status == 0) break;
    ::usleep(20000);
  }
  pclose(vplReader);
  EXPECT_EQ(piped.status, 0) << piped.out;
  EXPECT_NO_THROW(nlohmann::json::parse(readText(got))) << "the reader got a cut file";
  struct stat st {};
  ASSERT_EQ(::stat(fifo.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
}

// --- inputs ------------------------------------------------------------------------------------------------------

TEST(HostileInputs, SpecialFilesAndFoldersAreRefusedNamingThePath) {
  std::string fifo = makeFifo("scene.fifo"), fifoImage = makeFifo("image.pfm"), folderImage = test::tmpPath("dir.exr");
  fs::create_directories(folderImage);
  const std::string ref = kAssets + "/references/cornell-box-64.exr";
  for (const std::string& path : {fifo, std::string("/dev/zero"), test::tmpDir(), fifoImage, folderImage}) {
    for (const std::string& args : {"info " + path, "reference " + path + " --size 8x8 -o " + test::tmpPath("x.pfm"),
                                    "compare " + path + " " + ref, "compare " + ref + " " + path}) {
      CliRun r = vplab(args);
      EXPECT_EQ(r.status, 3) << args << "\n" << r.out;  // an input that cannot be read
      EXPECT_TRUE(contains(r.out, path)) << args << "\n" << r.out;
      EXPECT_FALSE(contains(r.out, "basic_filebuf")) << r.out;
      EXPECT_FALSE(contains(r.out, "out of memory")) << r.out;
    }
  }
  CliRun settings = vplab("reference " + kScene + " --size 8x8 -o " + test::tmpPath("y.pfm") + " --settings " + fifo);
  EXPECT_EQ(settings.status, 2) << settings.out;
  EXPECT_TRUE(contains(settings.out, fifo + ": is a FIFO")) << settings.out;
}

TEST(HostileInputs, ATooLargeFileIsRefusedBeforeItIsRead) {
  std::string big = test::tmpPath("big.json");
  {
    std::ofstream out(big);
    out << "{\"exposure\": 1" << std::string(2u << 20, ' ') << "}";
  }
  CliRun r = vplab("reference " + kScene + " --size 8x8 -o " + test::tmpPath("z.pfm") + " --settings " + big);
  EXPECT_EQ(r.status, 2) << r.out;
  EXPECT_TRUE(contains(r.out, big + ": 2 MiB, larger than the 1 MiB that vplab reads as a settings file")) << r.out;
}

// --- errors in the project's words ---------------------------------------------------------------------------------

TEST(HostileErrors, JsonErrorsNameTheFileAndKeyWithoutLibraryIds) {
  const std::string out = " -o " + test::tmpPath("o.pfm");
  std::string huge = test::tmpPath("huge.json"), empty = test::tmpPath("empty.json");
  writeText(huge, "{\"clampBound\": 1e999}");
  writeText(empty, "");
  CliRun h = vplab("reference " + kScene + " --size 8x8" + out + " --settings " + huge);
  EXPECT_EQ(h.status, 2) << h.out;  // like every other settings error
  EXPECT_TRUE(contains(h.out, huge + ": \"clampBound\": the number 1e999 is out of range")) << h.out;
  EXPECT_FALSE(contains(h.out, "json.exception")) << h.out;
  CliRun e = vplab("reference " + kScene + " --size 8x8" + out + " --settings " + empty);
  EXPECT_EQ(e.status, 2) << e.out;
  EXPECT_TRUE(contains(e.out, empty + ": the file is empty (expected a JSON object)")) << e.out;

  std::string scene = test::tmpPath("scene.gltf");
  fs::copy_file(kScene, scene, fs::copy_options::overwrite_existing);
  writeText(scene + ".lights.json",
            "{\"punctualLights\": [{\"type\": \"point\", \"intensity\": [1e999, 1, 1], \"position\": [0, 1, 0]}], "
            "\"areaLights\": []}");
  CliRun l = vplab("info " + scene);
  EXPECT_EQ(l.status, 3) << l.out;
  EXPECT_TRUE(contains(l.out, ".lights.json: \"intensity\": the number 1e999 is out of range")) << l.out;
  EXPECT_FALSE(contains(l.out, "not a JSON object")) << l.out;
}

TEST(HostileErrors, FlagErrorsNameTheFlagTypedAndItsRealRange) {
  const std::string render = "render " + kScene + " -o " + test::tmpPath("o.pfm");
  CliRun size = vplab("reference " + kScene + " -o " + test::tmpPath("o.pfm") + " --size 0x0");
  EXPECT_EQ(size.status, 2);
  EXPECT_TRUE(contains(size.out, "option --size: '0x0': width and height must each be in [1, 16384]")) << size.out;
  EXPECT_FALSE(contains(size.out, "--width")) << size.out;
  CliRun clamp = vplab(render + " --clamp-bound 1e300");
  EXPECT_EQ(clamp.status, 2);
  EXPECT_TRUE(contains(clamp.out, "'1e300': out of the range of a float")) << clamp.out;
  CliRun count = vplab(render + " --vpl-count 1e9");
  EXPECT_EQ(count.status, 2);
  EXPECT_TRUE(contains(count.out, "option --vpl-count: '1e9': outside [0, 1048576]")) << count.out;
  EXPECT_FALSE(contains(count.out, "2147483647")) << count.out;
  CliRun word = vplab(render + " --vpl-count many");
  EXPECT_TRUE(contains(word.out, "'many': expected an integer in [0, 1048576]")) << word.out;
  std::string zeroWidth = test::tmpPath("w.json");
  writeText(zeroWidth, "{\"width\": 0}");
  CliRun file = vplab(render + " --settings " + zeroWidth);
  EXPECT_EQ(file.status, 2);
  EXPECT_FALSE(contains(file.out, "--width")) << file.out;
  EXPECT_TRUE(contains(file.out, "width")) << file.out;
}

TEST(HostileErrors, ThePreviewSaysTenThousandLightsAreTheCause) {
  Scene scene;
  PunctualLight light;
  light.type = PunctualLight::Type::Point;
  scene.punctualLights.assign(10000, light);
  GlLimits limits;
  limits.maxTextureSize = limits.maxFramebufferSize = 16384;
  limits.maxArrayLayers = 2048;
  limits.memoryBytes = 4.0 * 1024 * 1024 * 1024;
  limits.memorySource = "test budget";
  Settings settings;
  settings.width = settings.height = 64;
  std::string why = previewFitProblem(scene, 16, settings, limits);
  EXPECT_TRUE(contains(why, "the scene's 10000 lights need")) << why;
  EXPECT_TRUE(contains(why, "the lights are the cause")) << why;
  EXPECT_FALSE(contains(why, "--vpls")) << why;
}

TEST(HostileErrors, SettingsKeysAreWhatHelpPromises) {
  const std::string out = " -o " + test::tmpPath("o.pfm") + " --samples-per-pixel 1";
  std::string sized = test::tmpPath("size.json"), zero = test::tmpPath("zero.json"), method = test::tmpPath("m.json");
  writeText(sized, "{\"size\": \"8x6\"}");
  writeText(zero, "{\"size\": \"0x8\"}");
  writeText(method, "{\"method\": \"vpl\"}");
  CliRun ok = vplab("reference " + kScene + out + " --settings " + sized);
  EXPECT_EQ(ok.status, 0) << ok.out;
  EXPECT_TRUE(contains(ok.out, "8x6")) << ok.out;
  CliRun bad = vplab("reference " + kScene + out + " --settings " + zero);
  EXPECT_EQ(bad.status, 2) << bad.out;
  EXPECT_TRUE(contains(bad.out, zero + ": 'size': \"0x8\": width and height must each be in [1, 16384]")) << bad.out;
  CliRun m = vplab("reference " + kScene + out + " --settings " + method);
  EXPECT_EQ(m.status, 2) << m.out;
  EXPECT_TRUE(contains(m.out, "unknown key 'method' (not a setting; command options such as --method go on the "
                              "command line)"))
      << m.out;
  CliRun help = vplab("reference --help");
  EXPECT_TRUE(contains(help.out, "command options (--method, --frames, -o) are not settings")) << help.out;
}

// --- invalid glTF values -------------------------------------------------------------------------------------------

/// The bundled Cornell box with one change, written to the test's folder.
std::string mutatedScene(const std::string& name, const std::function<void(nlohmann::json&)>& change) {
  nlohmann::json doc = nlohmann::json::parse(readText(kScene));
  change(doc);
  std::string path = test::tmpPath(name);
  writeText(path, doc.dump());
  return path;
}

std::string loadError(const std::string& path) {
  try {
    loadScene(path);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "(loaded)";
}

TEST(HostileGltf, InvalidValuesAreErrorsNamingTheGltfPath) {
  auto pbr = [](nlohmann::json& d) -> nlohmann::json& { return d["materials"][0]["pbrMetallicRoughness"]; };
  const std::vector<std::pair<std::function<void(nlohmann::json&)>, std::string>> cases = {
      {[&](nlohmann::json& d) { pbr(d)["baseColorFactor"] = "red"; },
       "materials[0].pbrMetallicRoughness.baseColorFactor: expected 4 numbers in [0, 1], got a string"},
      {[&](nlohmann::json& d) { pbr(d)["baseColorFactor"] = {1, 1}; },
       "baseColorFactor: expected 4 numbers in [0, 1], got an array of 2"},
      {[&](nlohmann::json& d) { pbr(d)["baseColorFactor"] = {1e30, 1, 1, 1}; }, "baseColorFactor[0]: expected"},
      {[&](nlohmann::json& d) { pbr(d)["roughnessFactor"] = -1; },
       "materials[0].pbrMetallicRoughness.roughnessFactor: expected a number in [0, 1], got the number -1"},
      {[&](nlohmann::json& d) { pbr(d)["roughnessFactor"] = 2; }, "roughnessFactor: expected a number in [0, 1]"},
      {[&](nlohmann::json& d) { pbr(d)["metallicFactor"] = "1"; }, "metallicFactor: expected a number in [0, 1]"},
      {[&](nlohmann::json& d) { d["materials"][0]["emissiveFactor"] = {-1, 0, 0}; },
       "materials[0].emissiveFactor[0]: expected 3 numbers >= 0, got the number -1"},
      {[&](nlohmann::json& d) { d["extensionsRequired"] = "KHR_materials_volume"; },
       "extensionsRequired: expected an array, got a string"},
      {[&](nlohmann::json& d) { d["extensionsUsed"] = {7}; }, "extensionsUsed[0]: expected an extension name"},
      {[&](nlohmann::json& d) {
         d["nodes"][0]["matrix"] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, "NaN"};
       },
       "nodes[0].matrix[15]: expected 16 numbers, got a string"},
      {[&](nlohmann::json& d) { d["nodes"][0]["translation"] = "up"; }, "nodes[0].translation: expected 3 numbers"},
      {[&](nlohmann::json& d) {
         d["extensionsUsed"] = {"KHR_lights_punctual"};
         d["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"color", "white"}}};
       },
       "extensions.KHR_lights_punctual.lights[0].color: expected 3 numbers >= 0, got a string"},
      {[&](nlohmann::json& d) {
         d["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "spot"}, {"spot", {{"outerConeAngle", 3}}}}};
       },
       "lights[0].spot.outerConeAngle: expected a number in [0, 1.5708], got the number 3"},
      {[&](nlohmann::json& d) {
         d["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", -5}}};
       },
       "lights[0].intensity: expected a number >= 0, got the number -5"},
      {[&](nlohmann::json& d) { d["accessors"][0].erase("count"); },
       "accessors[0]: the required property 'count' is missing"},
      {[&](nlohmann::json& d) { d["accessors"][0]["type"] = "VEC2"; }, "accessor type VEC2, expected VEC3"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    std::string path = mutatedScene("case" + std::to_string(i) + ".gltf", cases[i].first);
    std::string e = loadError(path);
    EXPECT_TRUE(contains(e, path + ": ")) << e;
    EXPECT_TRUE(contains(e, cases[i].second)) << "case " << i << ": " << e;
  }
}

TEST(HostileGltf, GlbContainerVersionsOtherThanTwoAreRefused) {
  std::string json = readText(kScene);
  while (json.size() % 4) json += ' ';
  for (uint32_t version : {1u, 2u, 3u}) {
    std::string glb = "glTF";
    auto u32 = [&](uint32_t v) { glb.append(reinterpret_cast<const char*>(&v), 4); };
    u32(version);
    u32(static_cast<uint32_t>(12 + 8 + json.size()));
    u32(static_cast<uint32_t>(json.size()));
    glb += "JSON";
    glb += json;
    std::string path = test::tmpPath("v" + std::to_string(version) + ".glb");
    writeText(path, glb);
    std::string e = loadError(path);
    if (version == 2)
      EXPECT_EQ(e, "(loaded)");
    else
      EXPECT_TRUE(contains(e, ".glb container version " + std::to_string(version) + " is not supported (expected 2)"))
          << e;
  }
}

// --- text from files is escaped ----------------------------------------------------------------------------------

TEST(HostileText, ControlCharactersFromFilesArePrintedEscaped) {
  EXPECT_EQ(printable("a\x1b[2Jb\n"), "a\\x1b[2Jb\\n");
  EXPECT_EQ(printable(printable("a\x1b")), printable("a\x1b")) << "escaping twice changes nothing";
  std::string scene =
      mutatedScene("esc.gltf", [](nlohmann::json& d) { d["materials"][0]["name"] = "evil\x1b]0;owned\x07"; });
  CliRun info = vplab("info " + scene);
  EXPECT_EQ(info.status, 0) << info.out;
  EXPECT_FALSE(contains(info.out, "\x1b")) << "an ESC byte reached the terminal";
  EXPECT_TRUE(contains(info.out, "evil\\x1b]0;owned\\x07")) << info.out;

  std::string pfm = test::tmpPath("esc.pfm");
  writeText(pfm, "PF\n4\x1b[2J 4\n-1\n" + std::string(4 * 4 * 12, '\0'));
  CliRun cmp = vplab("compare " + pfm + " " + pfm);
  EXPECT_EQ(cmp.status, 3) << cmp.out;
  EXPECT_FALSE(contains(cmp.out, "\x1b")) << cmp.out;
  EXPECT_TRUE(contains(cmp.out, "invalid PFM dimension '4\\x1b[2J'")) << cmp.out;

  // A message's own line breaks stay line breaks (a list of choices, one per line, that scripts read); typed text in
  // it is escaped where it entered.
  EXPECT_EQ(printableMessage("a\nb\x1b"), "a\nb\\x1b");
#ifdef VPLAB_HAVE_EDITOR
  std::string script = test::tmpPath("esc-preset.txt");
  writeText(script, "preset \x1b[2J?\n");
  CliRun edit = vplab("edit --script " + script);
  EXPECT_NE(edit.status, 0) << edit.out;
  EXPECT_FALSE(contains(edit.out, "\x1b")) << edit.out;
  EXPECT_TRUE(contains(edit.out, "no preset named '\\x1b[2J?'; the presets are:\n  ")) << edit.out;
  EXPECT_FALSE(contains(edit.out, "\\n")) << edit.out;
#endif
}

// --- fuzz ----------------------------------------------------------------------------------------------------------

/// Values a hostile or careless user writes where a number, a string or an array belongs.
nlohmann::json hostileValue(std::mt19937& rng) {
  switch (std::uniform_int_distribution<int>(0, 15)(rng)) {
    case 0: return "red";
    case 1: return -1;
    case 2: return 2;
    case 3: return 1e30;
    case 4: return -1e300;
    case 5: return nullptr;
    case 6: return nlohmann::json::array();
    case 7: return nlohmann::json::object();
    case 8: return true;
    case 9: return "NaN";
    case 10: return 4294967296.0;
    case 11: return 0;
    case 12: return {1, 1};
    case 13: return "evil\x1b[2J";
    case 14: return 0.5;
    default: return 65536;
  }
}

/// Every value in a JSON document, as pointers ("/materials/0/name").
void collectPointers(const nlohmann::json& j, const std::string& at, std::vector<std::string>& out) {
  out.push_back(at);
  if (j.is_object())
    for (const auto& [key, value] : j.items()) collectPointers(value, at + "/" + key, out);
  else if (j.is_array())
    for (std::size_t i = 0; i < j.size(); ++i) collectPointers(j[i], at + "/" + std::to_string(i), out);
}

/// One to three structural mutations: a value replaced by a hostile one, a member erased, a value wrapped in an array.
std::string mutateJson(nlohmann::json doc, std::mt19937& rng) {
  int edits = std::uniform_int_distribution<int>(1, 3)(rng);
  for (int e = 0; e < edits; ++e) {
    std::vector<std::string> pointers;
    collectPointers(doc, "", pointers);
    const std::string at = pointers[std::uniform_int_distribution<std::size_t>(1, pointers.size() - 1)(rng)];
    const nlohmann::json::json_pointer p(at);
    switch (std::uniform_int_distribution<int>(0, 3)(rng)) {
      case 0:
      case 1: doc[p] = hostileValue(rng); break;
      case 2: {
        nlohmann::json& parent = doc[p.parent_pointer()];
        if (parent.is_object()) parent.erase(p.back());
        else if (parent.is_array() && !parent.empty()) parent.erase(parent.size() - 1);
        break;
      }
      default: doc[p] = nlohmann::json::array({doc[p]}); break;
    }
  }
  return doc.dump();
}

/// Byte-level damage: a byte replaced (an ESC among them), the text cut short, a control sequence inserted.
std::string mutateBytes(std::string text, std::mt19937& rng, std::size_t within = 0) {
  std::uniform_int_distribution<std::size_t> where(0, (within ? std::min(within, text.size()) : text.size()) - 1);
  switch (std::uniform_int_distribution<int>(0, 2)(rng)) {
    case 0:
      for (int i = 0; i < 4; ++i) text[where(rng)] = static_cast<char>(std::uniform_int_distribution<int>(0, 255)(rng));
      break;
    case 1: text.resize(where(rng)); break;
    default: text.insert(where(rng), "\x1b[2J\"1e999"); break;
  }
  return text;
}

bool allFinite(const std::string& pfm) {
  Image image = readImage(pfm);
  for (const glm::vec3& p : image.pixels)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return false;
  return true;
}

// A small fixed-seed mutator over the bundled scenes and the default settings file, run through the binary as a user
// would: every case must end with a documented exit status (0, 2 usage, 3 input), a failure with exactly one error
// line naming the mutated file, a success with finite pixels and no temporary left behind. The counts are recorded in
// docs/benchmarks.md ("Fuzzing the inputs").
TEST(HostileFuzz, MutatedScenesAndSettingsEndCleanly) {
  std::vector<std::string> scenes;
  for (const auto& e : fs::directory_iterator(kAssets + "/scenes"))
    if (e.path().extension() == ".gltf") scenes.push_back(e.path().string());
  std::sort(scenes.begin(), scenes.end());
  ASSERT_FALSE(scenes.empty());
  const nlohmann::json defaults = nlohmann::json::parse(settingsToJson(Settings{}));
  const std::string refPfm = test::tmpPath("ref.pfm"), litScene = test::tmpPath("lit.gltf");
  writeImage(refPfm, Image(4, 4, glm::vec3(0.5f)));
  const std::string pfmText = readText(refPfm);
  fs::copy_file(kScene, litScene, fs::copy_options::overwrite_existing);
  const nlohmann::json lights = nlohmann::json::parse(lightsToJson(loadScene(kScene)));
  // The suite's seed is fixed; VPLAB_FUZZ_SEED explores others (a failure there is a finding for a test of its own).
  const char* seedText = std::getenv("VPLAB_FUZZ_SEED");
  std::mt19937 rng(seedText ? static_cast<unsigned>(std::strtoul(seedText, nullptr, 10)) : 27u);
  const std::string out = test::tmpPath("out.pfm");
  const auto start = std::chrono::steady_clock::now();
  // A fixed number of cases, so that the seed checks the same inputs on any machine at any load (a time bound made the
  // count, and the test's verdict, depend on the load): 400 take about a minute in Release; under the sanitizers each
  // case's process costs about 0.6 s, and 100 cases are the same minute.
#if defined(__SANITIZE_ADDRESS__)
  const int kCases = 100;
#else
  const int kCases = 400;
#endif
  int cases = 0, successes = 0, statusCount[8] = {};
  for (; cases < kCases; ++cases) {
    const int kind = std::uniform_int_distribution<int>(0, 11)(rng);
    std::string input, command;
    fs::remove(out);
    fs::remove(out + ".json");
    if (kind == 10) {  // an image to compare: the PFM header (and a little of the raster) damaged
      input = test::tmpPath("case.pfm");
      writeText(input, mutateBytes(pfmText, rng, 24));
      command = "compare " + input + " " + refPfm;
    } else if (kind == 11) {  // the lights sidecar the editor saves beside a scene
      input = litScene + ".lights.json";
      writeText(input, mutateJson(lights, rng));
      command = std::uniform_int_distribution<int>(0, 1)(rng) == 0
                    ? "info " + litScene
                    : "render " + litScene + " --size 8x8 --vpl-count 16 -o " + out;
    } else if (kind < 7) {  // a scene: 5 in 12 structural, 2 in 12 byte damage
      const std::string& seed = scenes[std::uniform_int_distribution<std::size_t>(0, scenes.size() - 1)(rng)];
      std::string text = readText(seed);
      input = test::tmpPath("case.gltf");
      writeText(input, kind < 5 ? mutateJson(nlohmann::json::parse(text), rng) : mutateBytes(text, rng));
      const int verb = std::uniform_int_distribution<int>(0, 2)(rng);
      command = verb == 0   ? "info " + input
                : verb == 1 ? "reference " + input + " --size 8x8 --samples-per-pixel 1 -o " + out
                            : "render " + input + " --size 8x8 --vpl-count 16 -o " + out;
    } else {  // a settings file (3 in 12), the flags that bound the work given after it
      input = test::tmpPath("case.json");
      writeText(input, kind < 9 ? mutateJson(defaults, rng) : mutateBytes(defaults.dump(2), rng));
      command = "render " + kScene + " --settings " + input + " --size 8x8 --vpl-count 16 -o " + out;
    }
    CliRun r = vplab(command);
    const std::string where = "case " + std::to_string(cases) + ": vplab " + command + "\n" + r.out;
    ASSERT_TRUE(r.status == 0 || r.status == 2 || r.status == 3) << "exit status " << r.status << "\n" << where;
    ++statusCount[r.status];
    EXPECT_FALSE(contains(r.out, "\x1b")) << where;
    EXPECT_FALSE(contains(r.out, "json.exception")) << where;
    EXPECT_FALSE(contains(r.out, "basic_filebuf")) << where;
    if (r.status == 0) {
      ++successes;
      if (fs::exists(out)) {
        EXPECT_TRUE(allFinite(out)) << "non-finite pixel\n" << where;
      }
    } else {
      int errorLines = 0;
      std::string line, errorLine;
      std::istringstream lines(r.out);
      while (std::getline(lines, line))
        if (line.rfind("vplab ", 0) == 0 && !contains(line, ": warning: ") && !contains(line, ": staged ") &&
            !contains(line, "zero power")) {
          ++errorLines;
          errorLine = line;
        }
      EXPECT_EQ(errorLines, 1) << where;
      EXPECT_TRUE(contains(errorLine, input)) << "the error does not name the input\n" << where;
    }
    std::size_t temporaries = 0;
    for (const auto& e : fs::directory_iterator(test::tmpDir()))
      if (contains(e.path().filename().string(), ".tmp-")) ++temporaries;
    EXPECT_EQ(temporaries, 0u) << where;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("fuzz: %d cases in %.1f s: %d successes, %d usage errors (exit 2), %d input errors (exit 3)\n", cases,
              seconds, successes, statusCount[2], statusCount[3]);
}

}  // namespace
}  // namespace vplab
