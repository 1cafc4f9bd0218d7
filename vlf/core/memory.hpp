// memory.hpp — the process's resident memory, for the reports' memory figures, and the
// pages its heap is made of.
#pragma once

#include <cstdint>

namespace vlf {

int64_t peak_rss_bytes();     // the most resident memory so far (getrusage)
int64_t current_rss_bytes();  // resident memory now (/proc/self/statm)

// Restarts the program (execv of /proc/self/exe with `argv`) with glibc's malloc asked to
// back the heap with transparent huge pages (GLIBC_TUNABLES glibc.malloc.hugetlb=1, read
// only at start-up), unless GLIBC_TUNABLES already names that tunable (so a user can set
// it to 0, and the restarted program does not restart again). Returns when it does not
// restart (or the restart fails). To be called first in main(), before any thread or file.
// A bake's arrays are gigabytes read at random: with 2 MiB pages their first touch costs a
// fault per 2 MiB instead of one per 4 KiB, and their reads miss the TLB far less
// (BENCHMARKS.md "Glass", its paragraph "Huge pages").
void restart_with_huge_pages(char** argv);
// Whether this process's heap was asked for huge pages (GLIBC_TUNABLES sets
// glibc.malloc.hugetlb=1), and how much of its memory is on them now (AnonHugePages of
// /proc/self/smaps_rollup; 0 where the kernel gives none).
bool heap_on_huge_pages();
int64_t huge_page_bytes();

}  // namespace vlf
