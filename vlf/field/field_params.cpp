#include "vlf/field/field_params.hpp"

#include <algorithm>

namespace vlf {

nlohmann::json to_json(const FieldParams& p) {
    return {{"directions", p.directions},
            {"resolution", p.resolution},
            {"tile", p.tile},
            {"tiles_per_side", p.resolution / std::max(1, p.tile)},
            {"scheme", to_string(p.scheme)}};
}

}  // namespace vlf
