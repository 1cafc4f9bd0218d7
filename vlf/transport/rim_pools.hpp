// rim_pools.hpp — texels mostly outside their face share their host's estimate.
//
// A texel at a face's rim, partly outside the polygon, is a small area: the few beams
// that touch it in each direction make its received power a noisy estimate (a corner
// sliver of 1 % of a texel sees a piece of a beam or none). After every cycle such a texel
// pools its received power with its host, the neighbouring texel (of the 8) most inside
// the face, when that one is more inside than itself and at least half inside (followed
// to a texel wholly inside where there is one): the pool's power is shared by area, so a
// uniform field stays uniform and the energy of the face is unchanged to rounding
// (docs/propagation.md §3). A rim texel thus shows the mean of itself and its host: the
// rim is resolved at two texels, as a lightmap baker's dilation would.
#pragma once

#include <cstdint>
#include <vector>

#include "vlf/core/math.hpp"
#include "vlf/field/texture_maps.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

struct RimPools {
    std::vector<uint32_t> host;     // per texel (global index into the texture maps)
    std::vector<double> pool_area;  // per host: area of the host and its members
    bool empty() const;
};

RimPools build_rim_pools(const Scene& scene, const TextureMaps& maps);

// Shares each pool's power in `power` (a texture map, e.g. P^N) among its texels by area.
void pool_rim_texels(const RimPools& pools, const Scene& scene, const TextureMaps& maps,
                     std::vector<Rgb>& power);

}  // namespace vlf
