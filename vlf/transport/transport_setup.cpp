// transport_setup.cpp — what every cycle of the transport reads, built once: the rotations
// of each pass's directions (the true ones and each perturbation, VLF §5), the rays each
// face covers, the diffuse send normalisers (§4.4 eq. (3)), the texture and radiance maps,
// the mean reflectance (§4.5 eq. (4)), face polygons and rim pools.
#include <cmath>

#include "vlf/core/parallel.hpp"
#include "vlf/core/rotation.hpp"
#include "vlf/transport/lamp_caustics.hpp"
#include "vlf/transport/perturbation.hpp"
#include "vlf/transport/small_emitters.hpp"
#include "vlf/transport/transport_internal.hpp"

namespace vlf {

Coverage measure_coverage(const Scene& scene, const std::vector<Mat3>& rotations, int N,
                          const std::vector<uint8_t>& which) {
    const size_t nf = scene.faces.size();
    Coverage cov;
    cov.directions = static_cast<int>(rotations.size());
    cov.row.assign(nf, -1);
    std::vector<int> faces;
    for (size_t f = 0; f < nf; ++f)
        if (which[f]) {
            cov.row[f] = cov.rows++;
            faces.push_back(int(f));
        }
    cov.count.assign(rotations.size() * size_t(cov.rows), 0);
    parallel_for(0, static_cast<long>(rotations.size()), [&](long d) {
        uint32_t* count = cov.count.data() + size_t(d) * cov.rows;
        for (int k = 0; k < cov.rows; ++k) {
            const Face& f = scene.faces[faces[k]];
            // A twin covers its face's rays (one polygon: TwinRasters), unless either is
            // edge-on by its own normal.
            if (f.twin >= 0 && f.twin < f.id && cov.row[size_t(f.twin)] >= 0 &&
                std::abs((rotations[d] * f.normal).z) >= kEdgeOnCosine &&
                std::abs((rotations[d] * scene.faces[size_t(f.twin)].normal).z) >= kEdgeOnCosine) {
                count[k] = count[cov.row[size_t(f.twin)]];
                continue;
            }
            count[k] = count_covered(f, rotations[d], N);
        }
    });
    return cov;
}

double transport_detail::projected_cosine(const Scene& scene, const Chart& c,
                                          const Mat3& rotation) {
    if (c.faces.size() == 1) return std::abs((rotation * scene.faces[c.faces[0]].normal).z);
    // Every face faces the same way when omega is further from the chart's plane than the
    // faces are from its normal: then sum A |n . omega| = |sum A n . omega|.
    const Vec3 omega(rotation[0][2], rotation[1][2], rotation[2][2]);  // (R n).z = n . omega
    const double spread_sin = std::sqrt(std::max(0.0, 1.0 - c.min_cos * c.min_cos));
    if (c.min_cos > 0 && std::abs(glm::dot(c.normal, omega)) > spread_sin + 1e-9)
        return std::abs(glm::dot(c.area_normal, omega)) / c.area;
    double s = 0.0;
    for (int f : c.faces) s += scene.faces[f].area * std::abs((rotation * scene.faces[f].normal).z);
    return s / c.area;
}

// Sum over the directions a chart has rays in of |n . omega_d| * Delta_d: the denominator
// of the diffuse share (VLF §4.4 eq. (3), the "total projected unit area", corrected for
// unequal solid angles — §5). Restricting it to covered directions makes the shares of
// every chart sum to exactly 1. Here for the emitting charts, which send in the first
// cycle; the others' come from the first cycle's geometry (finish_normalisers).
std::vector<double> send_normalisers(const Scene& scene, const DirectionSet& dirs,
                                     const std::vector<Mat3>& rotations, const Coverage& coverage) {
    std::vector<double> norm(scene.charts.size(), 0.0);
    parallel_for(0, static_cast<long>(scene.charts.size()), [&](long k) {
        const Chart& c = scene.charts[k];
        if (!scene.material_of(c).is_emitter()) return;
        for (int d = 0; d < dirs.size(); ++d) {
            bool covered = false;
            for (int f : c.faces) covered = covered || coverage(d, f) > 0;
            if (covered)
                norm[k] += transport_detail::projected_cosine(scene, c, rotations[d]) *
                           dirs.solid_angle(d);
        }
    });
    return norm;
}

void Transport::finish_normalisers(Pass& pass) {
    for (int d = 0; d < m_dirs.size(); ++d)
        for (const ChartCosine& cc : pass.charts[d])
            if (!m_scene.material_of(m_scene.charts[cc.chart]).is_emitter())
                pass.send_norm[cc.chart] += cc.cosine * m_dirs.solid_angle(d);
    pass.norms_known = true;
}

namespace {

// The mean reflectance rho_S of VLF §4.5 eq. (4), weighted by face area.
double mean_reflectance(const Scene& scene) {
    double area = 0.0, refl = 0.0;
    for (const Face& f : scene.faces) {
        const Material& mat = scene.material_of(f);
        area += f.area;
        refl += f.area * (mat.dielectric ? 1.0 : luminance(mat.diffuse + mat.specular));
    }
    return area > 0 ? refl / area : 0.0;
}

}  // namespace

Transport::Pass Transport::make_pass(int p) const {
    // Super-sampled exchange (§5): every pass runs on an s-times finer ray grid; the
    // directional radiance maps stay on the N x N grid.
    const int s = m_params.supersample;
    const int P = m_params.perturbations;
    const int l = m_dirs.size();
    Pass pass;
    if (p == 0) {
        pass.rotations = m_rot;
    } else {
        // VLF §5: the whole direction set rotated by a stratified random rotation inside
        // the mean solid angle (one set per run, perturbation.hpp).
        const Mat3 r = perturbation_rotation(m_dirs, m_params.seed, p, P);
        pass.rotations.resize(l);
        for (int d = 0; d < l; ++d) pass.rotations[d] = rotation_to_z(r * m_dirs.direction(d));
    }
    // The emitters' normalisers now (they send in the first cycle), on the pass's grid.
    std::vector<uint8_t> emitters(m_scene.faces.size(), 0);
    for (const Face& f : m_scene.faces) emitters[f.id] = m_scene.material_of(f).is_emitter();
    pass.send_norm =
        p == 0 && s == 1
            ? send_normalisers(m_scene, m_dirs, m_rot, m_coverage)
            : send_normalisers(m_scene, m_dirs, pass.rotations,
                               measure_coverage(m_scene, pass.rotations,
                                                m_params.field.resolution * s, emitters));
    return pass;
}

namespace transport_detail {

std::vector<PassFace> pass_faces(const Scene& scene, const SmoothSurfaces& surfaces) {
    std::vector<PassFace> out(scene.faces.size());
    for (const Face& f : scene.faces)
        out[size_t(f.id)] = {f.normal, f.chart, surfaces.of_face[size_t(f.id)], f.material,
                             f.inner && scene.material_of(f).is_absorbing()};
    return out;
}

}  // namespace transport_detail

Transport::Transport(const Scene& scene, const PropagateParams& params, Ranks& ranks)
    : m_scene(scene), m_params(params), m_dirs(params.field.directions, params.field.scheme) {
    validate(params);
    m_ranks = &ranks;
    const Stopwatch setup;
    const int l = m_dirs.size();
    m_rot.resize(l);
    for (int d = 0; d < l; ++d) m_rot[d] = rotation_to_z(m_dirs.direction(d));
    // Coverage is measured up front only where it is needed before the first cycle:
    // stored faces (their map sizes) and emitters (they send in it).
    std::vector<uint8_t> measured(scene.faces.size(), 0);
    for (const Face& f : scene.faces) {
        const Material& mat = scene.material_of(f);
        measured[f.id] = mat.is_emitter() || mat.is_specular() || params.store_all_rays;
    }
    m_coverage = measure_coverage(scene, m_rot, params.field.resolution, measured);
    m_surfaces = find_smooth_surfaces(scene, m_dirs, m_coverage);
    m_caustic_faces = caustic_faces(scene, m_surfaces);
    if (params.cache_budget_mib > 0)  // (kept only with a cache budget, as the geometry)
        m_surface_plans.resize(size_t(m_dirs.size()) * size_t(m_surfaces.size()) * 2);
    m_passes.resize(size_t(params.perturbations) + 1);
    for (int p = 0; p <= params.perturbations; ++p) m_passes[p] = make_pass(p);
    m_tex = TextureMaps(scene);

    const size_t nf = scene.faces.size();
    std::vector<bool> spec(nf), other(nf);
    for (size_t f = 0; f < nf; ++f) {
        spec[f] = scene.material_of(scene.faces[f]).is_specular();
        other[f] = params.store_all_rays && !spec[f];
    }
    // Only this rank's directions' rays are allocated (issue 13: memory per rank ~ 1 / K).
    const int r = m_ranks->rank(), d0 = first_direction(r), d1 = first_direction(r + 1);
    m_spec = RadianceMaps(scene, spec, l, m_coverage, true, d0, d1);
    m_other = RadianceMaps(scene, other, l, m_coverage, false, d0, d1);
    m_mean_reflectance = mean_reflectance(scene);
    m_deferred.assign(scene.charts.size(), 0);
    m_small_emitters = small_emitter_charts(scene, params.field.resolution * params.supersample);
    // A beam's footprint reaches about a pixel (2 / N, the PSF square's side over N) from
    // its ray; two pixels of the exchange grid cover beams down to cos 0.35 (docs/charts.md).
    m_rim_reach = 2.0 * 2.0 / (params.field.resolution * params.supersample);
    m_polygons = faces_in_texels(scene, m_rim_reach);
    m_pools = build_rim_pools(scene, m_tex);
    m_cache.resize(static_cast<size_t>(l) * m_passes.size());
    m_work = std::make_unique<Workspace>();
    m_work->faces = transport_detail::pass_faces(scene, m_surfaces);
    for (const transport_detail::PassFace& f : m_work->faces)
        m_work->absorbing_glass |= f.absorbing_inner;
    m_timings.setup = setup.seconds();
}

Transport::~Transport() = default;

}  // namespace vlf
