// coverage.hpp — how many rays a face covers in each PSF (VLF §3), kept only for the faces
// that need the count before their directions are rasterised: stored faces (their
// directional radiance maps are sized by it, radiance_maps.hpp) and emitters (they send in
// the first cycle, VLF §4.4 eq. (3)). A million-face scene holds rows for a handful.
#pragma once

#include <cstdint>
#include <vector>

#include "vlf/core/error.hpp"

namespace vlf {

struct Coverage {
    int directions = 0;
    int rows = 0;
    std::vector<int32_t> row;     // per face: its row, or -1 when not measured
    std::vector<uint32_t> count;  // d * rows + row[f]: covered rays

    bool measured(int face) const { return row[face] >= 0; }
    uint32_t operator()(int d, int face) const {
        VLF_CHECK(row[face] >= 0);
        return count[size_t(d) * rows + row[face]];
    }
    int64_t bytes() const {
        return static_cast<int64_t>(row.size() * sizeof(int32_t) + count.size() * sizeof(uint32_t));
    }
};

}  // namespace vlf
