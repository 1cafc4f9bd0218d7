// parameters.cpp — checking, writing and reading back the run parameters (parameters.hpp).
#include "vlf/transport/parameters.hpp"

#include <fmt/format.h>

#include <cmath>

#include "vlf/core/error.hpp"
#include "vlf/core/json_reader.hpp"
#include "vlf/field/psf.hpp"

namespace vlf {

void validate(const PropagateParams& p) {
    if (!DirectionSet::is_valid_count(p.field.directions))
        throw ParameterError(fmt::format("--directions: {} is not a valid direction count ({})",
                                         p.field.directions, DirectionSet::valid_counts_text()));
    try {
        validate_raster(p.field.resolution, p.field.tile);
    } catch (const ParameterError& e) {
        throw ParameterError(fmt::format("--resolution/--tile: {}", e.what()));
    }
    if (!(p.texel_size >= 0.0) || !std::isfinite(p.texel_size))
        throw ParameterError(
            fmt::format("--texel-size: {} must be a positive length", p.texel_size));
    if (p.texel_divisions < 1 || p.texel_divisions > 4096)
        throw ParameterError(
            fmt::format("--texel-divisions: {} is out of range (1 to 4096)", p.texel_divisions));
    if (!(p.chart_angle_deg >= 0.0) || p.chart_angle_deg >= 90.0)
        throw ParameterError(fmt::format(
            "--chart-angle: {} is out of range (0 to less than 90 degrees)", p.chart_angle_deg));
    if (!(p.stop_unshot >= 0.0) || p.stop_unshot >= 1.0)
        throw ParameterError(
            fmt::format("--stop-unshot: {} is out of range (0 = off, up to 1)", p.stop_unshot));
    if (p.cycles < 1 || p.cycles > 10000)
        throw ParameterError(fmt::format("--cycles: {} is out of range (1 to 10000)", p.cycles));
    if (p.threads < 0 || p.threads > 1024)
        throw ParameterError(
            fmt::format("--threads: {} is out of range (0 = all, up to 1024)", p.threads));
    if (p.perturbations < 0 || p.perturbations > 64)
        throw ParameterError(
            fmt::format("--perturbations: {} is out of range (0 to 64)", p.perturbations));
    if (p.perturb_cycles < 1 || p.perturb_cycles > 10000)
        throw ParameterError(
            fmt::format("--perturb-cycles: {} is out of range (1 to 10000)", p.perturb_cycles));
    if (!(p.filter_sigma >= 0.0) || p.filter_sigma > 16.0)
        throw ParameterError(
            fmt::format("--filter-sigma: {} is out of range (0 to 16 texels)", p.filter_sigma));
    if (p.supersample < 1 || p.supersample > 8)
        throw ParameterError(
            fmt::format("--supersample: {} is out of range (1 to 8)", p.supersample));
    if (!(p.light_dim >= 0.0) || p.light_dim > 0.1)
        throw ParameterError(
            fmt::format("--light-dim: {} is out of range (0 to 0.1)", p.light_dim));
    if (!(p.caustic_noise >= 0.0) || p.caustic_noise > 0.5)
        throw ParameterError(
            fmt::format("--caustic-noise: {} is out of range (0 = the field carries it, up to 0.5)",
                        p.caustic_noise));
    if (p.gather < 0 || p.gather > 65536)
        throw ParameterError(fmt::format("--gather: {} is out of range (0 to 65536)", p.gather));
    if (!(p.gather_below >= 0.0) || p.gather_below > 1e6)
        throw ParameterError(
            fmt::format("--gather-below: {} is out of range (0 to 1e6 texels)", p.gather_below));
    if (p.chunks < 1 || p.chunks > 4096)
        throw ParameterError(fmt::format("--chunks: {} is out of range (1 to 4096)", p.chunks));
    if (p.cache_budget_mib < 0 || p.cache_budget_mib > (int64_t(1) << 24))
        throw ParameterError(fmt::format("--cache-budget: {} MiB is out of range (0 to 16777216)",
                                         p.cache_budget_mib));
    if (p.field.resolution * p.supersample > 4096)
        throw ParameterError(
            fmt::format("--supersample: N x s = {} x {} exceeds the 4096-ray limit of a PSF side",
                        p.field.resolution, p.supersample));
}

nlohmann::json to_json(const PropagateParams& p) {
    nlohmann::json j = to_json(p.field);
    j["quality"] = p.quality;
    j["texel_size"] = p.texel_size;
    j["texel_divisions"] = p.texel_divisions;
    j["chart_angle_deg"] = p.chart_angle_deg;
    j["cycles"] = p.cycles;
    j["stop_unshot"] = p.stop_unshot;
    j["threads"] = p.threads;
    j["deferred"] = p.deferred;
    j["perturbations"] = p.perturbations;
    j["perturb_cycles"] = p.perturb_cycles;
    j["filter_sigma"] = p.filter_sigma;
    j["supersample"] = p.supersample;
    j["resample"] = p.resample;
    j["store_all_rays"] = p.store_all_rays;
    j["seed"] = p.seed;
    j["cache_budget_mib"] = p.cache_budget_mib;
    j["chunks"] = p.chunks;
    j["light_dim"] = p.light_dim;
    j["caustic_noise"] = p.caustic_noise;
    j["gather"] = p.gather;
    j["gather_below"] = p.gather_below;
    return j;
}

PropagateParams propagate_params_from_json(const JsonReader& r) {
    r.only_keys({"directions",       "resolution",    "tile",           "tiles_per_side",
                 "scheme",           "quality",       "texel_size",     "texel_divisions",
                 "chart_angle_deg",  "cycles",        "stop_unshot",    "threads",
                 "deferred",         "perturbations", "perturb_cycles", "filter_sigma",
                 "supersample",      "resample",      "store_all_rays", "seed",
                 "cache_budget_mib", "chunks",        "light_dim",      "gather",
                 "gather_below",     "caustic_noise"});
    PropagateParams p;
    p.field.directions = r.required("directions").integer();
    p.field.resolution = r.required("resolution").integer();
    p.field.tile = r.required("tile").integer();
    const std::vector<DirectionScheme> schemes = {DirectionScheme::Octahedral,
                                                  DirectionScheme::EqualArea};
    std::vector<std::string> scheme_names;
    for (DirectionScheme s : schemes) scheme_names.push_back(to_string(s));
    p.field.scheme = schemes[r.required("scheme").one_of(scheme_names, "direction scheme")];
    p.quality = r.required("quality").string();
    p.texel_size = r.required("texel_size").number();
    p.texel_divisions = r.required("texel_divisions").integer();
    p.chart_angle_deg = r.required("chart_angle_deg").number();
    p.cycles = r.required("cycles").integer();
    p.stop_unshot = r.required("stop_unshot").number();
    p.threads = r.required("threads").integer();
    p.deferred = r.required("deferred").boolean();
    p.perturbations = r.required("perturbations").integer();
    p.perturb_cycles = r.required("perturb_cycles").integer();
    p.filter_sigma = r.required("filter_sigma").number();
    p.supersample = r.required("supersample").integer();
    p.resample = r.required("resample").boolean();
    p.store_all_rays = r.required("store_all_rays").boolean();
    p.seed = r.required("seed").unsigned64();
    p.cache_budget_mib = r.required("cache_budget_mib").integer64();
    // Bakes before issue 13 were all made with 16 chunks.
    if (const auto chunks = r.optional("chunks")) p.chunks = chunks->integer();
    // Bakes before dim beams split every light beam to half a texel.
    p.light_dim = 0.0;
    if (const auto dim = r.optional("light_dim")) p.light_dim = dim->number();
    // Bakes before the lamp caustics' shot carried that light in the field.
    p.caustic_noise = 0.0;
    if (const auto noise = r.optional("caustic_noise")) p.caustic_noise = noise->number();
    p.gather = r.required("gather").integer();
    p.gather_below = r.required("gather_below").number();
    try {
        validate(p);
    } catch (const ParameterError& e) {
        r.fail(e.what());
    }
    if (const auto tiles = r.optional("tiles_per_side")) {
        const int want = p.field.resolution / p.field.tile;
        if (tiles->integer() != want)
            tiles->fail(
                fmt::format("must be resolution / tile = {} (got {})", want, tiles->json().dump()));
    }
    return p;
}

}  // namespace vlf
