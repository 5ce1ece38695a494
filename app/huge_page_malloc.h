#pragma once
// Transparent huge pages for malloc's large blocks in the GL commands, without the user setting an environment
// variable. llvmpipe zero-fills every texture it allocates (shadow-map arrays, screen targets), and on 4 KiB pages
// each page of them costs a page fault: a third of a cold `vplab preview`'s samples (docs/benchmarks.md, "The cold
// headless preview"). glibc (2.35 and later) madvises its large blocks MADV_HUGEPAGE under the tunable
// glibc.malloc.hugetlb=1, but reads tunables only when the process starts and has no mallopt() for it, so the
// process runs itself again with the tunable added.

namespace vplab::app {

/// Re-executes this program (/proc/self/exe, same arguments) with glibc.malloc.hugetlb=1 appended to GLIBC_TUNABLES,
/// keeping the tunables already there, when all of these hold: the kernel's transparent huge pages are in `madvise`
/// mode (in `always` mode the kernel uses them anyway, in `never` the tunable does nothing), glibc is 2.35 or later,
/// the build is not under AddressSanitizer (its allocator is not glibc's), and GLIBC_TUNABLES does not name
/// glibc.malloc.hugetlb yet (so it runs at most once, and `GLIBC_TUNABLES=glibc.malloc.hugetlb=0` turns it off).
/// Returns only when it does not re-execute, or when the exec fails (the process then goes on as it is).
void reexecWithHugePageMalloc(char** argv);

}  // namespace vplab::app
