#include "vlf/field/exchange.hpp"

#include <algorithm>
#include <cmath>

namespace vlf {

namespace {
// Depths (normalised units, the scene inside the unit ball) closer than this are the same
// surface position: far above rounding (1e-16), far below any real gap.
constexpr double kCoincident = 1e-9;

using Entry = ExchangeScratch::Entry;

// The tile's layered depth image: a counting sort of its (ray, fragment) pairs by ray,
// filled in fragment order (= face order, so equal depths resolve deterministically).
// Afterwards the entries of ray r are scratch.entries[count[r], count[r + 1]); each
// fragment's depth on its rays goes to out.depth.
void sort_into_rays(const Scene& scene, const Psf& psf, const Tile& tile, TileExchange& out,
                    ExchangeScratch& scratch) {
    const int m = psf.tile_size;
    const int rays = m * m;
    scratch.count.assign(static_cast<size_t>(rays) + 1, 0);
    for (const Fragment& f : tile.fragments)
        tile.edge_table(f).for_each_ray([&](int u, int v, int) { ++scratch.count[v * m + u + 1]; });
    for (int r = 0; r < rays; ++r) scratch.count[r + 1] += scratch.count[r];
    scratch.entries.resize(tile.covered);

    const int i0 = tile.s * m, j0 = tile.t * m;
    std::vector<uint32_t> start(scratch.count.begin(), scratch.count.end());  // fill cursors
    for (int32_t fi = 0; fi < static_cast<int32_t>(tile.fragments.size()); ++fi) {
        const Fragment& f = tile.fragments[fi];
        const Face& face = scene.faces[f.face];
        const Vec3 nr = psf.rotation * face.normal;
        tile.edge_table(f).for_each_ray([&](int u, int v, int k) {
            const double x = psf.ray_x(i0 + u), y = psf.ray_y(j0 + v);
            const double z = (face.plane_offset - nr.x * x - nr.y * y) / nr.z;
            const uint32_t slot = start[v * m + u]++;
            scratch.entries[slot] = {z, fi, static_cast<uint32_t>(k), f.facing};
            out.depth[f.ray_offset + k] = static_cast<float>(z);
        });
    }
}

// One ray's entries [first, first + cnt) in depth order (ties: the surface facing -z
// first), coincident opposite-facing pairs settled.
void order_ray(const Scene& scene, const Tile& tile, Entry* first, uint32_t cnt) {
    std::sort(first, first + cnt, [](const Entry& a, const Entry& c) {
        if (a.depth != c.depth) return a.depth < c.depth;
        if (a.facing != c.facing) return a.facing < c.facing;
        return a.fragment < c.fragment;
    });
    // Coincident opposite-facing surfaces (equal depth up to rounding): the two sides
    // of a two-sided face look away from each other ([-1, +1]); any other pair is two
    // solids in contact, whose fronts look into each other ([+1, -1]): they exchange
    // only with each other, so nothing leaks through the contact.
    for (uint32_t q = 0; q + 1 < cnt; ++q) {
        Entry& a = first[q];
        Entry& c = first[q + 1];
        if (a.facing == c.facing || std::abs(a.depth - c.depth) > kCoincident) continue;
        const bool twins =
            scene.faces[tile.fragments[a.fragment].face].twin == tile.fragments[c.fragment].face;
        if ((twins && a.facing > 0) || (!twins && a.facing < 0)) std::swap(a, c);
        ++q;  // a pair is settled; do not reorder it with the next entry
    }
}

// Pairs every entry of one ordered ray with the neighbour its front side looks at: a
// fragment facing it is its partner; none is kEscaped; a back is kSealed or kBlocked.
void pair_ray(const Scene& scene, const Tile& tile, const Entry* first, uint32_t cnt,
              double seal_gap, TileExchange& out) {
    for (uint32_t q = 0; q < cnt; ++q) {
        const Entry& cur = first[q];
        const uint32_t slot = tile.fragments[cur.fragment].ray_offset + cur.k;
        const Entry* next = nullptr;
        if (cur.facing > 0) {
            if (q + 1 < cnt) next = &first[q + 1];
        } else {
            if (q > 0) next = &first[q - 1];
        }
        if (next == nullptr) {
            out.partner[slot] = kEscaped;
        } else if (next->facing == -cur.facing) {
            out.partner[slot] = next->fragment;
            out.partner_ray[slot] = next->k;
        } else {
            // Sealed: the back in front is a parallel face of the same orientation
            // within the gap (sealed_areas.hpp), not any back face that happens to be
            // near (a wall standing on the floor absorbs what the floor sends into it).
            const Face& a = scene.faces[tile.fragments[cur.fragment].face];
            const Face& b = scene.faces[tile.fragments[next->fragment].face];
            const bool sealed = std::abs(next->depth - cur.depth) < seal_gap &&
                                glm::dot(a.normal, b.normal) > 1.0 - 1e-6;
            out.partner[slot] = sealed ? kSealed : kBlocked;
        }
    }
}

}  // namespace

void build_exchange(const Scene& scene, const Psf& psf, const Tile& tile, TileExchange& out,
                    ExchangeScratch& scratch, double seal_gap) {
    out.partner.assign(tile.covered, kEscaped);
    out.partner_ray.assign(tile.covered, 0);
    out.depth.assign(tile.covered, 0.0f);
    sort_into_rays(scene, psf, tile, out, scratch);
    // Per ray: sort by depth, settle coincident pairs, then pair neighbours that face each
    // other.
    const int rays = psf.tile_size * psf.tile_size;
    for (int r = 0; r < rays; ++r) {
        Entry* first = scratch.entries.data() + scratch.count[r];
        const uint32_t cnt = scratch.count[r + 1] - scratch.count[r];
        order_ray(scene, tile, first, cnt);
        pair_ray(scene, tile, first, cnt, seal_gap, out);
    }
}

}  // namespace vlf
