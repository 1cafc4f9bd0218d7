#include "vlf/transport/transport.hpp"

#include <algorithm>
#include <cmath>

#include "vlf/core/error.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/core/progress.hpp"
#include "vlf/core/rotation.hpp"
#include "vlf/transport/gaussian_filter.hpp"
#include "vlf/transport/perturbation.hpp"
#include "vlf/transport/transport_internal.hpp"

namespace vlf {

using namespace transport_detail;

namespace {

double luminance(const Rgb& c) {
    return (c.x + c.y + c.z) / 3.0;
}

}  // namespace

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

// Sum over the directions a face has rays in of |n . omega_d| * Delta_d: the denominator
// of the diffuse share (VLF §4.4 eq. (3), the "total projected unit area", corrected for
// unequal solid angles — §5). Restricting it to covered directions makes the shares of
// every face sum to exactly 1.
std::vector<double> send_normalisers(const Scene& scene, const DirectionSet& dirs,
                                     const std::vector<Mat3>& rotations,
                                     const std::vector<uint32_t>& coverage) {
    const size_t nf = scene.faces.size();
    std::vector<double> norm(nf, 0.0);
    for (size_t f = 0; f < nf; ++f)
        for (int d = 0; d < dirs.size(); ++d)
            if (coverage[size_t(d) * nf + f] > 0)
                norm[f] += std::abs((rotations[d] * scene.faces[f].normal).z) * dirs.solid_angle(d);
    return norm;
}

Transport::Transport(const Scene& scene, const PropagateParams& params)
    : m_scene(scene), m_params(params), m_dirs(params.field.directions, params.field.scheme) {
    validate(params);
    const auto t0 = Clock::now();
    const int l = m_dirs.size();
    m_rot.resize(l);
    for (int d = 0; d < l; ++d) m_rot[d] = rotation_to_z(m_dirs.direction(d));
    m_coverage = measure_coverage(scene, m_rot, params.field.resolution, params.field.tile);
    // Super-sampled exchange (§5): every pass runs on an s-times finer ray grid; the
    // directional radiance maps stay on the N x N grid.
    const int s = params.supersample;
    const int P = params.perturbations;
    m_passes.resize(size_t(P) + 1);
    for (int p = 0; p <= P; ++p) {
        Pass& pass = m_passes[p];
        if (p == 0) {
            pass.rotations = m_rot;
        } else {
            // VLF §5: the whole direction set rotated by a stratified random rotation
            // inside the mean solid angle (one set per run, perturbation.hpp).
            const Mat3 r = perturbation_rotation(m_dirs, params.seed, p, P);
            pass.rotations.resize(l);
            for (int d = 0; d < l; ++d) pass.rotations[d] = rotation_to_z(r * m_dirs.direction(d));
        }
        pass.send_norm = p == 0 && s == 1
                             ? send_normalisers(scene, m_dirs, m_rot, m_coverage)
                             : send_normalisers(scene, m_dirs, pass.rotations,
                                                measure_coverage(scene, pass.rotations,
                                                                 params.field.resolution * s,
                                                                 params.field.tile * s));
    }
    m_tex = TextureMaps(scene);

    const size_t nf = scene.faces.size();
    std::vector<bool> spec(nf), other(nf);
    double area = 0.0, refl = 0.0;
    for (size_t f = 0; f < nf; ++f) {
        const Material& mat = scene.material_of(scene.faces[f]);
        spec[f] = mat.is_specular();
        other[f] = params.store_all_rays && !spec[f];
        area += scene.faces[f].area;
        refl += scene.faces[f].area * luminance(mat.diffuse + mat.specular);
    }
    m_spec = RadianceMaps(scene, spec, l, m_coverage, true);
    m_other = RadianceMaps(scene, other, l, m_coverage, false);
    m_mean_reflectance = area > 0 ? refl / area : 0.0;  // VLF §4.5 eq. (4)
    m_deferred.assign(nf, 0);
    m_polygons.resize(nf);
    for (size_t f = 0; f < nf; ++f) m_polygons[f] = face_in_texels(scene.faces[f]);
    m_pools = build_rim_pools(scene, m_tex);
    m_cache.resize(static_cast<size_t>(l) * m_passes.size());
    m_work = std::make_unique<Workspace>();
    m_timings.setup = since(t0);
}

Transport::~Transport() = default;

int64_t Transport::work(int cycles) const {
    const int perturbed = std::min(cycles, m_params.perturb_cycles);
    const int64_t passes = int64_t(perturbed) * int64_t(m_passes.size()) + (cycles - perturbed);
    return passes * m_dirs.size();
}

double Transport::to_user_power() const {
    const double s = m_scene.normalisation.scale;
    return 1.0 / (s * s);
}

int64_t Transport::memory_bytes() const {
    return static_cast<int64_t>(m_tex.texels() * 3 * sizeof(Rgb)) + m_spec.bytes() +
           m_other.bytes() + static_cast<int64_t>(m_coverage.size() * sizeof(uint32_t)) +
           static_cast<int64_t>(kWave * m_tex.texels() * sizeof(Rgb)) + geometry_cache_bytes();
}

void Transport::load_emission(LedgerEntry& e) {
    for (const Face& f : m_scene.faces) {
        const Material& mat = m_scene.material_of(f);
        if (!mat.is_emitter()) continue;
        const size_t b = m_tex.begin(f.id);
        for (size_t t = 0; t < m_tex.count(f.id); ++t) {
            // Exitance M = pi * Le of a Lambertian emitter, times the texel's area inside
            // the face: the texel's emitted power.
            const Rgb p = mat.emission * (kPi * f.texel_area[t]);
            m_tex.current[b + t] += p;
            m_tex.total[b + t] += p;
            e.emitted += p;
        }
    }
}

// VLF §4.5: a face whose unshot power is small against what the scene as a whole is
// expected to hold next cycle (rho_S times today's mean unshot exitance, eq. (4)) keeps
// accumulating instead of shooting. kappa < 1 keeps the threshold conservative.
void Transport::choose_deferred(bool last) {
    std::fill(m_deferred.begin(), m_deferred.end(), 0);
    if (!m_params.deferred || last || m_ledger.empty()) return;
    constexpr double kappa = 0.5;
    double unshot = 0.0, area = 0.0;
    std::vector<double> u(m_scene.faces.size());
    for (const Face& f : m_scene.faces) {
        u[f.id] = luminance(TextureMaps::sum(m_tex.current, m_tex.begin(f.id), m_tex.count(f.id)));
        unshot += u[f.id];
        area += f.area;
    }
    if (unshot <= 0.0) return;
    const double mean_exitance = unshot / area;
    for (const Face& f : m_scene.faces)
        if (u[f.id] > 0.0 && u[f.id] < kappa * m_mean_reflectance * mean_exitance * f.area)
            m_deferred[f.id] = 1;
}

void Transport::run_pass(int pass, double share) {
    const auto pass_start = Clock::now();
    const std::vector<Mat3>& rotations = m_passes[pass].rotations;
    const std::vector<double>& send_norm = m_passes[pass].send_norm;
    const bool true_directions = pass == 0;
    const Scene& scene = m_scene;
    const int s = m_params.supersample;
    const int Nc = m_params.field.resolution, mc = m_params.field.tile;  // radiance-map grid
    const int N = Nc * s, m = mc * s;                                    // exchange grid
    const int l = static_cast<int>(rotations.size());
    const size_t nf = scene.faces.size();

    // Which faces send diffuse power this pass, how much, and their unshot exitance.
    std::vector<uint8_t> sends(nf, 0);
    std::vector<Rgb> face_unshot(nf, Rgb(0.0));
    std::vector<Rgb> exitance(m_tex.texels(), Rgb(0.0));
    for (size_t f = 0; f < nf; ++f) {
        if (m_deferred[f]) continue;
        const size_t tb = m_tex.begin(int(f));
        const Rgb u = TextureMaps::sum(m_tex.current, tb, m_tex.count(int(f)));
        sends[f] = (u.x > 0 || u.y > 0 || u.z > 0) && send_norm[f] > 0;
        if (!sends[f]) continue;
        face_unshot[f] = u;
        const Face& face = scene.faces[f];
        for (size_t t = 0; t < m_tex.count(int(f)); ++t)
            if (face.texel_area[t] > 0.0)
                exitance[tb + t] = m_tex.current[tb + t] / face.texel_area[t];
    }
    // Geometry is kept across cycles while it fits the budget; the rest is rebuilt each
    // cycle (identical either way, so the budget never changes a map). A perturbed pass's
    // geometry is not worth keeping in the last cycle that perturbs: it clips only the rays
    // that carry power in this pass.
    const bool reused = pass == 0 || cycles_done() + 1 < m_params.perturb_cycles;
    const GeometryInputs inputs{.scene = scene,
                                .polygons = m_polygons,
                                .seal_gap = scene.seal_gap,
                                .N = N,
                                .m = m,
                                .sending = reused ? nullptr : sends.data()};
    const GeometryCache cache{.slots = m_cache.data() + size_t(pass) * size_t(l),
                              .used = m_cache_used,
                              .budget = reused ? m_params.cache_budget_mib << 20 : 0};
    // Chunks run in waves; each wave's accumulators are reduced in chunk order before the
    // next wave starts, so only a wave's worth of P^N accumulators is alive and the sums
    // are the same as reducing all kChunks at the end (DESIGN §5 Parallelism).
    std::vector<ChunkResult>& chunks = m_work->chunks;
    chunks.resize(kWave);
    std::vector<SpecularSource> sources;
    for (int wave = 0; wave < kChunks; wave += kWave) {
        parallel_for(wave, std::min(wave + kWave, kChunks), [&](long c) {
            ChunkResult& res = chunks[c - wave];
            res.reset(m_tex.texels());
            Scratch& w = m_work->scratch.local();
            const int d0 = static_cast<int>(c * l / kChunks),
                      d1 = static_cast<int>((c + 1) * l / kChunks);
            for (int d = d0; d < d1; ++d) {
                if (m_progress != nullptr) m_progress->advance();
                const Mat3& rot = rotations[d];
                // 1. The direction's geometry: PSF, partners, overlaps (§3, §4.1, §4.2).
                const DirectionGeometry& g =
                    direction_geometry(inputs, cache, rot, d, w, res.times);
                const Psf& psf = g.psf;
                const Vec3 omega = psf.omega;
                const double beam = psf.ray_area() * m_dirs.solid_angle(d);  // a * Delta_d
                const uint32_t S = g.tile_base.back();
                w.out.assign(S, Rgb(0.0));
                w.in.assign(S, Rgb(0.0));

                // 2. Senders load their rays (§4.4 eq. (3), §4.1 line 9).
                auto t0 = Clock::now();
                for (size_t f = 0; f < nf; ++f) {
                    const uint32_t fb = g.face_begin[f], fe = g.face_begin[f + 1];
                    const Face& face = scene.faces[f];
                    const size_t tb = m_tex.begin(int(f));
                    const bool spec_store = true_directions && m_spec.stores(int(f));
                    const bool other_store = true_directions && m_other.stores(int(f));
                    if (fb == fe) {
                        // A sliver with rays on the N x N grid but none on the finer exchange
                        // grid: its unshot specular light cannot leave; the ledger absorbs it.
                        if (spec_store && m_coverage[size_t(d) * nf + f] > 0) {
                            const double beam_c = ray_area(Nc) * m_dirs.solid_angle(d);
                            const uint64_t mb = m_spec.begin(d, int(f));
                            for (uint64_t k = 0; k < m_spec.count(d, int(f)); ++k)
                                res.lost.subpixel_mirror += Rgb(m_spec.unshot[mb + k]) * beam_c;
                        }
                        continue;
                    }
                    if (sends[f]) {
                        // Each ray samples the face's unshot exitance under its footprint
                        // (the weights are unbiased at the rim, texel_clip.hpp); the rays are
                        // then scaled so the face sends exactly its share into this
                        // direction, wd = cos(theta_d) Delta_d / sum (VLF §4.4 eq. (3)).
                        // Sampling exitance rather than splitting each texel's power keeps a
                        // uniform field uniform at the rim (docs/propagation.md §3).
                        const double nz = std::abs((rot * face.normal).z);
                        const double wd = share * nz * m_dirs.solid_angle(d) / send_norm[f];
                        Rgb sampled(0.0);
                        uint32_t rays = 0;
                        for_fragments(
                            g, fb, fe, [&](const Tile& tile, const Fragment& fr, uint32_t base) {
                                for (uint32_t k = 0; k < fr.covered; ++k) {
                                    if (g.partner[base + k] == kSealed) continue;
                                    ++rays;
                                    Rgb p(0.0);
                                    double rowsum = 0.0;
                                    for (uint32_t o = g.ov_begin[base + k];
                                         o < g.ov_begin[base + k + 1]; ++o) {
                                        p += exitance[tb + g.ov[o].texel] * double(g.ov[o].area);
                                        rowsum += g.ov[o].area;
                                    }
                                    if (rowsum > 0.0) p /= rowsum;
                                    w.out[base + k] = p;
                                    sampled += p;
                                }
                            });
                        const Rgb target = face_unshot[f] * wd;
                        Rgb scale(0.0), even(0.0);
                        for (int c = 0; c < 3; ++c) {
                            if (sampled[c] > 0.0)
                                scale[c] = target[c] / sampled[c];
                            else if (rays > 0)
                                even[c] = target[c] / rays;  // no ray sees the unshot texels
                            else
                                res.lost.sealed[c] += target[c];  // every ray is shut
                        }
                        for_fragments(g, fb, fe,
                                      [&](const Tile& tile, const Fragment& fr, uint32_t base) {
                                          for (uint32_t k = 0; k < fr.covered; ++k)
                                              if (g.partner[base + k] != kSealed)
                                                  w.out[base + k] = w.out[base + k] * scale + even;
                                      });
                    }
                    if ((spec_store || other_store) && s == 1) {
                        RadianceMaps& maps = spec_store ? m_spec : m_other;
                        const uint64_t mb = maps.begin(d, int(f));
                        VLF_CHECK(maps.count(d, int(f)) == m_coverage[size_t(d) * nf + f]);
                        uint64_t kl = 0;
                        for_fragments(
                            g, fb, fe, [&](const Tile& tile, const Fragment& fr, uint32_t base) {
                                for (uint32_t k = 0; k < fr.covered; ++k, ++kl) {
                                    Rgb& o = w.out[base + k];
                                    if (spec_store) o += Rgb(maps.unshot[mb + kl]) * beam;
                                    maps.total[mb + kl] += RgbF(o / beam);  // VLF §4.1 line 9
                                }
                            });
                    } else if (spec_store || other_store) {
                        // Super-sampled: each fine ray takes L_U of its N x N parent ray; the
                        // face's unshot power in this direction is rescaled to be sent whole.
                        // L_T of a parent is the mean radiance of its fine rays on the face.
                        RadianceMaps& maps = spec_store ? m_spec : m_other;
                        const uint64_t mb = maps.begin(d, int(f));
                        rasterise_face(face, rot, Nc, mc, w.coarse);
                        VLF_CHECK(maps.count(d, int(f)) == w.coarse.covered);
                        int ci0 = Nc, cj0 = Nc, ci1 = -1, cj1 = -1;
                        for (const FaceFragment& ff : w.coarse.fragments) {
                            ci0 = std::min(ci0, ff.s * mc);
                            ci1 = std::max(ci1, ff.s * mc + mc - 1);
                            cj0 = std::min(cj0, ff.t * mc + ff.row_begin);
                            cj1 = std::max(cj1, ff.t * mc + ff.row_begin + ff.rows - 1);
                        }
                        const int cw = ci1 - ci0 + 1;
                        w.coarse_index.assign(size_t(std::max(0, cw)) * std::max(0, cj1 - cj0 + 1),
                                              -1);
                        {  // local indices in face-local order
                            int32_t k = 0;
                            for (const FaceFragment& ff : w.coarse.fragments)
                                w.coarse.edge_table(ff).for_each_ray([&](int u, int v, int) {
                                    w.coarse_index[size_t(ff.t * mc + v - cj0) * cw +
                                                   (ff.s * mc + u - ci0)] = k++;
                                });
                        }
                        auto parent_of = [&](int i, int j) -> int32_t {
                            const int ci = i / s - ci0, cj = j / s - cj0;
                            if (ci < 0 || cj < 0 || ci >= cw || cj > cj1 - cj0) return -1;
                            return w.coarse_index[size_t(cj) * cw + ci];
                        };
                        const double beam_c = ray_area(Nc) * m_dirs.solid_angle(d);
                        Rgb scale(0.0);
                        if (spec_store) {
                            Rgb unshot(0.0), reach(0.0);
                            for (uint64_t k = 0; k < w.coarse.covered; ++k)
                                unshot += Rgb(maps.unshot[mb + k]) * beam_c;
                            for_fragments(
                                g, fb, fe,
                                [&](const Tile& tile, const Fragment& fr, uint32_t base) {
                                    tile.edge_table(fr).for_each_ray([&](int u, int v, int) {
                                        const int32_t pk =
                                            parent_of(tile.s * m + u, tile.t * m + v);
                                        if (pk >= 0) reach += Rgb(maps.unshot[mb + pk]) * beam;
                                    });
                                });
                            for (int c = 0; c < 3; ++c) {
                                if (reach[c] > 0.0)
                                    scale[c] = unshot[c] / reach[c];
                                else
                                    res.lost.subpixel_mirror[c] +=
                                        unshot[c];  // no fine ray carries it
                            }
                        }
                        w.parent_sum.assign(w.coarse.covered, Rgb(0.0));
                        w.parent_count.assign(w.coarse.covered, 0);
                        for_fragments(
                            g, fb, fe, [&](const Tile& tile, const Fragment& fr, uint32_t base) {
                                tile.edge_table(fr).for_each_ray([&](int u, int v, int k) {
                                    const int32_t pk = parent_of(tile.s * m + u, tile.t * m + v);
                                    Rgb& o = w.out[base + k];
                                    if (pk < 0) return;
                                    if (spec_store) o += Rgb(maps.unshot[mb + pk]) * beam * scale;
                                    w.parent_sum[pk] += o / beam;
                                    ++w.parent_count[pk];
                                });
                            });
                        for (uint64_t k = 0; k < w.coarse.covered; ++k)
                            if (w.parent_count[k] > 0)
                                maps.total[mb + k] +=
                                    RgbF(w.parent_sum[k] / double(w.parent_count[k]));
                    }
                }

                // 3. Exchange along every ray (§4.1 lines 5-8).
                for (uint32_t slot = 0; slot < S; ++slot) {
                    const int32_t p = g.partner[slot];
                    if (p >= 0) {
                        w.in[slot] = w.out[p];
                    } else if (p == kEscaped) {
                        res.escaped += w.out[slot];
                    } else if (p == kSealed) {
                        res.lost.sealed += w.out[slot];  // a mirror's light into a shut ray
                    } else {
                        res.absorbed_back += w.out[slot];  // a one-sided face's black back
                    }
                }
                res.times.transfer += since(t0);

                // 4. Receivers (§4.1 line 10, §4.2-4.3).
                t0 = Clock::now();
                for (size_t f = 0; f < nf; ++f) {
                    const uint32_t fb = g.face_begin[f], fe = g.face_begin[f + 1];
                    if (fb == fe) continue;
                    const Face& face = scene.faces[f];
                    const Material& mat = scene.material_of(face);
                    Rgb received(0.0);
                    int imin = N, imax = -1, jmin = N, jmax = -1;
                    for_fragments(
                        g, fb, fe, [&](const Tile& tile, const Fragment& fr, uint32_t base) {
                            for (uint32_t k = 0; k < fr.covered; ++k) received += w.in[base + k];
                            imin = std::min(imin, tile.s * m);
                            imax = std::max(imax, tile.s * m + m - 1);
                            jmin = std::min(jmin, tile.t * m + fr.row_begin);
                            jmax = std::max(jmax, tile.t * m + fr.row_begin + fr.rows - 1);
                        });
                    if (received.x <= 0 && received.y <= 0 && received.z <= 0) continue;
                    res.absorbed += received * (Rgb(1.0) - mat.diffuse - mat.specular);
                    if (mat.is_diffuse()) {
                        // The temporary radiance tile onto P^N (§4.2): each beam's power
                        // over the texels its footprint overlaps, by overlap area.
                        const size_t tb = m_tex.begin(int(f));
                        for (uint32_t q = fb; q < fe; ++q) {
                            const auto [ti, fi] = g.frags[q];
                            const Fragment& fr = psf.tiles[ti].fragments[fi];
                            const uint32_t base = g.tile_base[ti] + fr.ray_offset;
                            for (uint32_t k = 0; k < fr.covered; ++k) {
                                const Rgb p = w.in[base + k] * mat.diffuse;
                                if (p.x <= 0 && p.y <= 0 && p.z <= 0) continue;
                                double rowsum = 0.0;
                                for (uint32_t o = g.ov_begin[base + k];
                                     o < g.ov_begin[base + k + 1]; ++o)
                                    rowsum += g.ov[o].area;
                                if (rowsum <= 0.0) {
                                    res.lost.empty_footprint += p;
                                    continue;
                                }
                                for (uint32_t o = g.ov_begin[base + k];
                                     o < g.ov_begin[base + k + 1]; ++o)
                                    res.next[tb + g.ov[o].texel] += p * (g.ov[o].area / rowsum);
                            }
                        }
                    }
                    if (mat.is_specular()) {
                        SpecularSource src;
                        src.face = int(f);
                        src.rotation = rot;
                        src.resolution = N;
                        src.power = received * mat.specular;
                        const int facing = (rot * face.normal).z > 0 ? 1 : -1;
                        const Vec3 incoming =
                            omega * double(-facing);  // light travels towards the face
                        src.targets = specular_targets(m_dirs, face, incoming, m_coverage, nf,
                                                       src.target_direction, src.target_weight);
                        if (src.targets == 0) {
                            res.lost.grazing_mirror += src.power;  // no PSF can carry it
                            continue;
                        }
                        src.i0 = imin;
                        src.j0 = jmin;
                        src.width = imax - imin + 1;
                        src.height = jmax - jmin + 1;
                        src.radiance.assign(size_t(src.width) * src.height, RgbF(0.0f));
                        src.covered.assign(size_t(src.width) * src.height, 0);
                        for_fragments(
                            g, fb, fe, [&](const Tile& tile, const Fragment& fr, uint32_t base) {
                                tile.edge_table(fr).for_each_ray([&](int u, int v, int k) {
                                    const size_t at = size_t(tile.t * m + v - src.j0) * src.width +
                                                      (tile.s * m + u - src.i0);
                                    src.radiance[at] = RgbF(w.in[base + k] / beam);
                                    src.covered[at] = 1;
                                });
                            });
                        res.sources.push_back(std::move(src));
                    }
                }
                res.times.transfer += since(t0);
            }
        });

        // Reductions, in chunk order.
        const int in_wave = std::min(kWave, kChunks - wave);
        for (int k = 0; k < in_wave; ++k) {
            ChunkResult& c = chunks[k];
            for (size_t t = 0; t < m_tex.texels(); ++t) m_tex.next[t] += c.next[t];
            m_running.absorbed += c.absorbed;
            m_running.escaped += c.escaped;
            m_running.absorbed_back += c.absorbed_back;
            m_running.lost += c.lost;
            m_timings.rasterise += c.times.rasterise;
            m_timings.clipping += c.times.clipping;
            m_timings.exchange += c.times.exchange;
            m_timings.transfer += c.times.transfer;
            for (SpecularSource& s : c.sources) sources.push_back(std::move(s));
        }
    }
    m_timings.passes += since(pass_start);
    const auto t0 = Clock::now();
    if (!sources.empty())
        m_running.lost.rounding += gather_specular(scene, m_dirs, m_rot, Nc, mc, sources, m_spec);
    m_timings.specular += since(t0);
}

void Transport::fold_unshot_into_total() {
    for (size_t k = 0; k < m_spec.total.size(); ++k) m_spec.total[k] += m_spec.unshot[k];
}

void Transport::run_cycle(bool last) {
    auto t0 = Clock::now();
    LedgerEntry e;
    e.cycle = cycles_done() + 1;
    if (e.cycle == 1) load_emission(m_running);
    choose_deferred(last);
    for (auto& v : m_spec.unshot_next) v = RgbF(0.0f);
    m_timings.bookkeeping += since(t0);

    // VLF §5: the first few cycles perturb (their light comes from the emitters, small and
    // bright, whose beams leave the holes); the later ones run the true directions only.
    const bool perturb = e.cycle <= m_params.perturb_cycles;
    const int passes = perturb ? int(m_passes.size()) : 1;
    for (int p = 0; p < passes; ++p) run_pass(p, 1.0 / double(passes));
    if (perturb && e.cycle == m_params.perturb_cycles) release_perturbed_geometry();

    // End of cycle: pool, filter, accumulate, swap (VLF §4.1 closing lines, §5 filtering).
    t0 = Clock::now();
    pool_rim_texels(m_pools, m_scene, m_tex, m_tex.next);
    if (m_params.filter_sigma > 0.0) gaussian_filter_next(m_scene, m_tex, m_params.filter_sigma);
    m_timings.filter += since(t0);
    t0 = Clock::now();
    Rgb unshot(0.0), deferred(0.0);
    for (const Face& f : m_scene.faces) {
        const size_t b = m_tex.begin(f.id), n = m_tex.count(f.id);
        for (size_t t = b; t < b + n; ++t) {
            m_tex.total[t] += m_tex.next[t];
            if (m_deferred[f.id]) {
                m_tex.current[t] += m_tex.next[t];
                deferred += m_tex.current[t];
            } else {
                m_tex.current[t] = m_tex.next[t];
                unshot += m_tex.current[t];
            }
            m_tex.next[t] = Rgb(0.0);
        }
    }
    std::swap(m_spec.unshot, m_spec.unshot_next);
    const double area = ray_area(m_params.field.resolution);
    for (int d = 0; d < m_dirs.size(); ++d) {
        const double beam = area * m_dirs.solid_angle(d);
        for (int f : m_spec.faces) {
            const uint64_t b = m_spec.begin(d, f), n = m_spec.count(d, f);
            for (uint64_t k = b; k < b + n; ++k) unshot += Rgb(m_spec.unshot[k]) * beam;
        }
    }
    const double u = to_user_power();
    e.emitted = m_running.emitted * u;
    e.absorbed = m_running.absorbed * u;
    e.escaped = m_running.escaped * u;
    e.absorbed_back = m_running.absorbed_back * u;
    e.lost = m_running.lost * u;
    e.unshot = unshot * u;
    e.deferred = deferred * u;
    m_ledger.push_back(e);
    m_timings.bookkeeping += since(t0);
}

}  // namespace vlf
