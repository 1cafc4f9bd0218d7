#include "vlf/field/radiance_maps.hpp"

#include <algorithm>
#include <limits>

#include "vlf/core/error.hpp"

namespace vlf {

RadianceMaps::RadianceMaps(const Scene& scene, const std::vector<bool>& stored, int dirs,
                           const Coverage& coverage, bool unshot_maps, int d0, int d1)
    : directions(dirs), with_unshot(unshot_maps) {
    const size_t nf = scene.faces.size();
    slot.assign(nf, -1);
    for (size_t f = 0; f < nf; ++f)
        if (stored[f]) {
            slot[f] = static_cast<int>(faces.size());
            faces.push_back(static_cast<int>(f));
        }
    const size_t per = faces.size() + 1;
    dir_first.assign(size_t(dirs) + 1, 0);
    within.assign(size_t(dirs) * per, 0);
    uint64_t at = 0;
    for (int d = 0; d < dirs; ++d) {
        dir_first[size_t(d)] = at;
        uint64_t n = 0;
        for (size_t k = 0; k < faces.size(); ++k) {
            within[size_t(d) * per + k] = uint32_t(n);
            n += coverage(d, faces[k]);
        }
        VLF_CHECK(n <= std::numeric_limits<uint32_t>::max());
        within[size_t(d) * per + faces.size()] = uint32_t(n);
        at += n;
    }
    dir_first.back() = at;
    hold(d0, d1 < 0 ? dirs : d1);
}

void RadianceMaps::hold(int d0, int d1) {
    const uint64_t b = ray_begin(d0), e = ray_begin(d1);
    auto rehold = [&](std::vector<RgbF>& v) {
        std::vector<RgbF> held(e - b, RgbF(0.0f));
        const uint64_t lo = std::max(b, base), hi = std::min(e, base + v.size());
        for (uint64_t k = lo; k < hi; ++k) held[k - b] = v[k - base];
        v.swap(held);
    };
    rehold(total);
    if (with_unshot) {
        rehold(unshot);
        rehold(unshot_next);
    }
    first = d0;
    last = d1;
    base = b;
}

int64_t RadianceMaps::bytes() const {
    return static_cast<int64_t>(
        (total.capacity() + unshot.capacity() + unshot_next.capacity()) * sizeof(RgbF) +
        dir_first.capacity() * sizeof(uint64_t) + within.capacity() * sizeof(uint32_t));
}

}  // namespace vlf
