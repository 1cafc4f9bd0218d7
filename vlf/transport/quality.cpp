#include "vlf/transport/quality.hpp"

#include <fmt/format.h>

#include "vlf/core/error.hpp"

namespace vlf {

Quality quality_from_string(const std::string& name) {
    if (name == "draft") return Quality::Draft;
    if (name == "preview") return Quality::Preview;
    if (name == "final") return Quality::Final;
    if (name == "reference") return Quality::Reference;
    throw ParameterError(
        fmt::format("--quality: '{}' is not a preset (draft, preview, final or reference)", name));
}

std::string to_string(Quality q) {
    switch (q) {
        case Quality::Draft:
            return "draft";
        case Quality::Preview:
            return "preview";
        case Quality::Final:
            return "final";
        case Quality::Reference:
            return "reference";
    }
    return "?";
}

namespace {

struct Preset {
    int directions, resolution, tile, texel_divisions, cycles;
    double stop_unshot, filter_sigma;
    int gather;  // final gather rays per vertex (final_gather.hpp)
};

// Measured on the empty Cornell box against the path tracer (docs/quality.md,
// BENCHMARKS.md). What error remains at a setting is mostly the "ray effect" of a small
// lamp seen along discrete directions (blotches), which more directions and the filter
// reduce, and the texel size at the corners.
constexpr Preset kPresets[] = {
    {129, 32, 8, 16, 32, 1e-2, 1.0, 16},        // draft: a second, where the light goes
    {2049, 64, 8, 32, 64, 2e-3, 1.0, 64},       // preview: seconds, within 5 % away from emitters
    {2049, 128, 16, 64, 128, 5e-4, 1.5, 256},   // final: within a minute, within 2 %
    {8193, 128, 16, 64, 256, 1e-4, 1.5, 1024},  // reference: minutes, for comparisons
};

}  // namespace

PropagateParams quality_params(Quality q) {
    const Preset& k = kPresets[static_cast<int>(q)];
    PropagateParams p;
    p.quality = to_string(q);
    p.field = {k.directions, k.resolution, k.tile, DirectionScheme::Octahedral};
    p.texel_divisions = k.texel_divisions;
    p.cycles = k.cycles;
    p.stop_unshot = k.stop_unshot;
    p.filter_sigma = k.filter_sigma;
    p.gather = k.gather;
    return p;
}

}  // namespace vlf
