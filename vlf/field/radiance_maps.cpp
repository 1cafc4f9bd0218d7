#include "vlf/field/radiance_maps.hpp"

namespace vlf {

RadianceMaps::RadianceMaps(const Scene& scene, const std::vector<bool>& stored, int dirs,
                           const Coverage& coverage, bool unshot_maps)
    : directions(dirs), with_unshot(unshot_maps) {
    const size_t nf = scene.faces.size();
    slot.assign(nf, -1);
    for (size_t f = 0; f < nf; ++f)
        if (stored[f]) {
            slot[f] = static_cast<int>(faces.size());
            faces.push_back(static_cast<int>(f));
        }
    offset.assign(size_t(dirs) * faces.size() + 1, 0);
    uint64_t at = 0;
    for (int d = 0; d < dirs; ++d)
        for (size_t k = 0; k < faces.size(); ++k) {
            offset[size_t(d) * faces.size() + k] = at;
            at += coverage(d, faces[k]);
        }
    offset.back() = at;
    total.assign(at, RgbF(0.0f));
    if (with_unshot) {
        unshot.assign(at, RgbF(0.0f));
        unshot_next.assign(at, RgbF(0.0f));
    }
}

int64_t RadianceMaps::bytes() const {
    return static_cast<int64_t>((total.capacity() + unshot.capacity() + unshot_next.capacity()) *
                                    sizeof(RgbF) +
                                offset.capacity() * sizeof(uint64_t));
}

}  // namespace vlf
