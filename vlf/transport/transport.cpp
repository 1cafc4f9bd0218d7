// transport.cpp — the propagation cycles (VLF §4.1) and the passes inside them: a pass
// runs every direction through the steps send, exchange, receive (transport_internal.hpp)
// in fixed chunks of directions, and reduces the chunks' sums in chunk order; a cycle then
// pools, filters and swaps the maps and books the ledger.
#include "vlf/transport/transport.hpp"

#include <algorithm>
#include <cmath>

#include "vlf/core/parallel.hpp"
#include "vlf/core/progress.hpp"
#include "vlf/scene/raycaster.hpp"
#include "vlf/transport/gaussian_filter.hpp"
#include "vlf/transport/lamp_caustics.hpp"
#include "vlf/transport/light_beams.hpp"
#include "vlf/transport/small_emitters.hpp"
#include "vlf/transport/transport_internal.hpp"

namespace vlf {

using namespace transport_detail;

namespace {

// One direction of a pass: its geometry, then the steps of VLF §4.1 along its rays.
// The charts with rays in a direction (a face with at least one covered ray), ascending,
// with their projected cosines.
void record_charts(const Scene& scene, const DirectionGeometry& g, const Mat3& rot,
                   std::vector<ChartCosine>& out) {
    std::vector<uint32_t> charts;
    for (size_t k = 0; k < g.faces.size(); ++k) {
        uint32_t covered = 0;
        for_fragments(g, {g.face_begin[k], g.face_begin[k + 1]},
                      [&](const Tile&, const Fragment& fr, uint32_t) { covered += fr.covered; });
        if (covered > 0) charts.push_back(uint32_t(scene.faces[g.faces[k]].chart));
    }
    std::sort(charts.begin(), charts.end());
    charts.erase(std::unique(charts.begin(), charts.end()), charts.end());
    out.clear();
    for (uint32_t c : charts) out.push_back({c, projected_cosine(scene, scene.charts[c], rot)});
}

void run_direction(const PassContext& pc, const GeometryInputs& in, const GeometryCache& cache,
                   int d, Scratch& w, ChunkResult& res) {
    // 1. The geometry: PSF, exchange partners, beam/texel overlaps (§3, §4.1, §4.2).
    const DirectionGeometry& g = direction_geometry(in, cache, pc.rotations[d], d, w, res.times);
    if (pc.record_charts) record_charts(pc.scene, g, pc.rotations[d], pc.charts[d]);
    const PassDirection pd{d, g, g.psf.ray_area() * pc.dirs.solid_angle(d)};
    const Stopwatch transfer;
    // 2. Senders load their rays (§4.4 eq. (3), §4.1 line 9).
    send_step(pc, pd, w, res);
    // 3. Exchange along every ray (§4.1 lines 5-8).
    exchange_step(pd, w, res);
    attenuate_step(pc, pd, w, res);  // inside absorbing glass
    // 4. Receivers: P^N, absorption, specular sources (§4.1 line 10, §4.2-4.3).
    receive_step(pc, pd, w, res);
    res.times.transfer += transfer.seconds();
}

}  // namespace

int64_t Transport::work(int cycles) const {
    const int perturbed = std::min(cycles, m_params.perturb_cycles);
    const int64_t passes = int64_t(perturbed) * int64_t(m_passes.size()) + (cycles - perturbed);
    return passes * m_dirs.size();
}

double Transport::to_user_power() const {
    const double s = m_scene.normalisation.scale;
    return 1.0 / (s * s);
}

int64_t Transport::memory_bytes() const {
    return static_cast<int64_t>(m_tex.texels() * 3 * sizeof(Rgb)) + m_spec.bytes() +
           m_other.bytes() + m_coverage.bytes() + m_surface_rays.bytes() + surface_plan_bytes() +
           static_cast<int64_t>(m_work->chunks.capacity() * m_tex.texels() * sizeof(Rgb)) +
           static_cast<int64_t>(m_work->faces.capacity() * sizeof(PassFace)) +
           geometry_cache_bytes();
}

int64_t Transport::surface_plan_bytes() const {
    int64_t b = m_surface_rays.plan_bytes();
    b += int64_t(m_surface_plans.size() * sizeof(SurfacePlan) +
                 m_arrivals.power.capacity() * sizeof(ArrivalPower) +
                 m_arrivals.first.capacity() * sizeof(uint64_t));
    for (const SurfacePlan& p : m_surface_plans) b += p.bytes();
    return b;
}

void Transport::load_emission(LedgerEntry& e) {
    for (const Chart& c : m_scene.charts) {
        const Material& mat = m_scene.material_of(c);
        if (!mat.is_emitter()) continue;
        const size_t b = m_tex.begin(c.id);
        for (size_t t = 0; t < m_tex.count(c.id); ++t) {
            // Exitance M = pi * Le of a Lambertian emitter, times the chart's area in the
            // texel: the texel's emitted power.
            const Rgb p = mat.emission * (kPi * c.texel_area[t]);
            m_tex.current[b + t] += p;
            m_tex.total[b + t] += p;
            e.emitted += p;
        }
    }
}

namespace {

// A first shot's share of the ledger, into its chunk's result.
void book(const ShotResult& out, ChunkResult& res) {
    res.absorbed = out.absorbed;
    res.absorbed_back = out.absorbed_back;
    res.escaped = out.escaped;
    res.lost = out.lost;
}

}  // namespace

void Transport::shoot_small_emitters(const RayCaster& caster) {
    if (m_small_emitters.empty()) return;
    const Stopwatch shot;
    // Enough rays that every texel in view gets a few hundred of them.
    const uint64_t K =
        std::clamp<uint64_t>(uint64_t(256) * m_tex.texels(), uint64_t(1) << 20, uint64_t(1) << 25);
    const uint64_t chunks = uint64_t(m_params.chunks);
    PassSources none;
    for (int chart : m_small_emitters) {
        const size_t b = m_tex.begin(chart), n = m_tex.count(chart);
        const Rgb power = TextureMaps::sum(m_tex.current, b, n);
        for (size_t t = b; t < b + n; ++t) m_tex.current[t] = Rgb(0.0);  // shot now
        // Fixed chunks reduced in order (DESIGN §5 Parallelism): any thread count, one bake.
        run_chunks(
            [&](long c, ChunkResult& res) {
                ShotResult out{res.next};
                shoot_rays(m_scene, caster, m_tex, chart, power, K * uint64_t(c) / chunks,
                           K * uint64_t(c + 1) / chunks, K, out);
                book(out, res);
            },
            none);
    }
    m_timings.passes += shot.seconds();
}

void Transport::shoot_lights(const RayCaster& caster) {
    if (m_scene.lights.empty()) return;
    const Stopwatch shot;
    const LightBeams beams(m_scene, caster, m_tex, m_polygons, m_rim_reach, m_params.light_dim);
    const int64_t K = beams.roots();
    const int64_t chunks = m_params.chunks;
    // The lights' deposits are exact at rims and shadow edges: no rim pooling.
    shoot_beside_filter(
        [&](long c, ChunkResult& res) {
            LightShotResult out{res.next};
            beams.shoot(K * c / chunks, K * (c + 1) / chunks, out);
            res.absorbed = out.absorbed;
            res.absorbed_back = out.absorbed_back;
            res.escaped = out.escaped;
            res.lost = out.lost;
            res.emitted = out.emitted;
            res.leaves = out.leaves;
        },
        false);
    m_light_stats.roots = K;
    m_light_stats.seconds = shot.seconds();
    m_timings.passes += shot.seconds();
}

// The lights' and the lamp caustics' deposits join P^N after the rim pooling and the filter
// of run_cycle, which are there for the field's beams: they gather in m_light_next.
void Transport::shoot_beside_filter(const std::function<void(long, ChunkResult&)>& compute,
                                    bool pool) {
    std::vector<Rgb> held(m_tex.texels(), Rgb(0.0));
    std::swap(held, m_tex.next);
    PassSources none;
    // Fixed chunks reduced in order (DESIGN §5 Parallelism): any thread count, one bake.
    run_chunks(compute, none);
    if (pool) pool_rim_texels(m_pools, m_scene, m_tex, m_tex.next);
    if (m_light_next.empty())
        m_light_next = std::move(m_tex.next);
    else
        for (size_t t = 0; t < m_light_next.size(); ++t) m_light_next[t] += m_tex.next[t];
    m_tex.next = std::move(held);
}

void Transport::shoot_lamp_caustics(const LampCaustics& caustics) {
    const Stopwatch shot;
    m_hand_caustics = false;
    if (m_handed == Rgb(0.0)) return;  // no ray of the field reached those faces
    const uint64_t per_pair = caustics.rays_for(m_params.caustic_noise);
    const uint64_t K = per_pair * caustics.pairs(), chunks = uint64_t(m_params.chunks);
    // The rays' estimate of the handed power, in fixed chunks added in order: the same on
    // every rank and thread count.
    std::vector<Rgb> part(chunks, Rgb(0.0));
    parallel_for(0, long(chunks), [&](long c) {
        part[size_t(c)] =
            caustics.estimate(per_pair, K * uint64_t(c) / chunks, K * uint64_t(c + 1) / chunks);
    });
    Rgb estimated(0.0), scale(0.0);
    for (const Rgb& p : part) estimated += p;
    // Each ray scaled by handed / estimated, channel by channel, so the shot carries exactly
    // what the field handed over. A channel the rays did not find at all (K far too small
    // for the object) cannot be carried: booked as lost.
    for (int ch = 0; ch < 3; ++ch) {
        if (estimated[ch] > 0.0)
            scale[ch] = m_handed[ch] / estimated[ch];
        else
            m_running.lost.cut_beam[ch] += m_handed[ch];
    }
    m_caustic_stats = {int64_t(K), m_handed, estimated, 0.0};
    m_handed = Rgb(0.0);
    if (scale == Rgb(0.0)) return;
    // Like the lights' deposits, the shot's skip the filter: a caustic is sharper. Its rays
    // land in the texel under each hit, so a rim texel's sliver gets few of them: the rim
    // pools share those out by area, as they do the field's (rim_pools.hpp).
    shoot_beside_filter(
        [&](long c, ChunkResult& res) {
            ShotResult out{res.next};
            caustics.shoot(per_pair, K * uint64_t(c) / chunks, K * uint64_t(c + 1) / chunks, scale,
                           out);
            book(out, res);
        },
        true);
    m_caustic_stats.seconds = shot.seconds();
    m_timings.passes += shot.seconds();
}

// VLF §4.5: a chart whose unshot power is small against what the scene as a whole is
// expected to hold next cycle (rho_S times today's mean unshot exitance, eq. (4)) keeps
// accumulating instead of shooting. kappa < 1 keeps the threshold conservative.
void Transport::choose_deferred(bool last) {
    std::fill(m_deferred.begin(), m_deferred.end(), 0);
    if (!m_params.deferred || last || m_ledger.empty()) return;
    constexpr double kappa = 0.5;
    double unshot = 0.0, area = 0.0;
    std::vector<double> u(m_scene.charts.size());
    for (const Chart& c : m_scene.charts) {
        u[c.id] = luminance(TextureMaps::sum(m_tex.current, m_tex.begin(c.id), m_tex.count(c.id)));
        unshot += u[c.id];
        area += c.area;
    }
    if (unshot <= 0.0) return;
    const double mean_exitance = unshot / area;
    for (const Chart& c : m_scene.charts)
        if (u[c.id] > 0.0 && u[c.id] < kappa * m_mean_reflectance * mean_exitance * c.area)
            m_deferred[c.id] = 1;
}

void Transport::run_pass(int pass, double share) {
    const Stopwatch pass_time;
    Pass& directions = m_passes[pass];
    if (!directions.norms_known) directions.charts.resize(directions.rotations.size());
    const int l = static_cast<int>(directions.rotations.size());
    const int s = m_params.supersample;
    const int Nc = m_params.field.resolution, mc = m_params.field.tile;  // radiance-map grid
    const Senders senders = find_senders(m_scene, m_tex, m_deferred, directions.send_norm);
    // A single rank's true directions keep the smooth surfaces' gather plans; from the
    // second cycle on, their sources are the power their rays bring (SurfaceArrivals).
    // Like the geometry, they are kept only with a cache budget (0: least memory).
    const bool keep_plans = pass == 0 && !m_surfaces.empty() && m_params.cache_budget_mib > 0;
    const bool keep_arrivals = keep_plans && m_ranks->size() == 1;
    const PassContext pc{.scene = m_scene,
                         .faces = m_work->faces,
                         .absorbing_glass = m_work->absorbing_glass,
                         .dirs = m_dirs,
                         .coverage = m_coverage,
                         .surfaces = m_surfaces,
                         .charts = directions.charts,
                         .record_charts = !directions.norms_known,
                         .tex = m_tex,
                         .spec = m_spec,
                         .other = m_other,
                         .rotations = directions.rotations,
                         .send_norm = directions.send_norm,
                         .senders = senders,
                         .share = share,
                         .true_directions = pass == 0,
                         .hand_caustics = m_hand_caustics,
                         .caustic_faces = m_caustic_faces,
                         .surface_plans = keep_plans ? &m_surface_plans : nullptr,
                         .surface_arrivals = keep_arrivals ? &m_arrivals : nullptr,
                         .s = s,
                         .Nc = Nc,
                         .mc = mc,
                         .N = Nc * s,
                         .m = mc * s};
    // Geometry is kept across cycles while it fits the budget; the rest is rebuilt each
    // cycle (identical either way, so the budget never changes a map). A perturbed pass's
    // geometry is not worth keeping in the last cycle that perturbs: it clips only the rays
    // that carry power in this pass.
    const bool reused = pass == 0 || cycles_done() + 1 < m_params.perturb_cycles;
    const GeometryInputs inputs{.scene = m_scene,
                                .polygons = m_polygons,
                                .seal_gap = m_scene.seal_gap,
                                .N = pc.N,
                                .m = pc.m,
                                .sending = reused ? nullptr : senders.face_sends.data(),
                                .coverage = pass == 0 && s == 1 ? &m_coverage : nullptr};
    const GeometryCache cache{.slots = m_cache.data() + size_t(pass) * size_t(l),
                              .used = m_cache_used,
                              .budget = reused ? m_params.cache_budget_mib << 20 : 0};
    // Chunks run in waves; each wave's accumulators are reduced in chunk order before the
    // next wave starts, so only a wave's worth of P^N accumulators is alive and the sums
    // are the same as reducing all chunks at the end (DESIGN §5 Parallelism).
    PassSources sources;
    run_chunks(
        [&](long c, ChunkResult& res) {
            Scratch& w = m_work->scratch.local();
            const int d0 = static_cast<int>(c * l / m_params.chunks),
                      d1 = static_cast<int>((c + 1) * l / m_params.chunks);
            for (int d = d0; d < d1; ++d) {
                if (m_progress != nullptr) m_progress->advance();
                run_direction(pc, inputs, cache, d, w, res);
            }
        },
        sources);
    if (!directions.norms_known) share_charts(directions);
    m_timings.passes += pass_time.seconds();
    // Then the reflected light of the pass into the mirrors' unshot maps (specular.hpp).
    const Stopwatch specular;
    const bool arrived = keep_arrivals && m_arrivals.ready;
    if (!sources.empty() || arrived) {
        // Each rank deposits into its own directions; the rounding is summed in direction
        // order across the ranks (DESIGN §5 Parallelism).
        std::vector<Rgb> rounding =
            gather_specular(m_scene, m_dirs, m_rot, Nc, mc, sources.faces, m_spec);
        std::vector<Rgb> smooth;
        if (arrived) {
            smooth = gather_surface_arrivals(m_scene, m_dirs, Nc, m_surfaces, m_arrivals,
                                             m_surface_rays, m_spec);
        } else {
            const bool keep = keep_arrivals && index_arrivals(m_surface_plans, m_arrivals);
            if (keep) power_to_arrivals(m_surfaces, sources.surfaces, m_arrivals);
            smooth =
                gather_surface_sources(m_scene, m_dirs, m_rot, Nc, mc, m_surfaces, sources.surfaces,
                                       keep ? &m_arrivals : nullptr, m_surface_rays, m_spec);
        }
        for (size_t d = 0; d < rounding.size(); ++d) rounding[d] += smooth[d];
        Rgb sum(0.0);
        sum_in_rank_order(sum, [&](Rgb& s) {
            for (const Rgb& r : rounding) s += r;
        });
        m_running.lost.rounding += sum;
    }
    m_timings.specular += specular.seconds();
    if (!directions.norms_known) finish_normalisers(directions);
}

// The reductions of a wave, in chunk order (DESIGN §5 Parallelism): P^N, the ledger, the
// timings, and the specular sources (in chunk order, then direction order within a chunk).
void Transport::reduce_chunks(int count, PassSources& sources) {
    for (int k = 0; k < count; ++k) {
        ChunkResult& c = m_work->chunks[k];
        for (size_t t = 0; t < m_tex.texels(); ++t) m_tex.next[t] += c.next[t];
        m_running.absorbed += c.absorbed;
        m_running.escaped += c.escaped;
        m_running.absorbed_back += c.absorbed_back;
        m_running.lost += c.lost;
        m_running.emitted += c.emitted;
        m_light_stats.leaves += c.leaves;
        m_handed += c.handed;
        m_timings.rasterise += c.times.rasterise;
        m_timings.clipping += c.times.clipping;
        m_timings.exchange += c.times.exchange;
        m_timings.transfer += c.times.transfer;
        for (SpecularSource& src : c.sources.faces) sources.faces.push_back(std::move(src));
        for (SurfaceSources& s : c.sources.surfaces) sources.surfaces.push_back(std::move(s));
    }
}

void Transport::fold_unshot_into_total() {
    for (size_t k = 0; k < m_spec.total.size(); ++k) m_spec.total[k] += m_spec.unshot[k];
}

void Transport::run_cycle(bool last) {
    Stopwatch sw;
    LedgerEntry e;
    e.cycle = cycles_done() + 1;
    m_ranks->set_cycle(e.cycle);
    // Cycle 1's ray casting: the first shots of small lamps and lights, and the lamps'
    // light on curved mirrors and glass (one scene BVH for all).
    std::unique_ptr<RayCaster> caster;
    std::unique_ptr<LampCaustics> caustics;
    if (e.cycle == 1) {
        load_emission(m_running);
        const bool handing =
            m_params.caustic_noise > 0.0 &&
            std::find(m_caustic_faces.begin(), m_caustic_faces.end(), 1) != m_caustic_faces.end();
        if (!m_small_emitters.empty() || !m_scene.lights.empty() || handing)
            caster = std::make_unique<RayCaster>(m_scene);
        if (caster != nullptr) {
            shoot_small_emitters(*caster);
            shoot_lights(*caster);
        }
        if (handing) {
            caustics = std::make_unique<LampCaustics>(m_scene, *caster, m_tex, m_surfaces,
                                                      m_caustic_faces, m_small_emitters);
            m_hand_caustics = caustics->pairs() > 0;  // some lamp meets such an object
        }
    }
    choose_deferred(last);
    for (auto& v : m_spec.unshot_next) v = RgbF(0.0f);
    m_timings.bookkeeping += sw.lap();

    // VLF §5: the first few cycles perturb (their light comes from the emitters, small and
    // bright, whose beams leave the holes); the later ones run the true directions only.
    const bool perturb = e.cycle <= m_params.perturb_cycles;
    const int passes = perturb ? int(m_passes.size()) : 1;
    for (int p = 0; p < passes; ++p) run_pass(p, 1.0 / double(passes));
    if (perturb && e.cycle == m_params.perturb_cycles) release_perturbed_geometry();
    if (m_hand_caustics) shoot_lamp_caustics(*caustics);

    // End of cycle: pool, filter, accumulate, swap (VLF §4.1 closing lines, §5 filtering).
    sw.lap();
    pool_rim_texels(m_pools, m_scene, m_tex, m_tex.next);
    if (m_params.filter_sigma > 0.0) gaussian_filter_next(m_scene, m_tex, m_params.filter_sigma);
    for (size_t t = 0; t < m_light_next.size(); ++t) m_tex.next[t] += m_light_next[t];
    m_light_next.clear();
    m_timings.filter += sw.lap();
    Rgb unshot(0.0), deferred(0.0);
    swap_maps(unshot, deferred);
    const double u = to_user_power();
    e.emitted = m_running.emitted * u;
    e.absorbed = m_running.absorbed * u;
    e.escaped = m_running.escaped * u;
    e.absorbed_back = m_running.absorbed_back * u;
    e.lost = m_running.lost * u;
    e.unshot = unshot * u;
    e.deferred = deferred * u;
    m_ledger.push_back(e);
    m_timings.bookkeeping += sw.lap();
}

// VLF §4.1 closing lines: P^T += P^N; P^C <- P^N, or += P^N for deferred faces (§4.5);
// L_U <- L_U next. Adds the power left unshot to `unshot` (texels, then mirrors' rays)
// and the power deferred faces hold to `deferred`.
void Transport::swap_maps(Rgb& unshot, Rgb& deferred) {
    for (const Chart& c : m_scene.charts) {
        const size_t b = m_tex.begin(c.id), n = m_tex.count(c.id);
        for (size_t t = b; t < b + n; ++t) {
            m_tex.total[t] += m_tex.next[t];
            if (m_deferred[c.id]) {
                m_tex.current[t] += m_tex.next[t];
                deferred += m_tex.current[t];
            } else {
                m_tex.current[t] = m_tex.next[t];
                unshot += m_tex.current[t];
            }
            m_tex.next[t] = Rgb(0.0);
        }
    }
    std::swap(m_spec.unshot, m_spec.unshot_next);
    // The mirrors' rays, each rank its own directions: per direction (its stored faces'
    // rays are contiguous), then in direction order across the ranks (DESIGN §5
    // Parallelism), so the sum is the same on any thread and rank count.
    const double area = ray_area(m_params.field.resolution);
    std::vector<Rgb> per_direction(size_t(m_spec.last - m_spec.first), Rgb(0.0));
    if (!m_spec.faces.empty())
        parallel_for(m_spec.first, m_spec.last, [&](long d) {
            const uint64_t b = m_spec.ray_begin(int(d)) - m_spec.base,
                           e = m_spec.ray_begin(int(d) + 1) - m_spec.base;
            Rgb s(0.0);
            for (uint64_t k = b; k < e; ++k) s += Rgb(m_spec.unshot[k]);
            per_direction[size_t(d - m_spec.first)] = s * (area * m_dirs.solid_angle(int(d)));
        });
    sum_in_rank_order(unshot, [&](Rgb& sum) {
        for (const Rgb& s : per_direction) sum += s;
    });
}

}  // namespace vlf
