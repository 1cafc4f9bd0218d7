// transport_internal.hpp — what the transport's own files share, and nothing else
// includes: a direction's geometry and the pass's cache of it (geometry_cache.cpp), the
// worker scratch and chunk accumulators, and the steps one pass runs for each direction
// (send_step.cpp, receive_step.cpp), driven by Transport::run_pass (transport.cpp).
#pragma once

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "vlf/core/stopwatch.hpp"
#include "vlf/field/direction_set.hpp"
#include "vlf/field/exchange.hpp"
#include "vlf/field/psf.hpp"
#include "vlf/field/radiance_maps.hpp"
#include "vlf/field/texture_maps.hpp"
#include "vlf/scene/scene.hpp"
#include "vlf/transport/ledger.hpp"
#include "vlf/transport/specular.hpp"
#include "vlf/transport/surface_specular.hpp"
#include "vlf/transport/texel_clip.hpp"
#include "vlf/transport/transport.hpp"

namespace vlf {

// Everything of a direction that depends only on geometry: the PSF, the slots of its
// rays, fragments grouped by face, the beam/texel overlaps (continuous clipping) and the
// exchange partners. Built once per direction and, within the memory budget, kept for
// all cycles (the paper spent 80-85 % of its time re-clipping these every cycle).
struct DirectionGeometry {
    Psf psf;
    std::vector<uint32_t> tile_base;  // slots: tile_base[ti] + fragment.ray_offset + k
    // The faces with rays in this direction, ascending (a PSF holds a few thousand rays,
    // so of a million triangles only those few are here), and where each one's fragments
    // begin in frags (one more entry at the end).
    std::vector<uint32_t> faces;
    std::vector<uint32_t> face_begin;
    std::vector<std::pair<uint32_t, uint32_t>> frags;  // (tile, fragment) grouped by face
    std::vector<uint32_t> ov_begin;                    // slots + 1, into ov
    std::vector<TexelOverlap> ov;
    std::vector<int32_t> partner;  // per slot: partner slot, kEscaped, kBlocked or kSealed
    uint32_t slots() const { return tile_base.back(); }
    // Bytes of an exact-size copy (what the cache holds).
    int64_t bytes() const;
};

// A face's fragments in DirectionGeometry::frags, [first, second).
using FragRange = std::pair<uint32_t, uint32_t>;

// Calls fn(tile, fragment, first slot) for the fragments [fb, fe) of a face, in tile order.
template <class F>
void for_fragments(const DirectionGeometry& g, std::pair<uint32_t, uint32_t> range, F&& fn) {
    for (uint32_t q = range.first; q < range.second; ++q) {
        const auto [ti, fi] = g.frags[q];
        const Tile& tile = g.psf.tiles[ti];
        const Fragment& fr = tile.fragments[fi];
        fn(tile, fr, g.tile_base[ti] + fr.ray_offset);
    }
}

// The specular sources of a pass: per face (flat mirrors and glass, specular.hpp) and per
// smooth surface (surface_specular.hpp), in chunk order, then direction order.
struct PassSources {
    std::vector<SpecularSource> faces;
    std::vector<SurfaceSources> surfaces;  // per chunk that has any, in chunk order
    bool empty() const { return faces.empty() && surfaces.empty(); }
};

namespace transport_detail {

// Directions are split into PropagateParams::chunks fixed chunks, independent of the
// thread count and of the MPI ranks; chunk accumulators are reduced in chunk order
// (determinism; transport_ranks.cpp).
// Chunks processed (and their P^N accumulators alive) at a time; any value gives the same
// sums, since the reduction is always in chunk order.
inline constexpr int kWave = 4;

// CPU seconds inside a pass, by step (TransportTimings).
struct StepTimes {
    double rasterise = 0, clipping = 0, exchange = 0, transfer = 0;
};

// One worker's buffers, reused from direction to direction.
struct Scratch {
    std::vector<Rgb> out, in;  // per slot: power sent along the ray, power arriving on it
    std::unique_ptr<DirectionGeometry> local;  // where a direction's geometry is built
    TileExchange x;
    ExchangeScratch xs;
    FaceRaster coarse;  // super-sampling: the face on the N x N grid
    std::vector<int32_t> coarse_index;
    std::vector<Rgb> parent_sum;
    std::vector<int> parent_count;
    std::vector<std::pair<uint32_t, uint32_t>> by_chart;  // (chart, index into faces)
    std::vector<uint32_t> present;                        // one chart's part of by_chart
    std::vector<uint32_t> slot_face;                      // attenuate_step: per slot, its face
    std::vector<std::vector<SurfaceRay>> surface_rays;    // receive_step: per (surface, side)
    SurfacePlan surface_plan;                             // receive_step: one not kept
    std::vector<uint32_t> arrived;  // receive_step: per (surface, side), rays written down
};

// What one chunk of directions adds to the pass; reduced in chunk order.
struct ChunkResult {
    std::vector<Rgb> next;  // P^N
    Rgb absorbed{0.0}, absorbed_back{0.0}, escaped{0.0};
    NumericalLoss lost;
    Rgb emitted{0.0};    // the lights' first shot: power of the root beams
    int64_t leaves = 0;  // the lights' first shot: leaf beams traced
    Rgb handed{0.0};     // cycle 1: arrived on smooth surfaces, for the lamp caustics' shot
    PassSources sources;
    StepTimes times;
    // Zeroes everything, keeping the capacity of `next` (no fresh pages every pass).
    void reset(size_t texels) {
        next.assign(texels, Rgb(0.0));
        absorbed = absorbed_back = escaped = emitted = handed = Rgb(0.0);
        leaves = 0;
        lost = NumericalLoss{};
        sources.faces.clear();
        sources.surfaces.clear();  // (moved out by the reduction)
        times = StepTimes{};
    }
};

// What a direction's geometry is built from (geometry_cache.cpp).
struct GeometryInputs {
    const Scene& scene;
    const std::vector<FaceInTexels>& polygons;  // per face, in its chart's texel coordinates
    double seal_gap;                            // exchange.hpp kSealed
    int N, m;                                   // the exchange grid
    // A pass whose geometry is used once clips only the rays of these faces (per face,
    // nonzero: sends) and their partners; null clips every ray.
    const uint8_t* sending;
    // The coverage measured on this grid and these rotations (the true directions, not
    // super-sampled), or null: faces it knows to cover nothing are not rasterised again.
    const Coverage* coverage;
};

// This pass's part of the transport's geometry cache.
struct GeometryCache {
    std::unique_ptr<DirectionGeometry>* slots;  // per direction of the pass
    std::atomic<int64_t>& used;                 // bytes held by the whole cache
    int64_t budget;                             // bytes; 0 keeps nothing
};

// The geometry of direction d: the cached copy, or built in the worker's scratch (and
// kept in the cache while it fits the budget).
const DirectionGeometry& direction_geometry(const GeometryInputs& in, const GeometryCache& cache,
                                            const Mat3& rot, int d, Scratch& w, StepTimes& times);

// Which charts send diffuse power in a pass, and what they send.
struct Senders {
    std::vector<uint8_t> face_sends;  // per face: its chart sends
    std::vector<Rgb> unshot;          // per chart: its unshot power U (zero if it does not send)
    std::vector<Rgb> exitance;        // per texel: unshot exitance of the sending charts
};

// The area-weighted |n . omega| of a chart's faces in the rotated frame (+z = omega): a
// chart's projected area per unit area in that direction (VLF §4.4 eq. (3)).
double projected_cosine(const Scene& scene, const Chart& c, const Mat3& rotation);
Senders find_senders(const Scene& scene, const TextureMaps& tex,
                     const std::vector<uint8_t>& deferred, const std::vector<double>& send_norm);

// What the steps of a pass read of a face, packed. The scene's Face, with its vertex lists,
// is 152 bytes, and every direction of every pass visits each face with rays in it: a
// curved mirror's 10,000 faces (1.5 MB) do not fit a core's cache as Faces, and each visit
// missed it; as PassFaces (0.4 MB) they do (pass_faces).
struct PassFace {
    Vec3 normal;           // Face::normal
    int32_t chart;         // Face::chart
    int32_t surface;       // SmoothSurfaces::of_face: its smooth surface, or -1
    int32_t material;      // Face::material
    bool absorbing_inner;  // an inner face of absorbing glass (attenuate_step)
};
std::vector<PassFace> pass_faces(const Scene& scene, const SmoothSurfaces& surfaces);

// What every step of one pass reads, and the radiance maps its senders write.
struct PassContext {
    const Scene& scene;
    const std::vector<PassFace>& faces;  // per face of the scene
    bool absorbing_glass;                // some face is absorbing_inner
    const DirectionSet& dirs;
    const Coverage& coverage;  // stored faces and emitters, on the N x N grid
    const SmoothSurfaces& surfaces;
    // Per direction, the charts with rays in it and their projected cosines: recorded in
    // the pass's first run (`record_charts`), read by the senders.
    std::vector<std::vector<ChartCosine>>& charts;
    bool record_charts;
    const TextureMaps& tex;
    RadianceMaps& spec;                    // L_U, L_T of specular faces
    RadianceMaps& other;                   // L_T of the other faces (--store-all-rays)
    const std::vector<Mat3>& rotations;    // per direction of the pass
    const std::vector<double>& send_norm;  // per chart
    const Senders& senders;
    double share;          // 1 / the passes of the cycle: what each pass sends of a share
    bool true_directions;  // pass 0: radiance maps are read and written
    // Cycle 1 with a lamp caustics' shot: what arrives on the faces `caustic_faces` marks is
    // handed to it (lamp_caustics.hpp), summed in ChunkResult::handed.
    bool hand_caustics;
    const std::vector<uint8_t>& caustic_faces;
    // Per (direction, smooth surface, side): the plans of its sources, kept from cycle to
    // cycle; null where they are made afresh each time (the perturbed passes).
    std::vector<SurfacePlan>* surface_plans;
    // Where their rays' power goes once the gathers keep their plans (the true directions'
    // pass of a single rank); null otherwise.
    SurfaceArrivals* surface_arrivals;
    int s;       // super-sampling
    int Nc, mc;  // the radiance-map grid
    int N, m;    // the exchange grid, s times finer
};

// One direction of a pass, as its steps see it.
struct PassDirection {
    int d;
    const DirectionGeometry& g;
    double beam;  // a * Delta_d: a ray's cross-section times the direction's solid angle
};

// The steps of a pass for one direction, run in this order; power moves from step to step
// in w.out (per slot: sent along the ray) and w.in (per slot: arriving on it).
// VLF §4.4 eq. (3), §4.1 line 9 (send_step.cpp): the senders load w.out.
void send_step(const PassContext& pc, const PassDirection& pd, Scratch& w, ChunkResult& res);
// VLF §4.1 lines 5-8 (receive_step.cpp): w.out along each ray to its partner's w.in.
void exchange_step(const PassDirection& pd, Scratch& w, ChunkResult& res);
// Beer-Lambert inside glass (receive_step.cpp): w.in of absorbing glass's inner faces.
void attenuate_step(const PassContext& pc, const PassDirection& pd, Scratch& w, ChunkResult& res);
// VLF §4.1 line 10, §4.2-4.3 (receive_step.cpp): the receivers take w.in.
void receive_step(const PassContext& pc, const PassDirection& pd, Scratch& w, ChunkResult& res);

}  // namespace transport_detail

// What the passes keep as long as the transport: the packed per-face table (made once),
// one Scratch per worker thread and the chunk accumulators of a wave, reused by every pass
// of every cycle (their contents are overwritten, so reuse never changes a result).
struct Transport::Workspace {
    std::vector<transport_detail::PassFace> faces;  // pass_faces of the scene
    bool absorbing_glass = false;                   // some face is absorbing_inner
    tbb::enumerable_thread_specific<transport_detail::Scratch> scratch;
    std::vector<transport_detail::ChunkResult> chunks;
};

}  // namespace vlf
