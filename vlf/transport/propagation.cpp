#include "vlf/transport/propagation.hpp"

#include <algorithm>
#include <cstdio>

#include "vlf/core/memory.hpp"
#include "vlf/core/progress.hpp"
#include "vlf/core/stopwatch.hpp"
#include "vlf/scene/raycaster.hpp"
#include "vlf/scene/texel_frame.hpp"
#include "vlf/transport/checkpoint.hpp"
#include "vlf/transport/report.hpp"
#include "vlf/transport/resample.hpp"

namespace vlf {

bool settled(const LedgerEntry& e, double stop_unshot) {
    // Nothing left to shoot: more cycles would only repeat zeros (whatever the stop rule).
    if (e.unshot + e.deferred == Rgb(0.0)) return true;
    if (stop_unshot <= 0.0) return false;
    for (int c = 0; c < 3; ++c)
        if (e.unshot[c] + e.deferred[c] > stop_unshot * e.emitted[c]) return false;
    return true;
}

namespace {

// Every rank's share of the work, time and memory, in rank order (on every rank).
nlohmann::json rank_report(Ranks& ranks, const Transport& t, const Propagation& run) {
    const TransportTimings& tm = t.timings();
    const nlohmann::json mine = {
        {"rank", ranks.rank()},
        {"directions", t.first_direction(ranks.rank() + 1) - t.first_direction(ranks.rank())},
        {"first_direction", t.first_direction(ranks.rank())},
        {"passes_s", tm.passes},
        {"specular_s", tm.specular},
        {"cpu_in_passes_s", tm.rasterise + tm.clipping + tm.exchange + tm.transfer},
        {"total_s", run.seconds_total},
        {"bytes_sent", ranks.bytes_sent()},
        {"cycles_run", t.cycles_done() - run.resumed_after},
        {"geometry_cache_bytes", t.geometry_cache_bytes()},
        {"transport_bytes", t.memory_bytes()},
        {"peak_rss", peak_rss_bytes()}};
    nlohmann::json all = nlohmann::json::array();
    for (const std::string& part : ranks.all_gather(mine.dump()))
        all.push_back(nlohmann::json::parse(part));
    return all;
}

}  // namespace

Propagation propagate(const Scene& scene, const PropagateParams& params, const RunOptions& opts) {
    const Stopwatch total;
    Propagation run;
    Ranks& ranks = opts.ranks != nullptr ? *opts.ranks : single_process();
    run.transport = std::make_unique<Transport>(scene, params, ranks);
    const bool lead = ranks.rank() == 0;  // writes checkpoints, resamples
    bool done = false;
    if (opts.resume != nullptr) {
        const Stopwatch restore;
        restore_checkpoint(*opts.resume, *run.transport);
        run.seconds_checkpoint += restore.seconds();
        run.resumed_after = run.transport->cycles_done();
        for (const LedgerEntry& e : run.transport->ledger()) {
            if (opts.on_cycle) opts.on_cycle(e);
            done = done || settled(e, params.stop_unshot);
        }
    }
    const int first = run.transport->cycles_done() + 1;
    // Each rank advances the bar for its own directions.
    const int l = run.transport->directions().size();
    const int own = run.transport->first_direction(ranks.rank() + 1) -
                    run.transport->first_direction(ranks.rank());
    Progress bar("propagating",
                 (run.transport->work(params.cycles) - run.transport->work(first - 1)) * own / l,
                 opts.progress);
    run.transport->set_progress(&bar);
    for (int c = first; !done && c <= params.cycles; ++c) {
        run.transport->run_cycle(c == params.cycles);
        if (!opts.checkpoint_dir.empty()) {
            const Stopwatch write;
            run.transport->gather_radiance_maps(true);
            if (lead) write_checkpoint(opts.checkpoint_dir, scene, *run.transport);
            run.transport->keep_own_radiance_maps();
            run.seconds_checkpoint += write.seconds();
        }
        const LedgerEntry& e = run.transport->ledger().back();
        if (opts.on_cycle) opts.on_cycle(e);
        if (settled(e, params.stop_unshot)) break;
    }
    run.transport->set_progress(nullptr);
    bar.finish();
    run.transport->fold_unshot_into_total();     // each rank its own directions
    run.transport->gather_radiance_maps(false);  // L_T whole on rank 0, for the bake
    // VLF §5: after the last cycle, resample the specular total maps along real
    // reflection paths (backward ray tracing), once (by the rank that writes the bake),
    // here or by the caller as it writes the bake.
    run.resample_pending = lead && params.resample && scene.specular_face_count() > 0;
    if (run.resample_pending && !opts.resample_later) {
        run.resample_pending = false;
        const Stopwatch resample;
        const RayCaster caster(scene);
        resample_specular(*run.transport, caster);
        run.seconds_resample = resample.seconds();
    }
    run.seconds_total = total.seconds();
    if (ranks.size() > 1) run.ranks = rank_report(ranks, *run.transport, run);
    return run;
}

nlohmann::json surface_report(const Scene& scene, const TextureMaps& maps) {
    nlohmann::json faces = nlohmann::json::array();
    const double s2 = scene.normalisation.scale * scene.normalisation.scale;
    std::vector<TexelArea> in_face;
    for (const Face& f : scene.faces) {
        // The face's texels and its area in each: a chart of its own holds just the open
        // area (sealed_areas.hpp); a face sharing a chart weighs each texel it covers.
        const Chart& c = scene.chart_of(f);
        in_face.clear();
        if (c.faces.size() == 1) {
            for (size_t t = 0; t < c.texel_area.size(); ++t)
                if (c.texel_area[t] > 0) in_face.push_back({uint32_t(t), c.texel_area[t]});
        } else {
            face_texel_areas(c, f, in_face);
        }
        double open = 0.0;
        Rgb weighted(0.0);
        for (const TexelArea& ta : in_face) {
            open += ta.area;
            weighted += ta.area * maps.radiance(c, ta.texel);
        }
        const Rgb mean = open > 0 ? weighted / open : Rgb(0.0);
        Rgb lo(1e300), hi(-1e300);
        const double half = 0.5 * c.texels.size * c.texels.size;
        bool any = false;
        for (const TexelArea& ta : in_face) {
            if (ta.area < half) continue;
            const Rgb r = maps.radiance(c, ta.texel);
            lo = glm::min(lo, r);
            hi = glm::max(hi, r);
            any = true;
        }
        if (!any) lo = hi = mean;
        // Area-weighted RMS of the texel radiances about the face mean, rim texels included,
        // relative to the mean: in a furnace (uniform exact radiance) the RMS texel error.
        Rgb sq(0.0);
        for (const TexelArea& ta : in_face) {
            const Rgb d = maps.radiance(c, ta.texel) - mean;
            sq += ta.area * d * d;
        }
        Rgb rms(0.0);
        for (int c = 0; c < 3; ++c)
            if (open > 0 && mean[c] > 0) rms[c] = std::sqrt(sq[c] / open) / mean[c];
        faces.push_back({{"id", f.id},
                         {"object", scene.objects[f.object].name},
                         {"material", scene.materials[f.material].name},
                         {"area", f.area / s2},
                         {"radiance_mean", {mean.x, mean.y, mean.z}},
                         {"radiance_min", {lo.x, lo.y, lo.z}},
                         {"radiance_max", {hi.x, hi.y, hi.z}},
                         {"radiance_rms_deviation", {rms.x, rms.y, rms.z}}});
    }
    return faces;
}

void set_write_time(nlohmann::json& timings, const Propagation& run, double write_seconds) {
    const TransportTimings& tm = run.transport->timings();
    const double total = run.seconds_total + write_seconds;
    timings["write"] = write_seconds;
    timings["total"] = total;
    timings["checkpoint"] = run.seconds_checkpoint;
    timings["other"] =
        total - tm.wall() - run.seconds_resample - run.seconds_checkpoint - write_seconds;
}

nlohmann::json propagation_report(const Scene& scene, const PropagateParams& params,
                                  const Propagation& run, double write_seconds, bool surfaces) {
    const Transport& t = *run.transport;
    nlohmann::json ledger = nlohmann::json::array();
    for (const LedgerEntry& e : t.ledger()) ledger.push_back(to_json(e));
    const TransportTimings& tm = t.timings();
    // Wall-clock phases that add up to the total ("other" is what falls between them);
    // inside the passes, CPU seconds summed over worker threads.
    nlohmann::json timings = {{"setup", tm.setup},
                              {"passes", tm.passes},
                              {"specular", tm.specular},
                              {"filter", tm.filter},
                              {"bookkeeping", tm.bookkeeping},
                              {"resample", run.seconds_resample},
                              {"cpu_in_passes",
                               {{"rasterise", tm.rasterise},
                                {"clipping", tm.clipping},
                                {"exchange", tm.exchange},
                                {"transfer", tm.transfer}}}};
    set_write_time(timings, run, write_seconds);
    const auto& tex = t.texture_maps();
    nlohmann::json memory = {{"texture_maps", static_cast<int64_t>(tex.texels() * 3 * sizeof(Rgb))},
                             {"radiance_maps", t.specular_maps().bytes() + t.other_maps().bytes()},
                             {"coverage", t.coverage().bytes()},
                             {"geometry_cache", t.geometry_cache_bytes()},
                             {"smooth_surface_plans", t.surface_plan_bytes()},
                             {"transport_total", t.memory_bytes()},
                             {"peak_rss", peak_rss_bytes()}};
    nlohmann::json report = {{"parameters", to_json(params)},
                             {"scene", scene_summary(scene)},
                             {"ledger", ledger},
                             {"timings_s", timings},
                             {"memory_bytes", memory},
                             {"geometry_cache",
                              {{"budget_mib", params.cache_budget_mib},
                               {"directions_cached", t.cached_directions()},
                               {"directions", t.directions().size()}}}};
    if (!scene.lights.empty())  // the lights' first shot (light_beams.hpp)
        report["light_beams"] = {{"lights", scene.lights.size()},
                                 {"root_beams", t.light_beams().roots},
                                 {"leaf_beams", t.light_beams().leaves},
                                 {"seconds", t.light_beams().seconds}};
    if (const CausticStats& cs = t.lamp_caustics(); cs.rays > 0) {
        // The lamps' light on curved mirrors and glass (lamp_caustics.hpp): the field's power
        // handed over, and the rays' own estimate of it per channel (1 = they agree; null:
        // nothing handed in that channel).
        const double u = t.to_user_power();
        nlohmann::json ratio = nlohmann::json::array();
        for (int c = 0; c < 3; ++c)
            ratio.push_back(cs.handed[c] > 0 ? nlohmann::json(cs.estimated[c] / cs.handed[c])
                                             : nlohmann::json());
        report["lamp_caustics"] = {{"rays", cs.rays},
                                   {"handed", {cs.handed.x * u, cs.handed.y * u, cs.handed.z * u}},
                                   {"estimate_over_handed", ratio},
                                   {"seconds", cs.seconds}};
    }
    if (!run.ranks.is_null()) {
        // Load balance: the slowest rank's passes against the mean (1 = even).
        double worst = 0.0, sum = 0.0;
        for (const nlohmann::json& r : run.ranks) {
            worst = std::max(worst, r["passes_s"].get<double>());
            sum += r["passes_s"].get<double>();
        }
        report["ranks"] = {{"count", run.ranks.size()},
                           {"imbalance", sum > 0 ? worst * double(run.ranks.size()) / sum : 1.0},
                           {"per_rank", run.ranks}};
    }
    if (surfaces) report["surfaces"] = surface_report(scene, tex);
    return report;
}

}  // namespace vlf
