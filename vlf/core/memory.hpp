// memory.hpp — the process's resident memory, for the reports' memory figures, and the
// pages its heap is made of.
#pragma once

#include <cstdint>
#include <string>

namespace vlf {

int64_t peak_rss_bytes();     // the most resident memory so far (getrusage)
int64_t current_rss_bytes();  // resident memory now (/proc/self/statm)

// Restarts the program (execv of /proc/self/exe with `argv`) with glibc's malloc set up for
// a bake's gigabytes (GLIBC_TUNABLES, read only at start-up): the heap on transparent huge
// pages (glibc.malloc.hugetlb=1), blocks below 32 MiB taken from the heap rather than
// mapped and unmapped one by one (mmap_threshold), freed memory kept for the next phase
// rather than handed back to the kernel (trim_threshold) and the heap grown 64 MiB at a
// time (top_pad). A tunable the user's GLIBC_TUNABLES already names (even with an empty
// value), or whose older MALLOC_*_ variable the user sets, is left as the user set it (for
// example glibc.malloc.hugetlb=0); when all four are, there is no restart. The restarted
// program never restarts again (VLF_HEAP_RESTARTED marks it, and it removes the mark).
// Returns when it does not restart, or when the restart fails (GLIBC_TUNABLES then as it
// was). To be called first in main(), before any thread or file. A bake's arrays are
// gigabytes read at random: with 2 MiB pages their first touch costs a fault per 2 MiB
// instead of one per 4 KiB, and their reads miss the TLB far less; each fresh page costs a
// fault and zeroing, so memory a phase frees is better reused by the next than returned
// (BENCHMARKS.md "Glass", its paragraphs "Huge pages" and "The heap kept").
void restart_with_heap_settings(char** argv);
// GLIBC_TUNABLES as this process runs with it (for the report).
std::string heap_tunables();
// Whether this process's heap was asked for huge pages (GLIBC_TUNABLES sets
// glibc.malloc.hugetlb=1), and how much of its memory is on them now (AnonHugePages of
// /proc/self/smaps_rollup; 0 where the kernel gives none).
bool heap_on_huge_pages();
int64_t huge_page_bytes();

}  // namespace vlf
