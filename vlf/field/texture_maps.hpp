// texture_maps.hpp — the diffuse texture maps of every chart (VLF §4.1; charts.hpp): P^C (current,
// unshot), P^N (next) and P^T (total). They hold *power* per texel (W in normalised
// units, RGB), so the energy ledger closes to rounding error (DESIGN §5); radiance is
// derived: L = P^T / (pi * the chart's surface area in the texel).
#pragma once

#include <cstddef>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

struct TextureMaps {
    std::vector<size_t> offset;  // charts + 1 entries: chart c owns [offset[c], offset[c+1])
    std::vector<Rgb> current;    // P^C
    std::vector<Rgb> next;       // P^N
    std::vector<Rgb> total;      // P^T: emitted + reflected outgoing power, all cycles

    explicit TextureMaps(const Scene& scene);
    TextureMaps() = default;
    size_t texels() const { return current.size(); }
    size_t begin(int chart) const { return offset[chart]; }
    size_t count(int chart) const { return offset[chart + 1] - offset[chart]; }

    static Rgb sum(const std::vector<Rgb>& map, size_t begin, size_t count);
    // Outgoing radiance (W m^-2 sr^-1) of texel t of chart c from P^T; 0 off the chart.
    double radiance(const Chart& c, size_t texel, int channel) const;
    Rgb radiance(const Chart& c, size_t texel) const;
};

}  // namespace vlf
