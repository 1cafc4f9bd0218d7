// transport.hpp — the propagation cycles of VLF §4.1 with the transfers of §4.2–4.4, in
// power units (DESIGN §5).
//
// One cycle, for every direction (in parallel over fixed chunks of directions):
//   1. rasterise the PSF; per face, clip every covered ray's beam against the face's
//      texel grid (§4.2 continuous clipping) — the weights serve both sending and receiving;
//   2. senders load their rays: diffuse texels share their unshot power U over the travel
//      directions on their front side by cos(theta_d) * Delta_d / sum_d' cos * Delta
//      (§4.4 eq. (3), solid-angle corrected), within a direction over the rays their beam
//      overlaps, by overlap area; specular faces add L_U * a * Delta; L_T += the ray's
//      radiance (§4.1 line 9);
//   3. exchange per tile: each ray's power moves to the facing fragment X(P) (§4.1 lines
//      5–8); rays leaving the scene are escaped, rays hitting a back face are absorbed;
//   4. receivers: rho_d of the power goes to P^N over the texels the beam overlaps (§4.1
//      line 10, the temporary radiance tile), (1 - rho_d - rho_s) is absorbed, rho_s is
//      reflected into the unshot maps of the enclosing mirror directions (specular.hpp).
// Then P^T += P^N; P^C <- P^N (or kept, for deferred faces, §4.5); L_U <- L_U next.
//
// The reductions are explicit: chunk accumulators of P^N and of the ledger are summed in
// chunk order, specular deposits are gathered per target; so the maps after a cycle do not
// depend on the number of threads (DESIGN §5 Parallelism).
//
// Built in transport_setup.cpp; cycles and passes in transport.cpp; a direction's geometry
// in geometry_cache.cpp; the steps 2 and 3-4 in send_step.cpp and receive_step.cpp (their
// shared private types in transport_internal.hpp).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "vlf/field/coverage.hpp"
#include "vlf/field/direction_set.hpp"
#include "vlf/field/radiance_maps.hpp"
#include "vlf/field/texture_maps.hpp"
#include "vlf/scene/scene.hpp"
#include "vlf/transport/ledger.hpp"
#include "vlf/transport/parameters.hpp"
#include "vlf/transport/ranks.hpp"
#include "vlf/transport/rim_pools.hpp"
#include "vlf/transport/smooth_surfaces.hpp"
#include "vlf/transport/surface_specular.hpp"
#include "vlf/transport/texel_clip.hpp"

namespace vlf {

// Rays each face with `which[f]` covers in each PSF (coverage.hpp).
Coverage measure_coverage(const Scene& scene, const std::vector<Mat3>& rotations, int resolution,
                          const std::vector<uint8_t>& which);
// Per emitting chart (the others are 0 here and summed from the first cycle's geometry):
// the sum over the directions it has rays in of its projected_cosine * Delta_d (VLF §4.4
// eq. (3)).
std::vector<double> send_normalisers(const Scene& scene, const DirectionSet& dirs,
                                     const std::vector<Mat3>& rotations, const Coverage& coverage);

class RayCaster;
struct DirectionGeometry;  // per-direction PSF, overlaps, partners (transport_internal.hpp)

// A chart with rays in a direction and its projected cosine there (VLF §4.4 eq. (3)).
struct ChartCosine {
    uint32_t chart;
    double cosine;
};
struct PassSources;
namespace transport_detail {
struct ChunkResult;
}

// Wall-clock seconds of each phase of the propagation (they add up to the transport's
// wall time), and the CPU seconds, summed over worker threads, inside the passes.
// The lights' first shot (light_beams.hpp): root and leaf beams traced, wall seconds.
struct LightBeamStats {
    int64_t roots = 0, leaves = 0;
    double seconds = 0.0;
};
// The lamp caustics' shot (lamp_caustics.hpp): rays cast, the power the field handed over
// and the rays' own estimate of it (normalised units), wall seconds.
struct CausticStats {
    int64_t rays = 0;
    Rgb handed{0.0}, estimated{0.0};
    double seconds = 0.0;
};

struct TransportTimings {
    double setup = 0;        // directions, rotations, coverage, normalisers, maps, pools
    double passes = 0;       // the true and perturbed passes over all directions
    double specular = 0;     // gathering reflected light into the mirrors' unshot maps
    double filter = 0;       // rim pooling and the Gaussian filter of P^N
    double bookkeeping = 0;  // deferral choice, map swaps, the ledger
    // CPU seconds inside the passes, by step.
    double rasterise = 0, clipping = 0, exchange = 0, transfer = 0;
    double wall() const { return setup + passes + specular + filter + bookkeeping; }
};

class Transport {
  public:
    // `ranks`: the processes sharing this propagation (ranks.hpp; default: this one alone);
    // every rank must run the same calls in the same order. Each rank allocates the
    // radiance maps of its own directions only (RadianceMaps::first, last).
    Transport(const Scene& scene, const PropagateParams& params, Ranks& ranks = single_process());
    ~Transport();
    Transport(const Transport&) = delete;
    Transport& operator=(const Transport&) = delete;

    // Runs cycle `cycles_done() + 1`; `last` disables deferral (all faces shoot).
    void run_cycle(bool last);
    // After the last cycle: light the mirrors received in it is still in L_U; add it to
    // L_T so the stored outgoing radiance holds every bounce, like P^T does.
    void fold_unshot_into_total();
    // Advanced by one for every direction of every pass processed (may be null).
    void set_progress(class Progress* progress) { m_progress = progress; }
    const Ranks& ranks() const { return *m_ranks; }
    // The directions this rank owns (all of them for one process).
    int first_direction(int rank) const;
    // With several ranks (transport_ranks.cpp; nothing to do for one process): every rank's
    // part of the radiance maps to rank 0, which then holds them whole for every direction.
    // `whole_state`: L_U, L_U next and L_T, before a checkpoint (keep_own_radiance_maps()
    // after writing it); otherwise, after the last cycle, only L_T (L_U is dropped on every
    // rank first; fold_unshot_into_total() must have run).
    void gather_radiance_maps(bool whole_state);
    // Rank 0 goes back to holding its own directions only (after a checkpoint is written).
    void keep_own_radiance_maps();
    // Directions processed by `cycles` cycles (every pass of each): the unit of progress.
    int64_t work(int cycles) const;
    int cycles_done() const { return static_cast<int>(m_ledger.size()); }
    const std::vector<LedgerEntry>& ledger() const { return m_ledger; }

    const Scene& scene() const { return m_scene; }
    const PropagateParams& params() const { return m_params; }
    const DirectionSet& directions() const { return m_dirs; }
    const TextureMaps& texture_maps() const { return m_tex; }
    const RadianceMaps& specular_maps() const { return m_spec; }
    RadianceMaps& specular_maps() { return m_spec; }
    const RadianceMaps& other_maps() const { return m_other; }
    const std::vector<Mat3>& rotations() const { return m_rot; }
    const Coverage& coverage() const { return m_coverage; }
    const TransportTimings& timings() const { return m_timings; }
    const LightBeamStats& light_beams() const { return m_light_stats; }
    const CausticStats& lamp_caustics() const { return m_caustic_stats; }
    int64_t memory_bytes() const;
    int64_t geometry_cache_bytes() const;
    // Directions whose geometry is kept across cycles (within params().cache_budget_mib).
    int cached_directions() const;
    // The smooth surfaces' plans kept across cycles (none when cache_budget_mib is 0) and the
    // arrivals they read (surface_specular.hpp).
    int64_t surface_plan_bytes() const;
    // Charts deferred in the last cycle run (VLF §4.5).
    const std::vector<uint8_t>& deferred() const { return m_deferred; }
    // Ledger values are kept in normalised units internally; this converts a power to
    // the user's units (area scale^-2).
    double to_user_power() const;

    // Everything run_cycle reads next, between two cycles (transport_state.cpp): the
    // texture and radiance maps, deferral, the ledger and its running sums, each pass's
    // send normalisers and recorded charts, the lights' first shot. Not the geometry cache
    // (rebuilt alike) nor the timings. load_state() into a transport made from the same
    // scene and parameters continues bit for bit as the saved one would have
    // (checkpoint.hpp); a section of the wrong size throws Error naming it.
    void save_state(class StateWriter& out) const;
    void load_state(class StateReader& in);

  private:
    // The direction set of one pass: rotations to +z and the diffuse send normalisers.
    struct Pass {
        std::vector<Mat3> rotations;
        std::vector<double> send_norm;  // per chart: sum_d |n . omega_d| Delta_d, covered d
        bool norms_known = false;       // every chart's, after the pass's first run
        // Per direction, from the pass's first run: its charts, ascending, with cosines.
        std::vector<std::vector<ChartCosine>> charts;
    };
    // After a pass's first run: the send normalisers of the charts that do not emit, from
    // the charts each direction's geometry held.
    void finish_normalisers(Pass& pass);
    // Pass 0: the true directions; p >= 1: those of perturbation p (transport_setup.cpp).
    Pass make_pass(int p) const;

    void load_emission(LedgerEntry& e);
    // Cycle 1: the emitters smaller than a ray shoot their power by ray casting
    // (small_emitters.hpp) instead of through the PSFs.
    void shoot_small_emitters(const RayCaster& caster);
    // Cycle 1: point, spot and directional lights send their light into P^N by beam
    // tracing (light_beams.hpp).
    void shoot_lights(const RayCaster& caster);
    // Cycle 1: the light the passes handed over at smooth surfaces (m_handed) is traced on
    // from the lamps (lamp_caustics.hpp), into P^N.
    void shoot_lamp_caustics(const class LampCaustics& caustics);
    // Runs a first shot's chunks (as run_chunks) into P^N of their own, rim-pooled if
    // `pool`, and adds that to m_light_next, which joins P^N after the cycle's filter.
    void shoot_beside_filter(
        const std::function<void(long, transport_detail::ChunkResult&)>& compute, bool pool);
    void choose_deferred(bool last);
    // Pass 0 runs the true directions; pass p >= 1 the directions of perturbation p.
    void run_pass(int pass, double share);
    // Adds the first `count` chunk accumulators of the workspace, in chunk order.
    void reduce_chunks(int count, PassSources& sources);
    // Runs compute(c, result) for every chunk c this rank owns and reduces all
    // params().chunks chunks in chunk order into P^N, the running ledger and `sources`, whatever
    // the number of ranks and threads (transport_ranks.cpp).
    void run_chunks(const std::function<void(long, transport_detail::ChunkResult&)>& compute,
                    PassSources& sources);
    // After a pass's first run on several ranks: every direction's recorded charts.
    void share_charts(Pass& pass);
    // A sum over the directions in direction order across the ranks (DESIGN §5): rank r
    // receives `sum` from rank r - 1 (whatever it held), add_own(sum) adds this rank's
    // directions, in order, and the last rank's result goes to every rank.
    void sum_in_rank_order(Rgb& sum, const std::function<void(Rgb&)>& add_own);
    // End of a cycle (VLF §4.1): P^T += P^N, P^C <- P^N (deferred faces: +=), L_U <- L_U
    // next; adds the power left unshot and the power deferred.
    void swap_maps(Rgb& unshot, Rgb& deferred);
    // After the last cycle that perturbs: the perturbed passes' geometry is not needed.
    void release_perturbed_geometry();

    const Scene& m_scene;
    PropagateParams m_params;
    DirectionSet m_dirs;
    std::vector<Mat3> m_rot;         // per direction (= m_passes[0].rotations)
    Coverage m_coverage;             // stored faces and emitters, on the N x N grid
    SmoothSurfaces m_surfaces;       // smooth mirrors and glass: one source per surface
    SurfaceRayCache m_surface_rays;  // their rays per direction, for the gathers
    // Per (direction, surface, side): the plans of their sources in the true directions.
    std::vector<SurfacePlan> m_surface_plans;
    SurfaceArrivals m_arrivals;  // the power their rays bring, once the gathers keep plans
    std::vector<Pass> m_passes;  // the true directions, then each perturbation
    TextureMaps m_tex;
    RadianceMaps m_spec;                   // L_U, L_T of specular faces, own directions
    RadianceMaps m_other;                  // L_T of the other faces (--store-all-rays), own
    std::vector<uint8_t> m_deferred;       // per chart, this cycle
    std::vector<int> m_small_emitters;     // charts that shoot by ray casting
    std::vector<Rgb> m_light_next;         // cycle 1: the lights' share of P^N (shoot_lights)
    LightBeamStats m_light_stats;          // the lights' beams (shoot_lights)
    std::vector<uint8_t> m_caustic_faces;  // per face: hands the lamps' light to the shot
    bool m_hand_caustics = false;          // cycle 1: those faces hand their light over
    Rgb m_handed{0.0};                     // ... what they handed (ChunkResult::handed)
    CausticStats m_caustic_stats;          // the lamp caustics' shot
    std::vector<FaceInTexels> m_polygons;  // per face: its polygon in its chart's texels
    double m_rim_reach = 0.0;              // ... with the chart's rim lines this near
    RimPools m_pools;                      // rim texels and the texels they pool with
    std::vector<LedgerEntry> m_ledger;
    LedgerEntry m_running;            // cumulative absorbed/escaped/emitted
    double m_mean_reflectance = 0.0;  // rho_S of §4.5 eq. (4)
    TransportTimings m_timings;
    std::atomic<int64_t> m_cache_used{0};  // bytes of geometry in m_cache
    class Progress* m_progress = nullptr;
    Ranks* m_ranks = &single_process();
    std::vector<std::unique_ptr<DirectionGeometry>> m_cache;  // pass * l + d
    struct Workspace;
    std::unique_ptr<Workspace> m_work;
};

}  // namespace vlf
