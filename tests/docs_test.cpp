// The documentation's examples, run as written: every fenced block whose info string is "sh example" in README.md
// and docs/*.md is a list of commands (one per line) that must exit 0, unless its comment says "# exits N"; a
// comment "prints TEXT" names text the output must contain. The commands run in a fresh folder whose assets/ is the
// repository's, with `vplab` replaced by the built executable, so a renamed flag or a changed output breaks this
// test instead of the reader's first try. (The suite runs the GL preview, hence its name and the "gl" label.)

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "tests/test_tmp.h"

namespace vplab {
namespace {

namespace fs = std::filesystem;

struct DocCommand {
  std::string file;
  int line = 0;
  std::string command;     ///< as written, comment removed
  int expectedStatus = 0;  ///< "# exits N"
  std::string mustPrint;   ///< "prints TEXT" (to the end of the comment)
};

/// The commands of every "```sh example" block of one Markdown file.
std::vector<DocCommand> exampleCommands(const fs::path& path) {
  std::vector<DocCommand> commands;
  std::ifstream in(path);
  std::string line;
  bool inExample = false;
  int number = 0;
  static const std::regex exits(R"(exits (\d+))"), prints(R"(prints (.*)$)");
  while (std::getline(in, line)) {
    ++number;
    if (line.rfind("```", 0) == 0) {
      inExample = !inExample && line == "```sh example";
      continue;
    }
    if (!inExample || line.empty() || line[0] == '#') continue;
    DocCommand c;
    c.file = path.filename().string();
    c.line = number;
    std::string comment;
    if (std::size_t hash = line.find(" #"); hash != std::string::npos) {
      comment = line.substr(hash + 2);
      line = line.substr(0, hash);
    }
    while (!line.empty() && line.back() == ' ') line.pop_back();
    c.command = line;
    std::smatch m;
    if (std::regex_search(comment, m, exits)) c.expectedStatus = std::stoi(m[1]);
    if (std::regex_search(comment, m, prints)) c.mustPrint = m[1];
    commands.push_back(c);
  }
  return commands;
}

std::vector<DocCommand> allExamples() {
  const fs::path root = fs::path(VPLAB_TEST_ASSETS).parent_path();
  std::vector<fs::path> files = {root / "README.md"};
  for (const auto& e : fs::directory_iterator(root / "docs"))
    if (e.path().extension() == ".md") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  std::vector<DocCommand> all;
  for (const fs::path& f : files) {
    std::vector<DocCommand> c = exampleCommands(f);
    all.insert(all.end(), c.begin(), c.end());
  }
  return all;
}

TEST(DocsExtractor, ReadsCommandsCommentsAndExpectations) {
  fs::path md = fs::path(vplab::test::tmpDir()) / "docs_extractor.md";
  std::ofstream(md) << "text\n```sh\nvplab not-an-example\n```\n```sh example\n# a comment line\nvplab info x.gltf\n"
                       "\nvplab compare a b --max-relmse 0  # exits 1, prints FAIL: relmse\n```\n```sh example\n"
                       "vplab info y.gltf  # prints PASS\n```\n";
  std::vector<DocCommand> c = exampleCommands(md);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c[0].command, "vplab info x.gltf");
  EXPECT_EQ(c[0].expectedStatus, 0);
  EXPECT_EQ(c[1].command, "vplab compare a b --max-relmse 0");
  EXPECT_EQ(c[1].expectedStatus, 1);
  EXPECT_EQ(c[1].mustPrint, "FAIL: relmse");
  EXPECT_EQ(c[2].mustPrint, "PASS");
  EXPECT_EQ(c[2].line, 12);
}

TEST(DocsExamplesGl, RunAsWritten) {
  std::vector<DocCommand> commands = allExamples();
  ASSERT_GE(commands.size(), 5u) << "the guide's examples must be found";
  const fs::path root = fs::path(VPLAB_TEST_ASSETS).parent_path();
  const fs::path work = fs::path(vplab::test::tmpDir()) / "docs_examples";
  fs::remove_all(work);
  fs::create_directories(work);
  fs::create_directory_symlink(root / "assets", work / "assets");
  for (const DocCommand& c : commands) {
    ASSERT_EQ(c.command.rfind("vplab ", 0), 0u) << c.file << ":" << c.line << ": examples start with vplab";
    std::string shell = "cd '" + work.string() + "' && " + std::string(VPLAB_BINARY) + c.command.substr(5) + " 2>&1";
    FILE* pipe = popen(shell.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string output;
    char buffer[512];
    while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
    int status = pclose(pipe);
    int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    EXPECT_EQ(code, c.expectedStatus) << c.file << ":" << c.line << ": " << c.command << "\n" << output;
    if (!c.mustPrint.empty()) {
      EXPECT_NE(output.find(c.mustPrint), std::string::npos)
          << c.file << ":" << c.line << ": " << c.command << " must print '" << c.mustPrint << "'\n"
          << output;
    }
  }
}

}  // namespace
}  // namespace vplab
