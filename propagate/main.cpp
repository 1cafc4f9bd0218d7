// propagate — builds the virtual light field of a scene and propagates light through it.
// Thin: options into vlf::PropagateParams, then the library does the work.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>

#include "vlf/bake/bake.hpp"
#include "vlf/core/cli_main.hpp"
#include "vlf/core/error.hpp"
#include "vlf/core/files.hpp"
#include "vlf/core/memory.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/core/progress.hpp"
#include "vlf/core/stopwatch.hpp"
#include "vlf/field/field_stats.hpp"
#include "vlf/render/final_gather.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/transport/checkpoint.hpp"
#include "vlf/transport/parameters.hpp"
#include "vlf/transport/propagation.hpp"
#include "vlf/transport/quality.hpp"
#include "vlf/transport/report.hpp"
#ifdef VLF_MPI
#include "mpi_ranks.hpp"
#endif

namespace {

struct Options {
    std::string scene;
    std::string output;
    std::string report;
    bool no_surfaces = false;
    std::string scheme = "octahedral";
    std::string quality;
    bool dry_run = false;
    bool validate_only = false;
    bool quiet = false;
    bool no_deferred = false;
    bool no_resample = false;
    std::string checkpoint;  // --checkpoint DIR
    std::string resume;      // --resume DIR
    vlf::PropagateParams params;
};

// The preset of --quality, with every option the user gave explicitly on top of it.
vlf::PropagateParams with_preset(const Options& o, const CLI::App& app) {
    vlf::PropagateParams p = o.params;
    if (o.quality.empty()) return p;
    const vlf::PropagateParams preset = vlf::quality_params(vlf::quality_from_string(o.quality));
    auto given = [&](const char* name) { return app.count(name) > 0; };
    vlf::PropagateParams q = preset;
    if (given("--directions")) q.field.directions = p.field.directions;
    if (given("--resolution")) q.field.resolution = p.field.resolution;
    if (given("--tile")) q.field.tile = p.field.tile;
    if (given("--texel-size")) q.texel_size = p.texel_size;
    if (given("--texel-divisions")) q.texel_divisions = p.texel_divisions;
    if (given("--cycles")) q.cycles = p.cycles;
    if (given("--stop-unshot")) q.stop_unshot = p.stop_unshot;
    if (given("--perturbations")) q.perturbations = p.perturbations;
    if (given("--perturb-cycles")) q.perturb_cycles = p.perturb_cycles;
    if (given("--filter-sigma")) q.filter_sigma = p.filter_sigma;
    if (given("--supersample")) q.supersample = p.supersample;
    q.threads = p.threads;
    q.store_all_rays = p.store_all_rays;
    q.cache_budget_mib = p.cache_budget_mib;
    q.seed = p.seed;
    q.chunks = p.chunks;
    q.light_dim = p.light_dim;
    q.caustic_noise = p.caustic_noise;
    if (given("--gather")) q.gather = p.gather;
    q.gather_below = p.gather_below;
    return q;
}

int run(Options o, const CLI::App& app, vlf::Ranks& ranks) {
    // With several ranks, rank 0 alone prints, writes the bake, the report and the
    // checkpoints; every rank loads the scene and checks the input alike.
    const bool lead = ranks.rank() == 0;
    if (!lead) o.quiet = true;
    // What the process holds before any scene data: code, libraries, the runtime. The
    // report's peak_rss minus this is what the propagation itself needed.
    const int64_t startup_rss = vlf::current_rss_bytes();
    vlf::PropagateParams p = with_preset(o, app);
    if (app.count("--scheme") > 0 || o.quality.empty())
        p.field.scheme = vlf::direction_scheme_from_string(o.scheme);
    p.deferred = !o.no_deferred;
    p.resample = !o.no_resample;
    vlf::validate(p);
    if (ranks.size() > p.chunks)
        throw vlf::ParameterError(
            fmt::format("mpirun -np {}: more ranks than --chunks {} (each rank owns a block of "
                        "the chunks of directions; give --chunks {} or more)",
                        ranks.size(), p.chunks, ranks.size()));
    if (app.count("--texel-size") > 0 && !(o.params.texel_size > 0))
        throw vlf::ParameterError(
            fmt::format("--texel-size: {} must be a positive length (leave it out for the default)",
                        o.params.texel_size));
    if (!o.dry_run && !o.validate_only && o.output.empty())
        throw vlf::ParameterError("-o/--output: required unless --dry-run or --validate is given");
    if (!o.output.empty()) vlf::check_output_path(o.output);
    if (!o.report.empty()) vlf::check_output_path(o.report);
    if (!o.checkpoint.empty()) vlf::check_output_path(o.checkpoint);

    vlf::LoadOptions load;
    load.texel_size_user = p.texel_size;
    load.texel_divisions = p.texel_divisions;
    load.chart_angle_deg = p.chart_angle_deg;
    const vlf::Scene scene = vlf::load_scene(o.scene, load);
    for (const std::string& note : scene.load_notes)
        std::fprintf(stderr, "note: %s\n", note.c_str());
    if (o.validate_only) {
        std::fputs(vlf::format_scene_summary(scene).c_str(), stdout);
        std::printf("%s: valid\n", o.scene.c_str());
        return 0;
    }
    vlf::ThreadLimit limit(p.threads);
    if (lead) std::fputs(vlf::format_scene_summary(scene).c_str(), stdout);

    if (o.dry_run) {
        const vlf::FieldStats stats = vlf::measure_field(scene, p.field);
        std::fputs(vlf::format_field_stats(stats).c_str(), stdout);
        if (!o.report.empty()) {
            const nlohmann::json dry = {{"scene", vlf::scene_summary(scene)},
                                        {"field", vlf::to_json(stats)},
                                        {"parameters", vlf::to_json(p)}};
            vlf::write_text_atomically(o.report, dry.dump(2) + "\n");
            std::printf("report     %s\n", o.report.c_str());
        }
        return 0;
    }

    vlf::RunOptions run_opts;
    // A checkpoint to continue from is checked against this scene and these parameters
    // before any propagation work (checkpoint.hpp).
    vlf::CheckpointInfo resume;
    if (!o.resume.empty()) {
        resume = vlf::check_checkpoint(o.resume, scene, p);
        run_opts.resume = &resume;
        if (lead) std::printf("resuming   %s after cycle %d\n", o.resume.c_str(), resume.cycle);
    }
    run_opts.checkpoint_dir = o.checkpoint;
    run_opts.ranks = &ranks;
    run_opts.resample_later = true;  // in the bake writer, below
    if (lead && ranks.size() > 1)
        std::printf("ranks      %d (MPI; each a block of the directions)\n", ranks.size());
    run_opts.progress = !o.quiet && vlf::Progress::stderr_is_terminal();
    run_opts.on_cycle = [&](const vlf::LedgerEntry& e) {
        if (!o.quiet) {
            if (run_opts.progress) std::fputs("\r\033[K", stderr);
            std::printf("%s\n", vlf::format_ledger(e).c_str());
            std::fflush(stdout);
        }
    };
    vlf::Propagation run = vlf::propagate(scene, p, run_opts);
    if (!lead) return 0;
    const vlf::Stopwatch write_time;
    nlohmann::json report = vlf::propagation_report(scene, p, run, 0.0, false);
    // The light field goes from the radiance maps to the file one direction at a time.
    vlf::Bake bake = vlf::make_bake(scene, p, *run.transport, report, false);
    // The final gather reads the finished field (final_gather.hpp); it is not propagation.
    const vlf::Stopwatch gather_time;
    const vlf::GatherStats gathered = vlf::final_gather(bake);
    const double gather_s = gather_time.seconds();
    bake.manifest["timings_s"]["gather"] = gather_s;
    // The specular maps are resampled a direction at a time as the writer makes that
    // direction's rays (resample.hpp), while it compresses the directions before.
    vlf::write_bake(o.output, bake,
                    run.resample_pending ? vlf::resampling_ray_source(scene, p, *run.transport)
                                         : vlf::ray_source(scene, p, *run.transport));
    const double write_s = write_time.seconds() - gather_s;
    vlf::set_write_time(report["timings_s"], run, write_s + gather_s);
    report["timings_s"]["write"] = write_s;
    report["timings_s"]["gather"] = gather_s;
    report["gather"] = vlf::to_json(gathered);
    // peak_rss of the propagation_report is before the bake was assembled and written.
    report["memory_bytes"]["peak_rss_propagation"] = report["memory_bytes"]["peak_rss"];
    report["memory_bytes"]["peak_rss"] = vlf::peak_rss_bytes();  // including the write
    report["memory_bytes"]["startup_rss"] = startup_rss;
    report["memory_bytes"]["heap_on_huge_pages"] = vlf::heap_on_huge_pages();
    report["memory_bytes"]["huge_pages"] = vlf::huge_page_bytes();   // resident at the end
    report["memory_bytes"]["heap_tunables"] = vlf::heap_tunables();  // GLIBC_TUNABLES
    if (!o.report.empty()) {
        // After the bake (its time and memory are not the bake's): one entry per face.
        if (!o.no_surfaces)
            report["surfaces"] = vlf::surface_report(scene, run.transport->texture_maps());
        vlf::write_text_atomically(o.report, report.dump(2) + "\n");
    }
    if (gathered.faces > 0 && !o.quiet)
        std::printf("gathered   %lld faces at %lld vertices, %d rays each, in %.2f s\n",
                    static_cast<long long>(gathered.faces), static_cast<long long>(gathered.points),
                    p.gather, gather_s);
    std::printf("propagated in %.2f s (write %.2f s); bake written to %s\n", run.seconds_total,
                write_s, o.output.c_str());
    if (!o.quiet)
        std::printf(
            "memory     peak %.1f MiB; geometry cache %.1f MiB for %d of %d directions "
            "(--cache-budget %lld)\n",
            double(vlf::peak_rss_bytes()) / (1 << 20),
            double(run.transport->geometry_cache_bytes()) / (1 << 20),
            run.transport->cached_directions(), run.transport->directions().size(),
            static_cast<long long>(p.cache_budget_mib));
    if (!o.quiet && !run.ranks.is_null())
        for (const nlohmann::json& r : run.ranks)
            std::printf("rank %-5d directions %d, passes %.2f s, sent %.1f MiB, peak %.1f MiB\n",
                        r["rank"].get<int>(), r["directions"].get<int>(),
                        r["passes_s"].get<double>(),
                        double(r["bytes_sent"].get<uint64_t>()) / (1 << 20),
                        double(r["peak_rss"].get<int64_t>()) / (1 << 20));
    if (!o.report.empty()) std::printf("report     %s\n", o.report.c_str());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    vlf::restart_with_heap_settings(argv);
    Options o;
    CLI::App app{
        "propagate: build the virtual light field of a scene and propagate light through it "
        "(Khanna et al., VLF).\nExample: propagate scenes/cornell.json -o out/cornell.vlf"};
    app.add_option("scene", o.scene,
                   "Scene: JSON (docs/scenes.md) or a model file assimp reads (.obj, .gltf, "
                   ".glb, .ply, .fbx, .dae, ...)")
        ->required();
    app.add_option("-o,--output", o.output, "Bake to write (OUT.vlf)");
    app.add_flag("--dry-run", o.dry_run,
                 "Load and rasterise only: print the scene summary and light-field statistics");
    app.add_flag("--validate", o.validate_only,
                 "Check the scene (JSON, meshes, imports, geometry) and stop: exit 0 when it "
                 "would propagate, else one line naming the problem and exit 2");
    app.add_option("--report", o.report, "Also write the summary/statistics/ledger as JSON");
    app.add_flag("--no-surfaces", o.no_surfaces,
                 "Leave the per-face radiance out of --report (large for a million faces)");
    app.add_option("--quality", o.quality,
                   "Preset: draft, preview, final or reference (field, stop rule, refinements, "
                   "texel density; options given explicitly win)");
    app.add_option("-l,--directions", o.params.field.directions,
                   "Line directions l: 9, 33, 129, 513, 2049 or 8193")
        ->capture_default_str();
    app.add_option("-N,--resolution", o.params.field.resolution, "Rays per PSF side N")
        ->capture_default_str();
    app.add_option("-m,--tile", o.params.field.tile, "Rays per tile side m (N must be a multiple)")
        ->capture_default_str();
    app.add_option("--scheme", o.scheme, "Direction set: octahedral or equal-area")
        ->capture_default_str();
    app.add_option("--texel-size", o.params.texel_size,
                   "Texel edge in scene units (default: settings.texel_size or radius/32)");
    app.add_option("--texel-divisions", o.params.texel_divisions,
                   "Default texel edge = scene radius / this, when neither --texel-size nor "
                   "the scene gives one")
        ->capture_default_str();
    app.add_option("--chart-angle", o.params.chart_angle_deg,
                   "Faces share a chart's texels while their normals lie within this many "
                   "degrees (0: a texel grid per face; docs/charts.md)")
        ->capture_default_str();
    app.add_option("-c,--cycles", o.params.cycles,
                   "Propagation cycles (with --stop-unshot: the most cycles)")
        ->capture_default_str();
    app.add_option("--stop-unshot", o.params.stop_unshot,
                   "Stop once less than this fraction of the emitted power is left to shoot "
                   "(0 = run all cycles)")
        ->capture_default_str();
    app.add_option("-t,--threads", o.params.threads, "Worker threads (0 = all cores)")
        ->capture_default_str();
    app.add_flag("--no-deferred", o.no_deferred, "Disable deferred propagation (VLF §4.5)");
    app.add_option("--perturbations", o.params.perturbations,
                   "Stratified perturbed PSFs per cycle (VLF §5; 0 = off)")
        ->capture_default_str();
    app.add_option("--perturb-cycles", o.params.perturb_cycles,
                   "Cycles that perturb, from the first (VLF §5: the first few suffice)")
        ->capture_default_str();
    app.add_option("--filter-sigma", o.params.filter_sigma,
                   "Gaussian filter of next texture maps, in texels (VLF §5; 0 = off)")
        ->capture_default_str();
    app.add_option("--supersample", o.params.supersample,
                   "Super-sampled exchange at polygon boundaries, s x s (VLF §5)")
        ->capture_default_str();
    app.add_option("--light-dim", o.params.light_dim,
                   "Point, spot and sun beams dimmer than this fraction of their light's mean "
                   "irradiance land coarse (0 = all split to half a texel)")
        ->capture_default_str();
    app.add_option("--caustic-noise", o.params.caustic_noise,
                   "The lamps' light on curved (smooth or faceted) mirrors and glass is ray traced "
                   "on with enough rays "
                   "for about this relative noise in the texels it lights (0 = the field "
                   "carries it)")
        ->capture_default_str();
    app.add_option("--gather", o.params.gather,
                   "Final gather: rays and light samples per vertex of the faces of charts "
                   "smaller than --gather-below texels (0 = off: every face reads its chart)")
        ->capture_default_str();
    app.add_option("--gather-below", o.params.gather_below,
                   "Charts smaller than this many texels of area are gathered per vertex")
        ->capture_default_str();
    app.add_flag("--no-resample", o.no_resample,
                 "Skip backward ray-traced resampling of specular maps (VLF §5)");
    app.add_flag("--store-all-rays", o.params.store_all_rays,
                 "Store L_T of every fragment in the bake, not only specular ones");
    app.add_option("--cache-budget", o.params.cache_budget_mib,
                   "MiB of per-direction geometry kept across cycles (0 = rebuild every "
                   "cycle and keep no smooth-surface plans: least memory); speed and memory "
                   "only, the bake is the same")
        ->capture_default_str();
    app.add_option("--seed", o.params.seed, "Seed of the perturbation streams")
        ->capture_default_str();
    app.add_option("--chunks", o.params.chunks,
                   "Fixed chunks of directions summed in order: the bake depends on it, not on "
                   "threads or MPI ranks; at most this many ranks (docs/cluster.md)")
        ->capture_default_str();
    app.add_option("--checkpoint", o.checkpoint,
                   "Write the propagation state to this directory after every cycle "
                   "(atomically; docs/cluster.md)");
    app.add_option("--resume", o.resume,
                   "Continue from the checkpoint in this directory (same scene and "
                   "parameters; the bake is the same as an uninterrupted run's)");
    app.add_flag("-q,--quiet", o.quiet, "No progress bar");

#ifdef VLF_MPI
    // Under mpirun or srun: the ranks share the directions (docs/cluster.md).
    if (vlf::MpiRanks::launched()) {
        vlf::MpiRanks ranks(&argc, &argv);
        if (ranks.rank() != 0) {
            // The command line is the same on every rank: rank 0 prints its help or its
            // error; the others stay silent (and are ended by rank 0's abort on an error).
            try {
                app.parse(argc, argv);
                app.clear();
            } catch (const CLI::CallForHelp&) {
                return 0;
            } catch (const CLI::ParseError&) {
                std::this_thread::sleep_for(std::chrono::seconds(2));
                ranks.abort(2);
            }
        }
        const int rc = vlf::cli_main(app, argc, argv, "propagate", [&] {
            try {
                return run(o, app, ranks);
            } catch (...) {
                // Bad input fails on every rank alike: let rank 0 say it once and end the
                // job; another rank speaks only when the failure is its own.
                if (ranks.rank() != 0) std::this_thread::sleep_for(std::chrono::seconds(2));
                throw;
            }
        });
        // An error on one rank would leave the others waiting in a reduction: end them all.
        if (rc != 0 && ranks.size() > 1) ranks.abort(rc);
        return rc;
    }
#endif
    return vlf::cli_main(app, argc, argv, "propagate",
                         [&] { return run(o, app, vlf::single_process()); });
}
