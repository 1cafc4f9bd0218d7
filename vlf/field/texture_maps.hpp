// texture_maps.hpp — the diffuse texture maps of every face (VLF §4.1): P^C (current,
// unshot), P^N (next) and P^T (total). They hold *power* per texel (W in normalised
// units, RGB), so the energy ledger closes to rounding error (DESIGN §5); radiance is
// derived: L = P^T / (pi * texel area inside the face).
#pragma once

#include <cstddef>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

struct TextureMaps {
    std::vector<size_t> offset;  // faces + 1 entries: face f owns [offset[f], offset[f+1])
    std::vector<Rgb> current;    // P^C
    std::vector<Rgb> next;       // P^N
    std::vector<Rgb> total;      // P^T: emitted + reflected outgoing power, all cycles

    explicit TextureMaps(const Scene& scene);
    TextureMaps() = default;
    size_t texels() const { return current.size(); }
    size_t begin(int face) const { return offset[face]; }
    size_t count(int face) const { return offset[face + 1] - offset[face]; }

    static Rgb sum(const std::vector<Rgb>& map, size_t begin, size_t count);
    // Outgoing radiance (W m^-2 sr^-1) of texel t of face f from P^T; 0 outside the face.
    double radiance(const Face& f, size_t texel, int channel) const;
    Rgb radiance(const Face& f, size_t texel) const;
};

}  // namespace vlf
