#pragma once
// Where a test writes its files. ctest runs every test as its own process, two or more at a time, so a file name
// that two tests share (a scene several tests build, say) would be rewritten by one while the other reads it: each
// test writes under its own directory, VPLAB_TEST_TMP/<Suite>.<Test>.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace vplab::test {

inline std::string tmpDir() {
  const testing::TestInfo* info = testing::UnitTest::GetInstance()->current_test_info();
  std::string name = info ? std::string(info->test_suite_name()) + "." + info->name() : "outside-a-test";
  for (char& c : name)
    if (c == '/') c = '_';  // parametrised suites and tests carry "Prefix/" and "/N"
  const std::filesystem::path dir = std::filesystem::path(VPLAB_TEST_TMP) / name;
  std::filesystem::create_directories(dir);
  return dir.string();
}

/// A file of that name in the test's own directory.
inline std::string tmpPath(const std::string& name) {
  return tmpDir() + "/" + name;
}

}  // namespace vplab::test
