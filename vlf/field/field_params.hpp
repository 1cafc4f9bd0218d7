// field_params.hpp — the parameters that shape the light field itself (VLF §3): the
// number of line directions l, the rays per PSF side N, the rays per tile side m and the
// direction scheme. The run's other parameters live in transport/parameters.hpp.
#pragma once

#include <nlohmann/json.hpp>

#include "vlf/field/direction_set.hpp"

namespace vlf {

struct FieldParams {
    int directions = 513;  // l, line directions (2*4^k + 1)
    int resolution = 64;   // N, rays per PSF side
    int tile = 8;          // m, rays per tile side
    DirectionScheme scheme = DirectionScheme::Octahedral;
};

nlohmann::json to_json(const FieldParams& p);

}  // namespace vlf
