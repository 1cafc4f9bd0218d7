#include "vlf/transport/smooth_surfaces.hpp"

#include <algorithm>
#include <utility>

#include "vlf/core/error.hpp"
#include "vlf/field/psf.hpp"
#include "vlf/scene/smooth_groups.hpp"

namespace vlf {

SmoothSurfaces find_smooth_surfaces(const Scene& scene, const DirectionSet& dirs,
                                    const Coverage& coverage) {
    SmoothSurfaces s;
    SmoothGroups groups = group_smooth_specular_faces(scene);
    s.of_face = std::move(groups.of_face);
    s.faces = std::move(groups.faces);
    s.directions = dirs.size();
    s.rays.assign(size_t(s.size()) * size_t(s.directions) * 2, 0);
    for (int k = 0; k < s.size(); ++k)
        for (int d = 0; d < s.directions; ++d) {
            const Vec3 omega = dirs.direction(d);
            for (int f : s.faces[size_t(k)]) {
                const double c = glm::dot(scene.faces[size_t(f)].normal, omega);
                if (c == 0.0) continue;
                s.rays[s.slot(k, d, c > 0 ? 1 : -1)] += coverage(d, f);
            }
        }
    return s;
}

void surface_rays(const Scene& scene, const SmoothSurfaces& surfaces, const RadianceMaps& maps,
                  int surface, int d, const Mat3& rotation, const Vec3& omega, int N, int m,
                  TwinRasters& twins, SurfaceRays& out) {
    out.rays.clear();
    FaceRaster fr;
    int imin = N, imax = -1, jmin = N, jmax = -1;
    for (int f : surfaces.faces[size_t(surface)]) {
        const Face& face = scene.faces[size_t(f)];
        if (glm::dot(face.normal, omega) <= 0.0) continue;
        const uint64_t count = maps.count(d, f);
        if (count == 0) continue;  // (most of a tessellated ball's faces, in any direction)
        twins.rasterise(face, rotation, N, m, fr);
        VLF_CHECK(fr.covered == count);
        uint32_t k = 0;
        for (const FaceFragment& ff : fr.fragments)
            fr.edge_table(ff).for_each_ray([&](int u, int v, int) {
                const int i = ff.s * m + u, j = ff.t * m + v;
                out.rays.push_back({f, k++, int16_t(i), int16_t(j)});
                imin = std::min(imin, i), imax = std::max(imax, i);
                jmin = std::min(jmin, j), jmax = std::max(jmax, j);
            });
    }
    out.i0 = imin, out.j0 = jmin;
    out.width = std::max(0, imax - imin + 1), out.height = std::max(0, jmax - jmin + 1);
    out.head.assign(size_t(out.width) * size_t(out.height), -1);
    out.next.assign(out.rays.size(), -1);
    // Reverse order, so each pixel's list runs in ray order.
    for (size_t r = out.rays.size(); r-- > 0;) {
        const size_t at =
            size_t(out.rays[r].j - out.j0) * size_t(out.width) + size_t(out.rays[r].i - out.i0);
        out.next[r] = out.head[at];
        out.head[at] = int32_t(r);
    }
}

}  // namespace vlf
