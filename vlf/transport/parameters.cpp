#include "vlf/transport/parameters.hpp"

#include <fmt/format.h>

#include <cmath>

#include "vlf/core/error.hpp"
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
    return j;
}

PropagateParams propagate_params_from_json(const nlohmann::json& j) {
    try {
        PropagateParams p;
        p.field.directions = j.at("directions").get<int>();
        p.field.resolution = j.at("resolution").get<int>();
        p.field.tile = j.at("tile").get<int>();
        p.field.scheme = direction_scheme_from_string(j.at("scheme").get<std::string>());
        p.quality = j.at("quality").get<std::string>();
        p.texel_size = j.at("texel_size").get<double>();
        p.texel_divisions = j.at("texel_divisions").get<int>();
        p.cycles = j.at("cycles").get<int>();
        p.stop_unshot = j.at("stop_unshot").get<double>();
        p.threads = j.at("threads").get<int>();
        p.deferred = j.at("deferred").get<bool>();
        p.perturbations = j.at("perturbations").get<int>();
        p.perturb_cycles = j.at("perturb_cycles").get<int>();
        p.filter_sigma = j.at("filter_sigma").get<double>();
        p.supersample = j.at("supersample").get<int>();
        p.resample = j.at("resample").get<bool>();
        p.store_all_rays = j.at("store_all_rays").get<bool>();
        p.seed = j.at("seed").get<uint64_t>();
        p.cache_budget_mib = j.at("cache_budget_mib").get<int64_t>();
        validate(p);
        return p;
    } catch (const nlohmann::json::exception& e) {
        throw Error(fmt::format("parameters: {}", e.what()));
    }
}

}  // namespace vlf
