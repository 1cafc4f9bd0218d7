#include "vlf/quality.hpp"

#include <fmt/format.h>

#include "vlf/error.hpp"

namespace vlf {

Quality quality_from_string(const std::string& name) {
    if (name == "draft") return Quality::Draft;
    if (name == "preview") return Quality::Preview;
    if (name == "final") return Quality::Final;
    if (name == "reference") return Quality::Reference;
    throw ParameterError(fmt::format(
        "--quality: '{}' is not a preset (draft, preview, final or reference)", name));
}

std::string to_string(Quality q) {
    switch (q) {
        case Quality::Draft: return "draft";
        case Quality::Preview: return "preview";
        case Quality::Final: return "final";
        case Quality::Reference: return "reference";
    }
    return "?";
}

PropagateParams quality_params(Quality q) {
    PropagateParams p;
    p.quality = to_string(q);
    switch (q) {
        case Quality::Draft:  // seconds: the layout of the light, 10-20 % per texel
            p.field = {129, 32, 8, DirectionScheme::Octahedral};
            p.texel_divisions = 16;
            p.cycles = 16;
            p.stop_unshot = 1e-2;
            break;
        case Quality::Preview:  // within 5 % away from emitters
            p.field = {513, 64, 8, DirectionScheme::Octahedral};
            p.texel_divisions = 32;
            p.cycles = 64;
            p.stop_unshot = 2e-3;
            p.filter_sigma = 0.7;
            break;
        case Quality::Final:  // within 2 %
            p.field = {2049, 128, 16, DirectionScheme::Octahedral};
            p.texel_divisions = 64;
            p.cycles = 128;
            p.stop_unshot = 5e-4;
            p.perturbations = 1;
            p.filter_sigma = 0.7;
            p.supersample = 2;
            break;
        case Quality::Reference:  // for comparisons: as far as the machine allows
            p.field = {8193, 256, 16, DirectionScheme::Octahedral};
            p.texel_divisions = 128;
            p.cycles = 256;
            p.stop_unshot = 1e-4;
            p.perturbations = 3;
            p.filter_sigma = 0.7;
            p.supersample = 2;
            break;
    }
    return p;
}

}  // namespace vlf
