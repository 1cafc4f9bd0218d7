#include "vlf/quality.hpp"

#include <fmt/format.h>

#include "vlf/error.hpp"

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

PropagateParams quality_params(Quality q) {
    PropagateParams p;
    p.quality = to_string(q);
    // Measured on the empty Cornell box against the path tracer (docs/quality.md,
    // BENCHMARKS.md). The error that remains at a setting is mostly the "ray effect" of a
    // small lamp seen along discrete directions (blotches), which more directions and the
    // filter reduce, and the texel size at the corners.
    switch (q) {
        case Quality::Draft:  // a second: where the light goes
            p.field = {129, 32, 8, DirectionScheme::Octahedral};
            p.texel_divisions = 16;
            p.cycles = 32;
            p.stop_unshot = 1e-2;
            p.filter_sigma = 1.0;
            break;
        case Quality::Preview:  // seconds: within 5 % away from emitters
            p.field = {2049, 64, 8, DirectionScheme::Octahedral};
            p.texel_divisions = 32;
            p.cycles = 64;
            p.stop_unshot = 2e-3;
            p.filter_sigma = 1.0;
            break;
        case Quality::Final:  // within a minute: within 2 %
            p.field = {2049, 128, 16, DirectionScheme::Octahedral};
            p.texel_divisions = 64;
            p.cycles = 128;
            p.stop_unshot = 5e-4;
            p.filter_sigma = 1.5;
            break;
        case Quality::Reference:  // minutes: for comparisons
            p.field = {8193, 128, 16, DirectionScheme::Octahedral};
            p.texel_divisions = 64;
            p.cycles = 256;
            p.stop_unshot = 1e-4;
            p.filter_sigma = 1.5;
            break;
    }
    return p;
}

}  // namespace vlf
