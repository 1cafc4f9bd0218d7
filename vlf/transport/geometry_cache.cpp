// geometry_cache.cpp — a direction's geometry (transport_internal.hpp DirectionGeometry):
// its PSF with the rays grouped by face (VLF §3), the exchange partner of every ray
// (§4.1 exchange buffers) and the beam/texel overlaps (§4.2 continuous clipping); built
// once per direction and kept across cycles within the memory budget.
#include "vlf/core/error.hpp"
#include "vlf/transport/transport_internal.hpp"

namespace vlf {

using namespace transport_detail;

int64_t DirectionGeometry::bytes() const {
    int64_t b = static_cast<int64_t>(sizeof(DirectionGeometry));
    for (const Tile& t : psf.tiles)
        b += static_cast<int64_t>(sizeof(Tile) + t.fragments.size() * sizeof(Fragment) +
                                  t.spans.size() * sizeof(Span));
    b += static_cast<int64_t>(
        (tile_base.size() + faces.size() + face_begin.size() + ov_begin.size()) * sizeof(uint32_t) +
        frags.size() * sizeof(frags[0]) + ov.size() * sizeof(TexelOverlap) +
        partner.size() * sizeof(int32_t) + psf.tile_of.size() * sizeof(int32_t));
    return b;
}

namespace {

// VLF §3: the PSF of the direction, its rays numbered as slots tile by tile, and its
// fragments grouped by face (in tile order within a face).
void rasterise_and_group(const Scene& scene, const Mat3& rot, int d, int N, int m,
                         const Coverage* coverage, DirectionGeometry& g) {
    const size_t nf = scene.faces.size();
    g.psf = rasterise_psf(scene, rot, d, N, m, coverage);
    const Psf& psf = g.psf;
    g.tile_base.resize(psf.tiles.size() + 1);
    g.tile_base[0] = 0;
    for (size_t ti = 0; ti < psf.tiles.size(); ++ti)
        g.tile_base[ti + 1] = g.tile_base[ti] + psf.tiles[ti].covered;
    // Fragments sorted by face (stable: tile order within a face); no per-face array of
    // the whole scene, so a direction costs what its rays cost.
    g.frags.clear();
    for (uint32_t ti = 0; ti < psf.tiles.size(); ++ti)
        for (uint32_t fi = 0; fi < psf.tiles[ti].fragments.size(); ++fi)
            g.frags.push_back({ti, fi});
    auto face_of = [&](const std::pair<uint32_t, uint32_t>& q) {
        return uint32_t(psf.tiles[q.first].fragments[q.second].face);
    };
    std::stable_sort(g.frags.begin(), g.frags.end(),
                     [&](const auto& a, const auto& b) { return face_of(a) < face_of(b); });
    g.faces.clear();
    g.face_begin.clear();
    for (uint32_t q = 0; q < g.frags.size(); ++q)
        if (q == 0 || face_of(g.frags[q]) != g.faces.back()) {
            VLF_CHECK(face_of(g.frags[q]) < nf);
            g.faces.push_back(face_of(g.frags[q]));
            g.face_begin.push_back(q);
        }
    g.face_begin.push_back(static_cast<uint32_t>(g.frags.size()));
}

// VLF §4.1 exchange buffers: the partner of every ray, as a slot (or kEscaped, kBlocked,
// kSealed), built tile by tile.
void find_partners(const Scene& scene, double seal_gap, DirectionGeometry& g, TileExchange& x,
                   ExchangeScratch& xs) {
    const Psf& psf = g.psf;
    g.partner.assign(g.slots(), kEscaped);
    for (uint32_t ti = 0; ti < psf.tiles.size(); ++ti) {
        const Tile& tile = psf.tiles[ti];
        // A ray shut within the scene's seal gap (a texel) by the back of another
        // surface is sealed: diffuse senders leave it out (exchange.hpp).
        build_exchange(scene, psf, tile, x, xs, seal_gap);
        const uint32_t tb = g.tile_base[ti];
        for (const Fragment& fr : tile.fragments)
            for (uint32_t k = 0; k < fr.covered; ++k) {
                const int32_t p = x.partner[fr.ray_offset + k];
                g.partner[tb + fr.ray_offset + k] =
                    p >= 0 ? static_cast<int32_t>(tb + tile.fragments[p].ray_offset +
                                                  x.partner_ray[fr.ray_offset + k])
                           : p;
            }
    }
}

// Per slot, nonzero for the rays that carry power in a pass whose geometry is used once:
// those of the sending faces and their partners.
std::vector<uint8_t> rays_carrying_power(const DirectionGeometry& g, size_t faces,
                                         const uint8_t* sending) {
    std::vector<uint8_t> needed(g.slots(), 0);
    VLF_CHECK(g.faces.empty() || g.faces.back() < faces);
    for (size_t k = 0; k < g.faces.size(); ++k) {
        if (!sending[g.faces[k]]) continue;
        for_fragments(g, {g.face_begin[k], g.face_begin[k + 1]},
                      [&](const Tile&, const Fragment& fr, uint32_t base) {
                          for (uint32_t k = 0; k < fr.covered; ++k) {
                              needed[base + k] = 1;
                              if (g.partner[base + k] >= 0) needed[g.partner[base + k]] = 1;
                          }
                      });
    }
    return needed;
}

// VLF §4.2 continuous clipping: the beams of faces that can hold diffuse power against
// their texel grids; rays not `needed` (when it is not empty) get no overlaps.
void clip_beams(const GeometryInputs& in, const Mat3& rot, const std::vector<uint8_t>& needed,
                DirectionGeometry& g) {
    const Psf& psf = g.psf;
    g.ov_begin.assign(g.slots() + 1, 0);
    g.ov.clear();
    for (uint32_t ti = 0; ti < psf.tiles.size(); ++ti) {
        const Tile& tile = psf.tiles[ti];
        for (const Fragment& fr : tile.fragments) {
            const Face& face = in.scene.faces[fr.face];
            const Material& mat = in.scene.material_of(face);
            const uint32_t base = g.tile_base[ti] + fr.ray_offset;
            if (!mat.is_diffuse() && !mat.is_emitter()) {
                for (uint32_t k = 0; k < fr.covered; ++k)
                    g.ov_begin[base + k + 1] = static_cast<uint32_t>(g.ov.size());
                continue;
            }
            const TexelFrame& grid = in.scene.chart_of(face).texels;
            const PsfToTexel map = psf_to_texel(face, grid, rot);
            const FaceInTexels& poly = in.polygons[fr.face];
            tile.edge_table(fr).for_each_ray([&](int u, int v, int k) {
                // The beam's footprint on the face itself: the part of the pixel's
                // parallelogram inside the polygon, sliced by the texel grid (area-exact at
                // the rim, docs/propagation.md §3).
                if (needed.empty() || needed[base + k])
                    pixel_texel_overlaps(map, tile.s * in.m + u, tile.t * in.m + v, in.N, poly,
                                         grid.width, grid.height, g.ov);
                g.ov_begin[base + k + 1] = static_cast<uint32_t>(g.ov.size());
            });
        }
    }
}

// Builds the geometry of direction d into g (x, xs: exchange scratch).
void build_geometry(const GeometryInputs& in, const Mat3& rot, int d, DirectionGeometry& g,
                    TileExchange& x, ExchangeScratch& xs, StepTimes& times) {
    Stopwatch sw;
    rasterise_and_group(in.scene, rot, d, in.N, in.m, in.coverage, g);
    times.rasterise += sw.lap();

    find_partners(in.scene, in.seal_gap, g, x, xs);
    times.exchange += sw.lap();

    const std::vector<uint8_t> needed =
        in.sending != nullptr ? rays_carrying_power(g, in.scene.faces.size(), in.sending)
                              : std::vector<uint8_t>();
    clip_beams(in, rot, needed, g);
    times.clipping += sw.lap();
}

}  // namespace

namespace transport_detail {

const DirectionGeometry& direction_geometry(const GeometryInputs& in, const GeometryCache& cache,
                                            const Mat3& rot, int d, Scratch& w, StepTimes& times) {
    std::unique_ptr<DirectionGeometry>& kept = cache.slots[d];
    if (kept) return *kept;
    if (!w.local) w.local = std::make_unique<DirectionGeometry>();
    build_geometry(in, rot, d, *w.local, w.x, w.xs, times);
    if (cache.budget > 0) {
        // Kept as an exact-size copy: the scratch keeps its grown capacity for the next
        // direction, and the cache holds no slack.
        const int64_t b = w.local->bytes();
        if (cache.used.fetch_add(b) + b <= cache.budget) {
            kept = std::make_unique<DirectionGeometry>(*w.local);
            return *kept;
        }
        cache.used.fetch_sub(b);
    }
    return *w.local;
}

}  // namespace transport_detail

void Transport::release_perturbed_geometry() {
    const size_t l = size_t(m_dirs.size());
    for (size_t k = l; k < m_cache.size(); ++k)
        if (m_cache[k]) {
            m_cache_used.fetch_sub(m_cache[k]->bytes());
            m_cache[k].reset();
        }
}

int Transport::cached_directions() const {
    int n = 0;
    for (const auto& g : m_cache) n += g != nullptr;
    return n;
}

int64_t Transport::geometry_cache_bytes() const {
    int64_t b = 0;
    for (const auto& g : m_cache)
        if (g) b += g->bytes();
    return b;
}

}  // namespace vlf
