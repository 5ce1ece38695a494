// The ctest labels come from gtest filters over suite names (tests/CMakeLists.txt, VPLAB_GL_SUITES). This test keeps
// the names and the patterns in step: every suite the gl patterns select is a GL suite by the naming rule, and
// every GL suite is selected, so `ctest -L cpu` runs exactly the tests that need no GL context; and the lists of
// statistical tests (the sanitized run leaves them out) name tests that exist, each in its own group.

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace {

/// gtest's filter syntax for positive patterns: '*' any run, '?' one character, ':' separates patterns.
bool globMatches(const char* pattern, const char* text) {
  if (*pattern == '\0') return *text == '\0';
  if (*pattern == '*') return globMatches(pattern + 1, text) || (*text != '\0' && globMatches(pattern, text + 1));
  if (*text == '\0') return false;
  return (*pattern == '?' || *pattern == *text) && globMatches(pattern + 1, text + 1);
}

bool anyPatternMatches(const std::string& patterns, const std::string& name) {
  std::size_t start = 0;
  while (start <= patterns.size()) {
    std::size_t end = patterns.find(':', start);
    if (end == std::string::npos) end = patterns.size();
    if (globMatches(patterns.substr(start, end - start).c_str(), name.c_str())) return true;
    start = end + 1;
  }
  return false;
}

/// The naming rule: a suite that needs a GL context is called Gl<Name> (GlPreview) or <Name>Gl (DocsExamplesGl).
/// "Gltf...", "Global..." are not GL suites.
bool isGlSuiteName(const std::string& suite) {
  const bool prefix =
      suite.size() > 2 && suite.compare(0, 2, "Gl") == 0 && std::isupper(static_cast<unsigned char>(suite[2]));
  const bool suffix = suite.size() > 2 && suite.compare(suite.size() - 2, 2, "Gl") == 0 &&
                      std::islower(static_cast<unsigned char>(suite[suite.size() - 3]));
  return prefix || suffix;
}

TEST(TestLabels, GlobMatchesLikeGtestFilters) {
  EXPECT_TRUE(globMatches("Gl*.*", "GlPreview.Foo"));
  EXPECT_TRUE(globMatches("*Gl.*", "DocsExamplesGl.RunAsWritten"));
  EXPECT_FALSE(globMatches("Gl*.*", "SceneLoaderValid.GlbLoadsLikeGltf"));
  EXPECT_FALSE(globMatches("*Gl.*", "VslIntegral.GlossyApproximationErrorIsBounded"));
  EXPECT_TRUE(globMatches("*/Gl*.*", "Gl/GlContextTest.Clears/0"));
}

TEST(TestLabels, SuiteNamesSelectTheirGroupExactly) {
  const std::string glPatterns = VPLAB_GL_SUITES;
  const testing::UnitTest& unit = *testing::UnitTest::GetInstance();
  int glTests = 0;
  for (int i = 0; i < unit.total_test_suite_count(); ++i) {
    const testing::TestSuite& suite = *unit.GetTestSuite(i);
    std::string name = suite.name();
    // A parametrised suite is "Prefix/Suite"; the rule applies to the suite itself.
    std::string bare = name.substr(name.find('/') == std::string::npos ? 0 : name.find('/') + 1);
    for (int j = 0; j < suite.total_test_count(); ++j) {
      std::string full = name + "." + suite.GetTestInfo(j)->name();
      bool selected = anyPatternMatches(glPatterns, full);
      EXPECT_EQ(selected, isGlSuiteName(bare))
          << full << ": the gl label's patterns (" << glPatterns << ") and the suite naming rule (Gl<Name> or "
          << "<Name>Gl for tests that need a GL context) disagree; rename the suite";
      glTests += selected;
    }
  }
  EXPECT_GT(glTests, 0);
}

/// The full names ("Suite.Test", "Prefix/Suite.Test/Param") of every test in the binary.
std::vector<std::string> allTestNames() {
  const testing::UnitTest& unit = *testing::UnitTest::GetInstance();
  std::vector<std::string> names;
  for (int i = 0; i < unit.total_test_suite_count(); ++i) {
    const testing::TestSuite& suite = *unit.GetTestSuite(i);
    for (int j = 0; j < suite.total_test_count(); ++j)
      names.push_back(std::string(suite.name()) + "." + suite.GetTestInfo(j)->name());
  }
  return names;
}

// Every pattern of tests/statistical-tests.txt selects at least one test, and only tests of its own group: a renamed
// test would otherwise drop out of the list silently (and back into the sanitized run), and a GL test in the cpu list
// would lose its GL label.
TEST(TestLabels, StatisticalPatternsNameExistingTestsOfTheirGroup) {
  const std::string path = std::string(VPLAB_TEST_ASSETS) + "/../tests/statistical-tests.txt";
  std::ifstream list(path);
  ASSERT_TRUE(list) << path;
  const std::vector<std::string> names = allTestNames();
  int patterns = 0;
  std::string line;
  while (std::getline(list, line)) {
    std::istringstream words(line);
    std::string group, pattern;
    words >> group >> pattern;
    if (group != "cpu" && group != "gl") continue;
    ++patterns;
    int selected = 0;
    for (const std::string& full : names) {
      if (!globMatches(pattern.c_str(), full.c_str())) continue;
      ++selected;
      const std::string suite = full.substr(0, full.find('.'));
      const std::string bare = suite.substr(suite.find('/') == std::string::npos ? 0 : suite.find('/') + 1);
      EXPECT_EQ(isGlSuiteName(bare), group == "gl") << pattern << " selects " << full << ", a test of the other group";
      EXPECT_NE(bare, "EditorWindow") << pattern << ": the editor's window tests keep their own label";
    }
    EXPECT_GT(selected, 0) << "the statistical pattern " << pattern << " selects no test: rename it with its test";
  }
  EXPECT_GT(patterns, 0);
}

// The sanitized run leaves the OSMesa instances of the two-backend suites out (tests/CMakeLists.txt): each must have
// its EGL twin, which the sanitized run keeps, and be a GL test.
TEST(TestLabels, EveryOsMesaTwinHasItsEglTwin) {
  const std::vector<std::string> names = allTestNames();
  int twins = 0;
  for (const std::string& full : names) {
    if (!globMatches(VPLAB_OSMESA_TWINS, full.c_str())) continue;
    ++twins;
    const std::string egl = full.substr(0, full.size() - std::string("OsMesa").size()) + "Egl";
    EXPECT_NE(std::find(names.begin(), names.end(), egl), names.end()) << full << " has no EGL twin " << egl;
    EXPECT_TRUE(anyPatternMatches(VPLAB_GL_SUITES, full)) << full << " is not a GL test";
  }
  EXPECT_GT(twins, 0) << "the pattern " << VPLAB_OSMESA_TWINS << " selects no test";
}

}  // namespace
