// memory.hpp — the process's resident memory, for the reports' memory figures.
#pragma once

#include <cstdint>

namespace vlf {

int64_t peak_rss_bytes();     // the most resident memory so far (getrusage)
int64_t current_rss_bytes();  // resident memory now (/proc/self/statm)

}  // namespace vlf
