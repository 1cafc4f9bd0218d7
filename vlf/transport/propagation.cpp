#include "vlf/transport/propagation.hpp"

#include <algorithm>
#include <cstdio>

#include "vlf/core/memory.hpp"
#include "vlf/core/progress.hpp"
#include "vlf/core/stopwatch.hpp"
#include "vlf/scene/raycaster.hpp"
#include "vlf/scene/texel_frame.hpp"
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

Propagation propagate(const Scene& scene, const PropagateParams& params, const RunOptions& opts) {
    const Stopwatch total;
    Propagation run;
    run.transport = std::make_unique<Transport>(scene, params);
    Progress bar("propagating", run.transport->work(params.cycles), opts.progress);
    run.transport->set_progress(&bar);
    for (int c = 1; c <= params.cycles; ++c) {
        run.transport->run_cycle(c == params.cycles);
        const LedgerEntry& e = run.transport->ledger().back();
        if (opts.on_cycle) opts.on_cycle(e);
        if (settled(e, params.stop_unshot)) break;
    }
    run.transport->set_progress(nullptr);
    bar.finish();
    run.transport->fold_unshot_into_total();
    // VLF §5: after the last cycle, resample the specular total maps along real
    // reflection paths (backward ray tracing), once.
    if (params.resample && scene.specular_face_count() > 0) {
        const Stopwatch resample;
        const RayCaster caster(scene);
        resample_specular(*run.transport, caster);
        run.seconds_resample = resample.seconds();
    }
    run.seconds_total = total.seconds();
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
    timings["other"] = total - tm.wall() - run.seconds_resample - write_seconds;
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
    if (surfaces) report["surfaces"] = surface_report(scene, tex);
    return report;
}

}  // namespace vlf
