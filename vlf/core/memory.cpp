#include "vlf/core/memory.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

namespace vlf {

int64_t peak_rss_bytes() {
    rusage u{};
    if (getrusage(RUSAGE_SELF, &u) != 0) return 0;
    return static_cast<int64_t>(u.ru_maxrss) * 1024;  // Linux: kilobytes
}

int64_t current_rss_bytes() {
    std::FILE* f = std::fopen("/proc/self/statm", "r");
    if (f == nullptr) return 0;
    long size = 0, resident = 0;
    const int n = std::fscanf(f, "%ld %ld", &size, &resident);
    std::fclose(f);
    return n == 2 ? static_cast<int64_t>(resident) * sysconf(_SC_PAGESIZE) : 0;
}

namespace {

constexpr const char* kHugePages = "glibc.malloc.hugetlb";  // glibc >= 2.35

// What the restart asks of glibc's malloc (docs/propagation.md §10), each tunable unless the
// user's GLIBC_TUNABLES names it or the user sets its older environment variable.
struct HeapTunable {
    const char* name;
    const char* value;
    const char* legacy;  // the MALLOC_*_ variable glibc also reads (a tunable overrides it)
};
constexpr HeapTunable kHeapTunables[] = {
    // The heap on transparent huge pages: a first touch costs a fault per 2 MiB, not per
    // 4 KiB, and random reads miss the TLB far less.
    {kHugePages, "1", nullptr},
    // Blocks below 32 MiB (glibc's ceiling for this tunable) come from the heap and are
    // reused once freed; above the default (128 KiB, raised only as mapped blocks are
    // freed) each was mapped, unmapped when freed, and faulted in afresh when made again.
    {"glibc.malloc.mmap_threshold", "33554432", "MALLOC_MMAP_THRESHOLD_"},
    // Freed memory at the heap's top stays in the process for the next phase rather than
    // going back to the kernel at every large free (1 TiB: never, in practice).
    {"glibc.malloc.trim_threshold", "1099511627776", "MALLOC_TRIM_THRESHOLD_"},
    // The heap grows 64 MiB at a time.
    {"glibc.malloc.top_pad", "67108864", "MALLOC_TOP_PAD_"},
};
// Set in the restarted program's environment: it never restarts again.
constexpr const char* kRestarted = "VLF_HEAP_RESTARTED";

// The value GLIBC_TUNABLES (`tunables`: name=value entries, ':'-separated) gives `name`
// (its last entry, the one glibc applies), or none where it names it not.
std::optional<std::string> tunable_value(const char* tunables, const std::string& name) {
    if (tunables == nullptr) return std::nullopt;
    const std::string list = std::string(":") + tunables + ":";
    const size_t at = list.rfind(":" + name + "=");
    if (at == std::string::npos) return std::nullopt;
    const size_t begin = at + name.size() + 2;
    return list.substr(begin, list.find(':', begin) - begin);
}

}  // namespace

void restart_with_heap_settings(char** argv) {
    if (std::getenv(kRestarted) != nullptr) {  // this is the restarted program
        unsetenv(kRestarted);                  // (not handed on to what it runs)
        return;
    }
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    const std::optional<std::string> before =
        tunables != nullptr ? std::optional<std::string>(tunables) : std::nullopt;
    std::string value = before.value_or("");
    bool added = false;
    for (const HeapTunable& t : kHeapTunables) {
        if (tunable_value(tunables, t.name) || (t.legacy && std::getenv(t.legacy))) continue;
        if (!value.empty()) value += ":";
        value += std::string(t.name) + "=" + t.value;
        added = true;
    }
    if (!added) return;  // all set by the user
    if (setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
    if (setenv(kRestarted, "1", 1) == 0) execv("/proc/self/exe", argv);
    // Not restarted: the program goes on with the heap it has, and says so in its report.
    if (before)
        setenv("GLIBC_TUNABLES", before->c_str(), 1);
    else
        unsetenv("GLIBC_TUNABLES");
    unsetenv(kRestarted);
}

std::string heap_tunables() {
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    return tunables != nullptr ? std::string(tunables) : std::string();
}

bool heap_on_huge_pages() {
    return tunable_value(std::getenv("GLIBC_TUNABLES"), kHugePages) == std::string("1");
}

int64_t huge_page_bytes() {
    std::FILE* f = std::fopen("/proc/self/smaps_rollup", "r");
    if (f == nullptr) return 0;
    char line[256];
    long kb = 0;
    while (std::fgets(line, sizeof line, f) != nullptr)
        if (std::sscanf(line, "AnonHugePages: %ld kB", &kb) == 1) break;
    std::fclose(f);
    return static_cast<int64_t>(kb) * 1024;
}

}  // namespace vlf
