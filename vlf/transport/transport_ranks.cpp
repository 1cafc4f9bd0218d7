// transport_ranks.cpp — a cycle's chunks shared among ranks (ranks.hpp; issue 13) with the
// single process's summation order kept exactly, so every number of ranks and threads
// gives the same bake, bit for bit (DESIGN §5 Parallelism).
//
// Rank r computes its block of chunks [c0, c1) in parallel (threads) and keeps their
// accumulators. The reduction is then a chain in rank order: rank r receives P^N and the
// running ledger with chunks [0, c0) already added (in order) from rank r - 1, adds its own
// chunks in order, and passes them on; the last rank broadcasts the result. Floating-point
// addition is not associative, so this is the one order that reproduces the single
// process's ((P^N + chunk 0) + chunk 1) + ... exactly. The specular sources are gathered
// in rank order, which is chunk order; every rank holds the radiance maps (L_U, L_T) of its
// own directions only and gathers into them, in source order, just the deposits that land
// there (gather_specular), so each map is written as the single process writes it. Sums
// over the maps (the unshot power, the rounding) run along the same chain in direction
// order (sum_in_rank_order). Rank 0 collects the maps whole only to write a checkpoint
// (then keeps its own part again) and, L_T alone, after the last cycle to write the bake
// (gather_radiance_maps).
#include <fmt/format.h>

#include <cstring>

#include "vlf/core/error.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/transport/transport_internal.hpp"

namespace vlf {

using namespace transport_detail;

namespace {

int chunk_begin(int rank, int ranks, int chunks) {
    return static_cast<int>(int64_t(rank) * chunks / ranks);
}

// A byte buffer of plain values and arrays, and its reader.
struct Packer {
    std::string bytes;
    template <class T>
    void put(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        bytes.append(reinterpret_cast<const char*>(&v), sizeof(T));
    }
    template <class T>
    void put_array(const std::vector<T>& v) {
        put(uint64_t(v.size()));
        bytes.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
    }
};
struct Unpacker {
    const std::string& bytes;
    size_t at = 0;
    template <class T>
    void get(T& v) {
        VLF_CHECK(at + sizeof(T) <= bytes.size());
        std::memcpy(&v, bytes.data() + at, sizeof(T));
        at += sizeof(T);
    }
    template <class T>
    void get_array(std::vector<T>& v) {
        uint64_t n = 0;
        get(n);
        VLF_CHECK(at + n * sizeof(T) <= bytes.size());
        v.resize(n);
        std::memcpy(v.data(), bytes.data() + at, n * sizeof(T));
        at += n * sizeof(T);
    }
    bool done() const { return at == bytes.size(); }
};

void pack(Packer& p, const SpecularSource& s) {
    p.put(s.face);
    p.put(s.rotation);
    p.put(s.resolution);
    p.put(s.i0);
    p.put(s.j0);
    p.put(s.width);
    p.put(s.height);
    p.put_array(s.radiance);
    p.put_array(s.covered);
    p.put(s.targets);
    p.put(s.target_direction);
    p.put(s.target_power);
}

void unpack(Unpacker& u, SpecularSource& s) {
    u.get(s.face);
    u.get(s.rotation);
    u.get(s.resolution);
    u.get(s.i0);
    u.get(s.j0);
    u.get(s.width);
    u.get(s.height);
    u.get_array(s.radiance);
    u.get_array(s.covered);
    u.get(s.targets);
    u.get(s.target_direction);
    u.get(s.target_power);
}

// A list of sources, and its reader (appending).
template <class S>
void pack_all(Packer& p, const std::vector<S>& v) {
    p.put(uint64_t(v.size()));
    for (const S& s : v) pack(p, s);
}
template <class S>
void unpack_all(Unpacker& u, std::vector<S>& v) {
    uint64_t n = 0;
    u.get(n);
    for (uint64_t k = 0; k < n; ++k) {
        S s;
        unpack(u, s);
        v.push_back(std::move(s));
    }
}

}  // namespace

int Transport::first_direction(int rank) const {
    const int l = m_dirs.size();
    const int C = m_params.chunks;
    return static_cast<int>(int64_t(chunk_begin(rank, m_ranks->size(), C)) * l / C);
}

void Transport::run_chunks(const std::function<void(long, ChunkResult&)>& compute,
                           PassSources& sources) {
    std::vector<ChunkResult>& chunks = m_work->chunks;
    const int K = m_ranks->size(), C = m_params.chunks;
    if (K == 1) {
        // Chunks run in waves; each wave's accumulators are reduced in chunk order before
        // the next wave starts, so only a wave's worth of P^N accumulators is alive and the
        // sums are the same as reducing all chunks at the end.
        chunks.resize(kWave);
        for (int wave = 0; wave < C; wave += kWave) {
            parallel_for(wave, std::min(wave + kWave, C), [&](long c) {
                ChunkResult& res = chunks[c - wave];
                res.reset(m_tex.texels());
                compute(c, res);
            });
            reduce_chunks(std::min(kWave, C - wave), sources);
        }
        return;
    }
    if (K > C)
        throw ParameterError(fmt::format(
            "--chunks: {} chunks cannot be shared by {} ranks (at most one rank per chunk)", C, K));
    const int r = m_ranks->rank();
    const int c0 = chunk_begin(r, K, C), c1 = chunk_begin(r + 1, K, C);
    chunks.resize(size_t(c1 - c0));
    parallel_for(c0, c1, [&](long c) {
        ChunkResult& res = chunks[c - c0];
        res.reset(m_tex.texels());
        compute(c, res);
    });
    // The chain in rank order: what the chunks before ours added, then ours, in order.
    const uint64_t next_bytes = m_tex.next.size() * sizeof(Rgb);
    auto transfer = [&](auto&& op, int peer) {
        op(m_tex.next.data(), next_bytes, peer);
        op(&m_running, sizeof(m_running), peer);
        op(&m_light_stats.leaves, sizeof(m_light_stats.leaves), peer);
        op(&m_handed, sizeof(m_handed), peer);
    };
    if (r > 0)
        transfer([&](void* p, uint64_t n, int peer) { m_ranks->receive(p, n, peer); }, r - 1);
    PassSources mine;
    reduce_chunks(c1 - c0, mine);
    if (r < K - 1)
        transfer([&](void* p, uint64_t n, int peer) { m_ranks->send(p, n, peer); }, r + 1);
    transfer([&](void* p, uint64_t n, int root) { m_ranks->broadcast(p, n, root); }, K - 1);
    // The specular sources in rank order = chunk order.
    Packer packed;
    pack_all(packed, mine.faces);
    packed.put(uint64_t(mine.surfaces.size()));
    for (const SurfaceSources& s : mine.surfaces) {
        packed.put(s.frame);
        packed.put_array(s.targets);
        packed.put_array(s.pixels);
        packed.put_array(s.power);
    }
    mine = PassSources{};
    for (const std::string& part : m_ranks->all_gather(packed.bytes)) {
        Unpacker u{part};
        unpack_all(u, sources.faces);
        uint64_t n = 0;
        u.get(n);
        for (uint64_t k = 0; k < n; ++k) {
            SurfaceSources& theirs = sources.surfaces.emplace_back();
            u.get(theirs.frame);
            u.get_array(theirs.targets);
            u.get_array(theirs.pixels);
            u.get_array(theirs.power);
        }
        VLF_CHECK(u.done());
    }
}

void Transport::share_charts(Pass& pass) {
    const int K = m_ranks->size();
    if (K == 1) return;
    const int r = m_ranks->rank();
    Packer packed;
    for (int d = first_direction(r); d < first_direction(r + 1); ++d) {
        packed.put(uint64_t(pass.charts[d].size()));
        for (const ChartCosine& cc : pass.charts[d]) {
            packed.put(cc.chart);
            packed.put(cc.cosine);
        }
    }
    const std::vector<std::string> parts = m_ranks->all_gather(packed.bytes);
    for (int q = 0; q < K; ++q) {
        Unpacker u{parts[q]};
        for (int d = first_direction(q); d < first_direction(q + 1); ++d) {
            uint64_t n = 0;
            u.get(n);
            std::vector<ChartCosine> list(n);
            for (ChartCosine& cc : list) {
                u.get(cc.chart);
                u.get(cc.cosine);
            }
            if (q != r) pass.charts[d] = std::move(list);
        }
        VLF_CHECK(u.done());
    }
}

void Transport::sum_in_rank_order(Rgb& sum, const std::function<void(Rgb&)>& add_own) {
    const int K = m_ranks->size();
    if (K == 1) {
        add_own(sum);
        return;
    }
    const int r = m_ranks->rank();
    if (r > 0) m_ranks->receive(&sum, sizeof(sum), r - 1);
    add_own(sum);
    if (r < K - 1) m_ranks->send(&sum, sizeof(sum), r + 1);
    m_ranks->broadcast(&sum, sizeof(sum), K - 1);
}

void Transport::gather_radiance_maps(bool whole_state) {
    const int K = m_ranks->size();
    if (K == 1) return;
    const int r = m_ranks->rank(), l = m_dirs.size();
    for (RadianceMaps* maps : {&m_spec, &m_other}) {
        if (!whole_state && maps->with_unshot) {
            // L_U is folded into L_T by now: not needed any more, and not sent.
            std::vector<RgbF>().swap(maps->unshot);
            std::vector<RgbF>().swap(maps->unshot_next);
            maps->with_unshot = false;
        }
        if (r == 0) maps->hold(0, l);
        if (maps->faces.empty()) continue;
        std::vector<std::vector<RgbF>*> arrays{&maps->total};
        if (maps->with_unshot) {
            arrays.push_back(&maps->unshot);
            arrays.push_back(&maps->unshot_next);
        }
        if (r == 0) {
            for (int q = 1; q < K; ++q) {
                const uint64_t b = maps->ray_begin(first_direction(q));
                const uint64_t e = maps->ray_begin(first_direction(q + 1));
                for (std::vector<RgbF>* a : arrays)
                    m_ranks->receive(a->data() + b, (e - b) * sizeof(RgbF), q);
            }
        } else {
            for (std::vector<RgbF>* a : arrays)
                m_ranks->send(a->data(), a->size() * sizeof(RgbF), 0);
        }
    }
}

void Transport::keep_own_radiance_maps() {
    if (m_ranks->size() == 1 || m_ranks->rank() != 0) return;
    for (RadianceMaps* maps : {&m_spec, &m_other})
        maps->hold(first_direction(0), first_direction(1));
}

}  // namespace vlf
