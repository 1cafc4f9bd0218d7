// receive_step.cpp — the last two steps of a pass in one direction. The exchange moves the
// power of every ray to its partner fragment X(P) (VLF §4.1 lines 5-8); rays leaving the
// scene are escaped, rays hitting a back face absorbed. Then the receivers take it: rho_d
// of the power goes to P^N over the texels each beam overlaps (§4.1 line 10, §4.2, the
// temporary radiance tile), (1 - rho_d - rho_s) is absorbed, and rho_s is reflected into
// the unshot maps of the enclosing mirror directions (§4.2-4.3, specular.hpp).
#include <algorithm>

#include "vlf/core/error.hpp"
#include "vlf/core/fresnel.hpp"
#include "vlf/scene/glass.hpp"
#include "vlf/scene/sealed_areas.hpp"
#include "vlf/scene/specular_turn.hpp"
#include "vlf/transport/transport_internal.hpp"

namespace vlf::transport_detail {

namespace {

// What a face receives in one direction: the power on its rays, and their bounding box on
// the exchange grid (by whole tile columns).
struct Received {
    Rgb power{0.0};
    int imin, imax, jmin, jmax;
};

Received gather_received(const PassContext& pc, const DirectionGeometry& g, FragRange frags,
                         const std::vector<Rgb>& in) {
    const int m = pc.m;
    Received r{Rgb(0.0), pc.N, -1, pc.N, -1};
    for_fragments(g, frags, [&](const Tile& tile, const Fragment& fr, uint32_t base) {
        for (uint32_t k = 0; k < fr.covered; ++k) r.power += in[base + k];
        r.imin = std::min(r.imin, tile.s * m);
        r.imax = std::max(r.imax, tile.s * m + m - 1);
        r.jmin = std::min(r.jmin, tile.t * m + fr.row_begin);
        r.jmax = std::max(r.jmax, tile.t * m + fr.row_begin + fr.rows - 1);
    });
    return r;
}

// VLF §4.2, the temporary radiance tile onto P^N: rho_d of each beam's power over the
// texels its footprint overlaps, by overlap area. A textured chart reflects with each
// texel's albedo (texel_albedo.hpp); returns the power reflected (or lost), so the rest
// of what the face received is absorbed.
Rgb receive_diffuse(const PassContext& pc, const DirectionGeometry& g, size_t f, FragRange frags,
                    const Rgb& diffuse, const std::vector<Rgb>& in, ChunkResult& res) {
    const Chart& chart = pc.scene.charts[size_t(pc.faces[f].chart)];
    const size_t tb = pc.tex.begin(chart.id);
    const std::vector<Rgb>& albedo = chart.texel_albedo;
    const std::vector<double>& open = chart.texel_open;
    Rgb reflected(0.0);
    for_fragments(g, frags, [&](const Tile&, const Fragment& fr, uint32_t base) {
        for (uint32_t k = 0; k < fr.covered; ++k) {
            const Rgb p = in[base + k];
            if (p.x <= 0 && p.y <= 0 && p.z <= 0) continue;
            const uint32_t ob = g.ov_begin[base + k], oe = g.ov_begin[base + k + 1];
            double rowsum = 0.0;
            for (uint32_t o = ob; o < oe; ++o) rowsum += g.ov[o].area;
            if (rowsum <= 0.0) {
                res.lost.empty_footprint += p * diffuse;
                reflected += p * diffuse;
                continue;
            }
            for (uint32_t o = ob; o < oe; ++o) {
                const Rgb rho = albedo.empty() ? diffuse : albedo[g.ov[o].texel];
                const Rgb q = p * rho * (g.ov[o].area / rowsum);
                reflected += q;
                // A texel sealed behind another face (sealed_areas.hpp) is reached only by
                // grazing beams running into the gap. With no open area to hold it, what
                // it reflects goes to the sealing face's back, one-sided and black, which
                // absorbs it (the gap is narrower than a texel). A texel with an open part
                // keeps what lands.
                if (!open.empty() && open[g.ov[o].texel] < kSealedTexel)
                    res.absorbed_back += q;
                else
                    res.next[tb + g.ov[o].texel] += q;
            }
        }
    });
    return reflected;
}

// The incoming radiance over the window of a specular face's rays in this direction: what
// a specular source gathers from (specular.hpp).
SpecularSource source_window(const PassContext& pc, const PassDirection& pd, size_t f,
                             FragRange frags, const Received& r, const std::vector<Rgb>& in) {
    const DirectionGeometry& g = pd.g;
    SpecularSource src;
    src.face = int(f);
    src.rotation = pc.rotations[pd.d];
    src.resolution = pc.N;
    src.i0 = r.imin;
    src.j0 = r.jmin;
    src.width = r.imax - r.imin + 1;
    src.height = r.jmax - r.jmin + 1;
    src.radiance.assign(size_t(src.width) * src.height, RgbF(0.0f));
    src.covered.assign(size_t(src.width) * src.height, 0);
    for_fragments(g, frags, [&](const Tile& tile, const Fragment& fr, uint32_t base) {
        tile.edge_table(fr).for_each_ray([&](int u, int v, int k) {
            const size_t at =
                size_t(tile.t * pc.m + v - src.j0) * src.width + (tile.s * pc.m + u - src.i0);
            src.radiance[at] = RgbF(in[base + k] / pd.beam);
            src.covered[at] = 1;
        });
    });
    return src;
}

// `power` leaves face `onto`'s front along `outgoing`: src (its window filled) aimed at the
// enclosing directions (on a nearby face of the chart where `onto` has no ray in one,
// chart_specular_targets), one source per face, or booked as lost when no direction can
// carry it.
void aim(const PassContext& pc, const SpecularSource& src, int onto, const Vec3& outgoing,
         const Rgb& power, ChunkResult& res) {
    if (!(power.x > 0 || power.y > 0 || power.z > 0)) return;
    std::array<SpecularTarget, 3> targets;
    const int n = chart_specular_targets(pc.scene, pc.dirs, pc.scene.faces[size_t(onto)], outgoing,
                                         pc.coverage, targets);
    if (n == 0) {
        res.lost.grazing_mirror += power;  // no PSF can carry it
        return;
    }
    for (int j = 0; j < n; ++j) {
        bool done = false;  // an earlier target's face already took it
        for (int i = 0; i < j; ++i) done |= targets[size_t(i)].face == targets[size_t(j)].face;
        if (done) continue;
        SpecularSource one = src;
        one.face = targets[size_t(j)].face;
        one.targets = 0;
        for (int i = j; i < n; ++i)
            if (targets[size_t(i)].face == one.face) {
                one.target_direction[size_t(one.targets)] = targets[size_t(i)].direction;
                one.target_power[size_t(one.targets++)] = power * targets[size_t(i)].weight;
            }
        res.sources.faces.push_back(std::move(one));
    }
}

// The rays of smooth face f in this direction, to its surface's list for the side it faces
// (surface_specular.hpp makes the sources).
void collect_surface_rays(const PassContext& pc, const PassDirection& pd, size_t f, FragRange frags,
                          const std::vector<Rgb>& in, std::vector<std::vector<SurfaceRay>>& out) {
    const PlaneInPsf plane(pc.scene.faces[f], pc.rotations[pd.d], pc.N);
    std::vector<SurfaceRay>& rays = out[size_t(pc.faces[f].surface) * 2 + (plane.n.z > 0 ? 0 : 1)];
    for_fragments(pd.g, frags, [&](const Tile& tile, const Fragment& fr, uint32_t base) {
        tile.edge_table(fr).for_each_ray([&](int u, int v, int k) {
            const int i = tile.s * pc.m + u, j = tile.t * pc.m + v;
            rays.push_back(
                {int(f), i, j, in[base + uint32_t(k)], plane.point(i, j), plane.depth(i, j)});
        });
    });
}

// The same rays' power only, once the gathers keep their plans: written where the plan of
// (direction, surface, side) expects its rays, in collect_surface_rays' order.
void collect_surface_power(const PassContext& pc, const PassDirection& pd, size_t f,
                           FragRange frags, const std::vector<Rgb>& in,
                           std::vector<uint32_t>& count, SurfaceArrivals& arrivals) {
    const int s = pc.faces[f].surface;
    const int side = (pc.rotations[pd.d] * pc.faces[f].normal).z > 0 ? 0 : 1;
    const size_t slot = pc.surfaces.pass_slot(pd.d, s, side);
    ArrivalPower* at = arrivals.power.data() + arrivals.first[slot];
    const uint64_t room = arrivals.first[slot + 1] - arrivals.first[slot];
    uint32_t& n = count[size_t(s) * 2 + size_t(side)];
    // A fragment's slots hold its rays in edge-table order, the order of the plan's rays.
    for_fragments(pd.g, frags, [&](const Tile&, const Fragment& fr, uint32_t base) {
        VLF_CHECK(n + fr.covered <= room);  // the plan was made from these very rays
        for (uint32_t k = 0; k < fr.covered; ++k) at[n + k].rgb = in[base + k];
        n += fr.covered;
    });
}

// VLF §4.2-4.3: rho_s of what a mirror received becomes a specular source: the incoming
// radiance over the window of its rays, gathered later into the unshot maps of the
// directions enclosing the mirrored one (specular.hpp). At glass (docs/propagation.md §13)
// the Fresnel reflectance R of the direction's angle of incidence is reflected so, and
// 1 - R is refracted: gathered into the twin's maps (the other side of the interface)
// around the refracted direction; past the critical angle all of it is reflected. Smooth
// faces are their surfaces' (collect_surface_rays).
void reflect_specular(const PassContext& pc, const PassDirection& pd, size_t f, FragRange frags,
                      const Received& r, const Material& mat, const std::vector<Rgb>& in,
                      ChunkResult& res) {
    const Face& face = pc.scene.faces[f];
    const Mat3& rot = pc.rotations[pd.d];
    const int facing = (rot * face.normal).z > 0 ? 1 : -1;
    const Vec3 incoming = pd.g.psf.omega * double(-facing);  // light travels towards the face
    const Vec3 mirrored = reflect(incoming, face.normal);
    const SpecularSource src = source_window(pc, pd, f, frags, r, in);
    if (!mat.dielectric) {
        aim(pc, src, int(f), mirrored, r.power * mat.specular, res);
        return;
    }
    const double eta = interface_eta(face.inner, mat.ior);
    const double R = fresnel_dielectric(-glm::dot(incoming, face.normal), eta);
    Vec3 refracted;
    if (R < 1.0 && refract(incoming, face.normal, eta, refracted)) {
        aim(pc, src, face.twin, refracted, r.power * (1.0 - R), res);
        aim(pc, src, int(f), mirrored, r.power * R, res);
    } else {
        aim(pc, src, int(f), mirrored, r.power, res);  // total internal reflection
    }
}

}  // namespace

// VLF §4.1 lines 5-8: each ray's power to its partner; what has none is escaped, lost in a
// sealed ray or absorbed by a back face.
void exchange_step(const PassDirection& pd, Scratch& w, ChunkResult& res) {
    const DirectionGeometry& g = pd.g;
    const uint32_t S = g.slots();
    w.in.assign(S, Rgb(0.0));
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
}

// Beer-Lambert inside glass (docs/propagation.md §13): light arriving on the front of an
// absorbing dielectric's inner face crossed the glass from its partner fragment; each ray
// keeps exp(-sigma d) of its power, d the distance between the two planes along the ray.
void attenuate_step(const PassContext& pc, const PassDirection& pd, Scratch& w, ChunkResult& res) {
    const DirectionGeometry& g = pd.g;
    if (!pc.absorbing_glass) return;
    const Scene& scene = pc.scene;
    bool any = false;
    for (uint32_t f : g.faces) any |= pc.faces[f].absorbing_inner;
    if (!any) return;
    // Which face each slot belongs to (the partner's plane).
    w.slot_face.assign(g.slots(), 0);
    for (size_t k = 0; k < g.faces.size(); ++k)
        for_fragments(g, {g.face_begin[k], g.face_begin[k + 1]},
                      [&](const Tile&, const Fragment& fr, uint32_t base) {
                          std::fill_n(w.slot_face.begin() + base, fr.covered, g.faces[k]);
                      });
    const Mat3& rot = pc.rotations[pd.d];
    auto depth = [&](const Face& f, double x, double y) { return plane_depth(f, rot, x, y); };
    for (size_t k = 0; k < g.faces.size(); ++k) {
        if (!pc.faces[g.faces[k]].absorbing_inner) continue;
        const Face& face = scene.faces[g.faces[k]];
        for_fragments(g, {g.face_begin[k], g.face_begin[k + 1]},
                      [&](const Tile& tile, const Fragment& fr, uint32_t base) {
                          tile.edge_table(fr).for_each_ray([&](int u, int v, int j) {
                              const uint32_t slot = base + uint32_t(j);
                              const int32_t p = g.partner[slot];
                              const Rgb arriving = w.in[slot];
                              if (p < 0 || (arriving.x <= 0 && arriving.y <= 0 && arriving.z <= 0))
                                  return;
                              const double x = ray_coord(tile.s * pc.m + u, pc.N);
                              const double y = ray_coord(tile.t * pc.m + v, pc.N);
                              const Face& from = scene.faces[w.slot_face[uint32_t(p)]];
                              const double d = std::abs(depth(face, x, y) - depth(from, x, y));
                              const Rgb kept = arriving * glass_transmittance(scene, face, d);
                              res.absorbed += arriving - kept;
                              w.in[slot] = kept;
                          });
                      });
    }
}

// VLF §4.1 line 10, §4.2-4.3, face by face: what a face receives is absorbed by
// (1 - rho_d - rho_s), rho_d of it goes to P^N, rho_s of it becomes a specular source.
void receive_step(const PassContext& pc, const PassDirection& pd, Scratch& w, ChunkResult& res) {
    const DirectionGeometry& g = pd.g;
    const SmoothSurfaces& surfaces = pc.surfaces;
    w.surface_rays.resize(size_t(surfaces.size()) * 2);
    for (auto& v : w.surface_rays) v.clear();
    w.arrived.assign(size_t(surfaces.size()) * 2, 0);
    SurfaceArrivals* arrivals = pc.surface_arrivals;
    const bool arriving = arrivals != nullptr && arrivals->ready;
    for (size_t k = 0; k < g.faces.size(); ++k) {
        const uint32_t f = g.faces[k];
        const FragRange frags{g.face_begin[k], g.face_begin[k + 1]};
        const Material& mat = pc.scene.materials[size_t(pc.faces[f].material)];
        if (pc.faces[f].surface >= 0) {
            // A smooth surface's rays, lit or not (the source's window is the whole surface).
            if (pc.hand_caustics) {
                // Cycle 1: the lamps' direct light, carried on by the lamp caustics' shot.
                res.handed += gather_received(pc, g, frags, w.in).power;
                for_fragments(g, frags, [&](const Tile&, const Fragment& fr, uint32_t base) {
                    std::fill_n(w.in.begin() + base, fr.covered, Rgb(0.0));
                });
            } else if (!mat.dielectric) {
                res.absorbed +=
                    gather_received(pc, g, frags, w.in).power * (Rgb(1.0) - mat.specular);
            }
            if (arriving)
                collect_surface_power(pc, pd, f, frags, w.in, w.arrived, *arrivals);
            else
                collect_surface_rays(pc, pd, f, frags, w.in, w.surface_rays);
            continue;
        }
        const Received r = gather_received(pc, g, frags, w.in);
        if (r.power.x <= 0 && r.power.y <= 0 && r.power.z <= 0) continue;
        if (pc.hand_caustics && pc.caustic_faces[f]) {
            res.handed += r.power;  // a faceted lens: cycle 1's lamp light goes to the shot
            continue;
        }
        // What is neither reflected diffusely (by the texels' albedo, which a texture
        // varies) nor specularly is absorbed.
        const Rgb reflected =
            mat.is_diffuse() ? receive_diffuse(pc, g, f, frags, mat.diffuse, w.in, res) : Rgb(0.0);
        // Glass absorbs nothing at its faces (R + T = 1); inside, see attenuate_step.
        if (!mat.dielectric) res.absorbed += r.power * (Rgb(1.0) - mat.specular) - reflected;
        if (mat.is_specular()) reflect_specular(pc, pd, f, frags, r, mat, w.in, res);
    }
    // The smooth surfaces' sources, surface by surface, each side (facing +z first). Their
    // plans are kept from cycle to cycle in the pass of the true directions; once the
    // gathers keep theirs too, only the power the rays bring is written down (above).
    if (surfaces.empty()) return;
    if (arriving) {
        for (size_t k = 0; k < w.arrived.size(); ++k) {
            const size_t slot = surfaces.pass_slot(pd.d, int(k / 2), int(k % 2));
            const SurfacePlan& plan = (*pc.surface_plans)[slot];
            VLF_CHECK(plan.built && plan.rays == w.arrived[k]);
            plan_losses(plan, arrivals->power.data() + arrivals->first[slot],
                        res.lost.grazing_mirror);
        }
        return;
    }
    // Each direction's sources in arrays of their own, sized before they are filled: one
    // array per chunk grown as it goes would copy its pixels at every doubling and touch
    // twice their memory.
    SurfaceSources& out = res.sources.surfaces.emplace_back();
    out.frame = surface_frame(pc.rotations[pd.d], pc.N, pd.d);
    const bool keep = pc.surface_plans != nullptr;
    auto incoming = [&](int side) { return pd.g.psf.omega * (side == 0 ? -1.0 : 1.0); };
    if (keep) {  // the plans first, kept in their slots, then the arrays at their size
        size_t targets = 0, pixels = 0, rays_in_all = 0;
        for (int s = 0; s < surfaces.size(); ++s)
            for (int side = 0; side < 2; ++side) {
                const std::vector<SurfaceRay>& rays = w.surface_rays[size_t(s) * 2 + side];
                SurfacePlan& plan = (*pc.surface_plans)[surfaces.pass_slot(pd.d, s, side)];
                if (!plan.built || plan.stripped || plan.rays != rays.size())
                    make_surface_plan(pc.scene, pc.dirs, surfaces, s, incoming(side), rays, plan);
                targets += plan.targets.size(), pixels += plan.pixels.size();
                rays_in_all += rays.size();
            }
        out.targets.reserve(targets);
        out.pixels.reserve(pixels);
        out.power.reserve(rays_in_all);
    }
    for (int s = 0; s < surfaces.size(); ++s)
        for (int side = 0; side < 2; ++side) {
            const std::vector<SurfaceRay>& rays = w.surface_rays[size_t(s) * 2 + side];
            const size_t slot = surfaces.pass_slot(pd.d, s, side);
            SurfacePlan& plan = keep ? (*pc.surface_plans)[slot] : w.surface_plan;
            if (!keep) {
                bool lit = false;
                for (const SurfaceRay& r : rays)
                    lit |= r.power.x > 0 || r.power.y > 0 || r.power.z > 0;
                if (!lit) continue;  // (a kept plan's targets are sent lit or not)
                make_surface_plan(pc.scene, pc.dirs, surfaces, s, incoming(side), rays, plan);
            }
            apply_surface_plan(plan, rays, res.lost.grazing_mirror, out);
            // Where the gathers will keep plans of their own (reading arrivals), this plan's
            // targets are not needed again: only its losses and ray count are.
            if (keep && arrivals != nullptr) plan.strip();
        }
    if (out.empty()) res.sources.surfaces.pop_back();
}

}  // namespace vlf::transport_detail
