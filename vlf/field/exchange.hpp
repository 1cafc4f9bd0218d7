// exchange.hpp — the exchange buffer X(omega, s, t, P) of VLF §4.1: for every ray a
// fragment P covers in a tile, the fragment Q adjacent to P along that ray such that the
// two face each other and nothing lies between them. X(P) = Q <=> X(Q) = P.
//
// Built on the fly for a whole tile at once (the tile's layered depth image: per ray, the
// fragments it crosses sorted by depth), then discarded — never stored (DESIGN §4).
#pragma once

#include <cstdint>
#include <vector>

#include "vlf/field/psf.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

// Partner codes besides a fragment index.
inline constexpr int32_t kEscaped = -1;  // nothing in front of P along its front side
inline constexpr int32_t kBlocked = -2;  // the next surface in front of P shows its back
// ... a parallel face of the same orientation within `seal_gap` of P: P is pressed
// against the back of another surface (a lamp just under a ceiling, a mirror panel on a
// wall), so the ray is shut, not a path (sealed_areas.hpp).
inline constexpr int32_t kSealed = -3;

struct TileExchange {
    // Indexed by fragment.ray_offset + k, k the ray's index in the fragment's edge table
    // (row-major order, EdgeTable::for_each_ray).
    std::vector<int32_t> partner;       // fragment index in the tile, kEscaped or kBlocked
    std::vector<uint32_t> partner_ray;  // k of the same ray in the partner's edge table
    std::vector<float> depth;           // rotated z of the fragment on that ray
};

// Scratch buffers, reused from tile to tile by one worker.
struct ExchangeScratch {
    std::vector<uint32_t> count;  // per ray of the tile
    struct Entry {
        double depth;
        int32_t fragment;
        uint32_t k;
        int8_t facing;
    };
    std::vector<Entry> entries;
};

// `seal_gap`: blocked rays whose back face lies closer than this (rotated z, normalised
// units) are kSealed; 0 keeps every such ray kBlocked.
void build_exchange(const Scene& scene, const Psf& psf, const Tile& tile, TileExchange& out,
                    ExchangeScratch& scratch, double seal_gap = 0.0);

}  // namespace vlf
