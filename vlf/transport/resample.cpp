#include "vlf/transport/resample.hpp"

#include "vlf/core/error.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/field/lightmap.hpp"
#include "vlf/field/psf.hpp"

namespace vlf {

namespace {

// Closest hit along `dir` from `origin` on `from`, ignoring `from` itself: a convex planar
// face cannot be met again by a ray leaving it, so a hit on it is rounding at t ~ 0.
bool trace_from(const RayCaster& caster, int from, const Vec3& origin, const Vec3& dir,
                RayHit& hit) {
    Vec3 o = origin + kResampleEpsilon * dir;
    for (int attempt = 0; attempt < 4; ++attempt) {
        if (!caster.intersect(o, dir, 0.0, 1e30, hit)) return false;
        if (hit.face != from) return true;
        o = hit.point + kResampleEpsilon * dir;
    }
    return false;
}

}  // namespace

// The reflection, derived. A mirror with unit normal n reflects light that travels along
// i (towards the mirror, i.n < 0) into the travel direction t = i - 2 (i.n) n, which
// leaves the front (t.n = -i.n > 0). Reflection about the plane is its own inverse, so the
// light that leaves along t arrived travelling along i = t - 2 (t.n) n. It came *from*
// the opposite way, so the surface that sent it lies along w = -i = 2 (t.n) n - t from the
// point (w.n = t.n > 0: on the front side, as it must). Tracing along w finds that surface
// Q at q; the light it sends towards the mirror travels along -w, which must leave Q's
// front: n_Q.(-w) > 0, i.e. n_Q.w < 0 — otherwise the ray met Q's back, which sends
// nothing. At Q the same step repeats with t <- -w while Q is specular.
Rgb specular_path_radiance(const Scene& scene, const RayCaster& caster,
                           const std::vector<Rgb>& radiance, const std::vector<size_t>& offset,
                           int face, const Vec3& point, const Vec3& travel, int max_bounces) {
    Rgb value(0.0), throughput(1.0);
    int cur = face;
    Vec3 p = point, t = travel;
    for (int bounce = 0;; ++bounce) {
        const Face& f = scene.faces[cur];
        const Material& mat = scene.material_of(f);
        // Own diffuse part (mixed materials add theirs at every bounce); P^T of an emitter
        // holds its emission.
        if (mat.is_diffuse() || mat.is_emitter())
            value += throughput *
                     sample_lightmap(scene.chart_of(f), radiance.data() + offset[f.chart], p);
        if (!mat.is_specular() || bounce >= max_bounces) break;
        const double tn = glm::dot(t, f.normal);
        if (tn <= 0.0) break;  // leaving the back: a mirror reflects on its front only
        const Vec3 w = 2.0 * tn * f.normal - t;
        RayHit hit;
        if (!trace_from(caster, cur, p, w, hit)) break;               // escaped
        if (glm::dot(scene.faces[hit.face].normal, w) >= 0.0) break;  // back face
        throughput *= mat.specular;
        cur = hit.face;
        p = hit.point;
        t = -w;
    }
    return value;
}

void resample_specular(Transport& transport, const RayCaster& caster, int /*threads_unused*/) {
    const Scene& scene = transport.scene();
    VLF_CHECK(caster.scene().faces.size() == scene.faces.size());
    const int N = transport.params().field.resolution, m = transport.params().field.tile;
    const std::vector<Rgb> radiance = texel_radiance(scene, transport.texture_maps());
    const std::vector<size_t>& offset = transport.texture_maps().offset;
    const DirectionSet& dirs = transport.directions();
    const std::vector<Mat3>& rotations = transport.rotations();
    RadianceMaps& maps = transport.specular_maps();
    if (maps.faces.empty()) return;

    parallel_for(0, dirs.size(), [&](long dl) {
        const int d = static_cast<int>(dl);
        const Mat3& rot = rotations[d];
        const Mat3 rt = glm::transpose(rot);  // rotated frame -> scene frame
        FaceRaster fr;
        for (int fid : maps.faces) {
            const uint64_t n = maps.count(d, fid);
            if (n == 0) continue;
            const Face& face = scene.faces[fid];
            rasterise_face(face, rot, N, m, fr);
            VLF_CHECK(fr.covered == n);
            // The face sends along +omega_d when its front faces +z of the PSF.
            const Vec3 travel = double(fr.facing) * dirs.direction(d);
            const Vec3 nr = rot * face.normal;
            const uint64_t base = maps.begin(d, fid);
            uint64_t k = 0;  // face-local ray order: fragments in tile order, edge-table order
            for (const FaceFragment& ff : fr.fragments)
                fr.edge_table(ff).for_each_ray([&](int u, int v, int) {
                    const double x = (2.0 * (ff.s * m + u) + 1.0) / N - 1.0;
                    const double y = (2.0 * (ff.t * m + v) + 1.0) / N - 1.0;
                    const double z = (face.plane_offset - nr.x * x - nr.y * y) / nr.z;
                    const Vec3 point = rt * Vec3(x, y, z);
                    const Rgb L =
                        specular_path_radiance(scene, caster, radiance, offset, fid, point, travel);
                    maps.total[base + k++] = RgbF(L);
                });
        }
    });
}

}  // namespace vlf
