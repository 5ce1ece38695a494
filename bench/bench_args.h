#pragma once
// Command-line values of the benchmark programs (bench/*.cpp): they take a few plain options, so they parse argv
// themselves instead of linking the app's CLI.

#include <cstdio>
#include <cstdlib>
#include <string>

namespace vplab {

/// The value following option argv[i], advancing i past it; a missing value exits with status 2 and a message.
inline std::string benchOptionValue(int argc, char** argv, int& i) {
  if (i + 1 >= argc) {
    std::fprintf(stderr, "%s: %s needs a value\n", argv[0], argv[i]);
    std::exit(2);
  }
  return argv[++i];
}

}  // namespace vplab
