#include "vlf/core/memory.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
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
constexpr const char* kTunable = "glibc.malloc.hugetlb";  // glibc >= 2.35
}  // namespace

void restart_with_huge_pages(char** argv) {
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    if (tunables != nullptr && std::strstr(tunables, kTunable) != nullptr) return;
    std::string value = tunables != nullptr && *tunables != '\0' ? std::string(tunables) + ":" : "";
    value += std::string(kTunable) + "=1";
    if (setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0) return;
    execv("/proc/self/exe", argv);
    // (Not restarted: the program goes on with the heap it has.)
}

bool heap_on_huge_pages() {
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    return tunables != nullptr &&
           std::strstr(tunables, (std::string(kTunable) + "=1").c_str()) != nullptr;
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
