// transport_setup.cpp — what every cycle of the transport reads, built once: the rotations
// of each pass's directions (the true ones and each perturbation, VLF §5), the rays each
// face covers, the diffuse send normalisers (§4.4 eq. (3)), the texture and radiance maps,
// the mean reflectance (§4.5 eq. (4)), face polygons and rim pools.
#include <cmath>

#include "vlf/core/parallel.hpp"
#include "vlf/core/rotation.hpp"
#include "vlf/transport/perturbation.hpp"
#include "vlf/transport/transport_internal.hpp"

namespace vlf {

using transport_detail::luminance;

std::vector<uint32_t> measure_coverage(const Scene& scene, const std::vector<Mat3>& rotations,
                                       int N, int m) {
    const size_t nf = scene.faces.size();
    std::vector<uint32_t> cov(rotations.size() * nf, 0);
    parallel_for(0, static_cast<long>(rotations.size()), [&](long d) {
        FaceRaster fr;
        for (size_t f = 0; f < nf; ++f) {
            rasterise_face(scene.faces[f], rotations[d], N, m, fr);
            cov[size_t(d) * nf + f] = fr.covered;
        }
    });
    return cov;
}

double transport_detail::projected_cosine(const Scene& scene, const Chart& c,
                                          const Mat3& rotation) {
    if (c.faces.size() == 1) return std::abs((rotation * scene.faces[c.faces[0]].normal).z);
    double s = 0.0;
    for (int f : c.faces) s += scene.faces[f].area * std::abs((rotation * scene.faces[f].normal).z);
    return s / c.area;
}

// Sum over the directions a chart has rays in of |n . omega_d| * Delta_d: the denominator
// of the diffuse share (VLF §4.4 eq. (3), the "total projected unit area", corrected for
// unequal solid angles — §5). Restricting it to covered directions makes the shares of
// every chart sum to exactly 1.
std::vector<double> send_normalisers(const Scene& scene, const DirectionSet& dirs,
                                     const std::vector<Mat3>& rotations,
                                     const std::vector<uint32_t>& coverage) {
    const size_t nf = scene.faces.size();
    std::vector<double> norm(scene.charts.size(), 0.0);
    parallel_for(0, static_cast<long>(scene.charts.size()), [&](long k) {
        const Chart& c = scene.charts[k];
        for (int d = 0; d < dirs.size(); ++d) {
            bool covered = false;
            for (int f : c.faces) covered = covered || coverage[size_t(d) * nf + f] > 0;
            if (covered) norm[k] += transport_detail::projected_cosine(scene, c, rotations[d]) * dirs.solid_angle(d);
        }
    });
    return norm;
}

namespace {

// The mean reflectance rho_S of VLF §4.5 eq. (4), weighted by face area.
double mean_reflectance(const Scene& scene) {
    double area = 0.0, refl = 0.0;
    for (const Face& f : scene.faces) {
        const Material& mat = scene.material_of(f);
        area += f.area;
        refl += f.area * luminance(mat.diffuse + mat.specular);
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
    pass.send_norm = p == 0 && s == 1
                         ? send_normalisers(m_scene, m_dirs, m_rot, m_coverage)
                         : send_normalisers(m_scene, m_dirs, pass.rotations,
                                            measure_coverage(m_scene, pass.rotations,
                                                             m_params.field.resolution * s,
                                                             m_params.field.tile * s));
    return pass;
}

Transport::Transport(const Scene& scene, const PropagateParams& params)
    : m_scene(scene), m_params(params), m_dirs(params.field.directions, params.field.scheme) {
    validate(params);
    const Stopwatch setup;
    const int l = m_dirs.size();
    m_rot.resize(l);
    for (int d = 0; d < l; ++d) m_rot[d] = rotation_to_z(m_dirs.direction(d));
    m_coverage = measure_coverage(scene, m_rot, params.field.resolution, params.field.tile);
    m_passes.resize(size_t(params.perturbations) + 1);
    for (int p = 0; p <= params.perturbations; ++p) m_passes[p] = make_pass(p);
    m_tex = TextureMaps(scene);

    const size_t nf = scene.faces.size();
    std::vector<bool> spec(nf), other(nf);
    for (size_t f = 0; f < nf; ++f) {
        spec[f] = scene.material_of(scene.faces[f]).is_specular();
        other[f] = params.store_all_rays && !spec[f];
    }
    m_spec = RadianceMaps(scene, spec, l, m_coverage, true);
    m_other = RadianceMaps(scene, other, l, m_coverage, false);
    m_mean_reflectance = mean_reflectance(scene);
    m_deferred.assign(scene.charts.size(), 0);
    // A beam's footprint reaches about a pixel (2 / N, the PSF square's side over N) from
    // its ray; two pixels of the exchange grid cover beams down to cos 0.35 (docs/charts.md).
    m_polygons = faces_in_texels(scene, 2.0 * 2.0 / (params.field.resolution * params.supersample));
    m_pools = build_rim_pools(scene, m_tex);
    m_cache.resize(static_cast<size_t>(l) * m_passes.size());
    m_work = std::make_unique<Workspace>();
    m_timings.setup = setup.seconds();
}

Transport::~Transport() = default;

}  // namespace vlf
