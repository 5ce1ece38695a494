#include "app/huge_page_malloc.h"

#include <gnu/libc-version.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>

#if defined(__SANITIZE_ADDRESS__)
#define VPLAB_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define VPLAB_ASAN 1
#endif
#endif

namespace vplab::app {

namespace {

/// The kernel's THP mode is `madvise`: only madvised memory gets huge pages, which is what the tunable adds.
bool thpInMadviseMode() {
  std::ifstream in("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return text.find("[madvise]") != std::string::npos;
}

/// glibc.malloc.hugetlb exists from glibc 2.35 on; older versions ignore it, and the second start would be wasted.
bool glibcHasHugetlbTunable() {
  int major = 0, minor = 0;
  if (std::sscanf(gnu_get_libc_version(), "%d.%d", &major, &minor) != 2) return false;
  return major > 2 || (major == 2 && minor >= 35);
}

}  // namespace

void reexecWithHugePageMalloc(char** argv) {
#ifdef VPLAB_ASAN
  (void)argv;
#else
  const char* set = std::getenv("GLIBC_TUNABLES");
  const std::string tunables = set ? set : "";
  // Set already, by the user or by this function in the process that started this one.
  if (tunables.find("glibc.malloc.hugetlb") != std::string::npos) return;
  if (!glibcHasHugetlbTunable() || !thpInMadviseMode()) return;
  const std::string value = (tunables.empty() ? "" : tunables + ":") + "glibc.malloc.hugetlb=1";
  if (setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
  execv("/proc/self/exe", argv);
  // Not re-executed (no /proc, ...): go on with 4 KiB pages and leave the environment as it was, so that the
  // programs this one starts do not inherit a tunable this process did not get.
  if (set)
    setenv("GLIBC_TUNABLES", tunables.c_str(), 1);
  else
    unsetenv("GLIBC_TUNABLES");
#endif
}

}  // namespace vplab::app
