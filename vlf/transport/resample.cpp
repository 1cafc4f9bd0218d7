#include "vlf/transport/resample.hpp"

#include "vlf/core/error.hpp"
#include "vlf/core/fresnel.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/field/lightmap.hpp"
#include "vlf/field/psf.hpp"
#include "vlf/scene/specular_turn.hpp"

namespace vlf {

bool trace_leaving(const RayCaster& caster, int from, const Vec3& origin, const Vec3& dir,
                   RayHit& hit) {
    return caster.intersect_past(from, origin + kResampleEpsilon * dir, dir, 0.0, 1e30, hit);
}

// The reflection, derived. A mirror with unit normal n reflects light that travels along
// i (towards the mirror, i.n < 0) into the travel direction t = i - 2 (i.n) n, which
// leaves the front (t.n = -i.n > 0). Reflection about the plane is its own inverse, so the
// light that leaves along t arrived travelling along i = t - 2 (t.n) n. It came *from*
// the opposite way, so the surface that sent it lies along w = -i = 2 (t.n) n - t from the
// point (w.n = t.n > 0: on the front side, as it must). Tracing along w finds that surface
// Q at q; the light it sends towards the mirror travels along -w, which must leave Q's
// front: n_Q.(-w) > 0, i.e. n_Q.w < 0 — otherwise the ray met Q's back, which sends
// nothing. At Q the same step repeats with t <- -w while Q is specular.
//
// Glass adds a second way in: light that leaves a dielectric face's front along t may
// have come through the interface from behind. A ray reversed along -t refracts into the
// back medium along w' = refract(-t, n, eta) (eta = n_front / n_back), Fresnel's R is the
// same both ways, and radiance crossing the interface scales by (n_front / n_back)^2
// (docs/propagation.md §13): L = R L_reflected + (1 - R) eta^2 L_behind. A path that runs
// inside absorbing glass keeps exp(-sigma d). On a smooth mirror or glass object n is the
// shading normal at the point (specular_turn.hpp), so a tessellated ball's resampled maps
// show a ball's reflection, not its facets'.
namespace {

struct PathTracer {
    const Scene& scene;
    const RayCaster& caster;
    const OutwardCasters* outward;  // or null: every cast searches the whole scene
    const std::vector<Rgb>& radiance;
    const std::vector<size_t>& offset;
    int max_bounces;

    // Radiance arriving at p along the look direction w (from the surface it meets);
    // `inside`: the segment runs through glass of material `medium`.
    Rgb look(int from, const Vec3& p, const Vec3& w, const Material* medium, double weight,
             int bounce) const {
        if (weight < kResampleMinWeight) return Rgb(0.0);  // not followed: nothing traced
        RayHit hit;
        const RayCaster& c = outward ? outward->leaving(from, w) : caster;
        if (!trace_leaving(c, from, p, w, hit)) return Rgb(0.0);                // escaped
        if (glm::dot(scene.faces[hit.face].normal, w) >= 0.0) return Rgb(0.0);  // back face
        Rgb kept(1.0);
        if (medium && medium->is_absorbing())
            kept = glm::exp(-medium->absorption * (hit.t / scene.normalisation.scale));
        return kept * leaving(hit.face, hit.point, -w, weight, bounce + 1);
    }

    Rgb leaving(int cur, const Vec3& p, const Vec3& t, double weight, int bounce) const {
        const Face& f = scene.faces[cur];
        const Material& mat = scene.material_of(f);
        Rgb value(0.0);
        // Own diffuse part (mixed materials add theirs at every bounce); P^T of an emitter
        // holds its emission.
        if (mat.is_diffuse() || mat.is_emitter())
            value += sample_lightmap(scene.chart_of(f), radiance.data() + offset[f.chart], p);
        if (!mat.is_specular() || bounce >= max_bounces) return value;
        if (glm::dot(t, f.normal) <= 0.0) return value;  // a mirror reflects on its front only
        // The reversed ray meets the front along -t and turns as any ray there does, about
        // the shading normal of a smooth surface (specular_turn.hpp).
        const SpecularTurn turn = specular_turn(scene, f, p, -t);
        if (!mat.dielectric)
            return value + mat.specular * look(cur, p, turn.reflected, nullptr,
                                               weight * luminance_of(mat.specular), bounce);
        const double eta = interface_eta(f.inner, mat.ior);
        const double R = turn.R;
        // The front's medium is the glass when the face is inner.
        value += R * look(cur, p, turn.reflected, f.inner ? &mat : nullptr, weight * R, bounce);
        if (turn.refracts)
            value +=
                ((1.0 - R) * eta * eta) *
                look(cur, p, turn.refracted, f.inner ? nullptr : &mat, weight * (1.0 - R), bounce);
        return value;
    }

    static double luminance_of(const Rgb& c) { return (c.x + c.y + c.z) / 3.0; }
};

}  // namespace

Rgb specular_path_radiance(const Scene& scene, const RayCaster& caster,
                           const std::vector<Rgb>& radiance, const std::vector<size_t>& offset,
                           int face, const Vec3& point, const Vec3& travel, int max_bounces) {
    const PathTracer tracer{scene, caster, nullptr, radiance, offset, max_bounces};
    return tracer.leaving(face, point, travel, 1.0, 0);
}

SpecularResampler::SpecularResampler(Transport& transport, const RayCaster& caster)
    : m_transport(transport),
      m_caster(caster),
      m_radiance(texel_radiance(transport.scene(), transport.texture_maps())),
      m_outward(transport.scene(), caster, [&](int object) {
          const Scene& s = transport.scene();
          const SceneObject& o = s.objects[size_t(object)];
          return o.face_count > 0 && s.material_of(s.faces[size_t(o.first_face)]).is_specular();
      }) {
    VLF_CHECK(caster.scene().faces.size() == transport.scene().faces.size());
}

bool SpecularResampler::resamples(int f) const {
    // An inner face's front looks into its glass: only an eye inside the glass sees it
    // (render.cpp), and it keeps the field's L_T.
    return m_transport.specular_maps().stores(f) && !m_transport.scene().faces[size_t(f)].inner;
}

bool SpecularResampler::face(int d, int fid, const FaceRaster& fr) const {
    RadianceMaps& maps = m_transport.specular_maps();
    const uint64_t n = maps.count(d, fid);
    if (n == 0 || !resamples(fid)) return false;
    VLF_CHECK(fr.covered == n);
    const Scene& scene = m_transport.scene();
    const int N = m_transport.params().field.resolution, m = m_transport.params().field.tile;
    const Mat3& rot = m_transport.rotations()[size_t(d)];
    // The face sends along +omega_d when its front faces +z of the PSF.
    const Vec3 travel = double(fr.facing) * m_transport.directions().direction(d);
    const PlaneInPsf plane(scene.faces[size_t(fid)], rot, N);
    const std::vector<size_t>& offset = m_transport.texture_maps().offset;
    const uint64_t base = maps.begin(d, fid);
    const PathTracer tracer{scene, m_caster, &m_outward, m_radiance, offset, kResampleMaxBounces};
    uint64_t k = 0;  // face-local ray order: fragments in tile order, edge-table order
    for (const FaceFragment& ff : fr.fragments)
        fr.edge_table(ff).for_each_ray([&](int u, int v, int) {
            const Vec3 point = plane.point(ff.s * m + u, ff.t * m + v);
            const Rgb L = tracer.leaving(fid, point, travel, 1.0, 0);
            maps.total[base + k++] = RgbF(L);
        });
    return true;
}

void SpecularResampler::direction(int d) const {
    const Scene& scene = m_transport.scene();
    const int N = m_transport.params().field.resolution, m = m_transport.params().field.tile;
    const RadianceMaps& maps = m_transport.specular_maps();
    thread_local FaceRaster fr;
    for (int fid : maps.faces) {
        if (maps.count(d, fid) == 0 || !resamples(fid)) continue;
        rasterise_face(scene.faces[size_t(fid)], m_transport.rotations()[size_t(d)], N, m, fr);
        face(d, fid, fr);
    }
}

void resample_specular(Transport& transport, const RayCaster& caster, int /*threads_unused*/) {
    if (transport.specular_maps().faces.empty()) return;
    const SpecularResampler resampler(transport, caster);
    parallel_for(0, transport.directions().size(),
                 [&](long d) { resampler.direction(static_cast<int>(d)); });
}

}  // namespace vlf
