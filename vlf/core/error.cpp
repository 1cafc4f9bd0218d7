#include "vlf/core/error.hpp"

#include <cstdio>
#include <cstdlib>

namespace vlf {

void check_failed(const char* expr, const char* file, int line) {
    std::fprintf(stderr, "internal error: check '%s' failed at %s:%d\n", expr, file, line);
    std::abort();
}

}  // namespace vlf
