// send_step.cpp — the first step of a pass in one direction: the senders load their rays.
// Diffuse faces send their share of their unshot power (VLF §4.4 eq. (3)); specular faces
// add their unshot radiance L_U; L_T of every stored face takes the radiance of its rays
// (§4.1 line 9), on a super-sampled grid through each ray's N x N parent (§5).
#include <algorithm>
#include <cmath>

#include "vlf/core/error.hpp"
#include "vlf/transport/transport_internal.hpp"

namespace vlf::transport_detail {

namespace {

// A sliver with rays on the N x N grid but none on the finer exchange grid: its unshot
// specular light cannot leave; the ledger absorbs it.
void lose_sliver_light(const PassContext& pc, int d, int f, NumericalLoss& lost) {
    const double beam_c = ray_area(pc.Nc) * pc.dirs.solid_angle(d);
    const uint64_t mb = pc.spec.begin(d, f);
    for (uint64_t k = 0; k < pc.spec.count(d, f); ++k)
        lost.subpixel_mirror += Rgb(pc.spec.unshot[mb + k]) * beam_c;
}

// Each ray of face f samples its chart's unshot exitance under its footprint (the weights
// are unbiased at the rim, texel_clip.hpp), into out; sealed rays are left out. Returns
// the sum of the samples, and in `rays` how many rays took one.
Rgb sample_exitance(const PassContext& pc, const DirectionGeometry& g, size_t k,
                    std::vector<Rgb>& out, uint32_t& rays) {
    const std::vector<Rgb>& exitance = pc.senders.exitance;
    const size_t tb = pc.tex.begin(pc.faces[g.faces[k]].chart);
    Rgb sampled(0.0);
    for_fragments(g, {g.face_begin[k], g.face_begin[k + 1]},
                  [&](const Tile&, const Fragment& fr, uint32_t base) {
                      for (uint32_t k = 0; k < fr.covered; ++k) {
                          if (g.partner[base + k] == kSealed) continue;
                          ++rays;
                          Rgb p(0.0);
                          double rowsum = 0.0;
                          for (uint32_t o = g.ov_begin[base + k]; o < g.ov_begin[base + k + 1];
                               ++o) {
                              p += exitance[tb + g.ov[o].texel] * double(g.ov[o].area);
                              rowsum += g.ov[o].area;
                          }
                          if (rowsum > 0.0) p /= rowsum;
                          out[base + k] = p;
                          sampled += p;
                      }
                  });
    return sampled;
}

// VLF §4.4 eq. (3): chart c sends exactly its share of its unshot power U into this
// direction, wd = cos(theta_d) Delta_d / sum_d' cos(theta_d') Delta_d', over the rays of
// all its faces in proportion to the exitance they sample: a face too small to own a ray
// still sends, through its neighbours' beams (docs/charts.md). Sampling exitance rather
// than splitting each texel's power keeps a uniform field uniform at the rim
// (docs/propagation.md §3).
// `present` holds the chart's faces with rays here, as indices into g.faces.
void send_diffuse(const PassContext& pc, const PassDirection& pd, const Chart& c,
                  const std::vector<uint32_t>& present, std::vector<Rgb>& out,
                  NumericalLoss& lost) {
    const DirectionGeometry& g = pd.g;
    // The chart's cosine here, recorded with the charts that have covered rays in this
    // direction (record_charts); a chart with fragments but no covered ray is not among
    // them, and is not in its normaliser: it sends nothing here.
    const std::vector<ChartCosine>& here = pc.charts[pd.d];
    const auto at =
        std::lower_bound(here.begin(), here.end(), uint32_t(c.id),
                         [](const ChartCosine& x, uint32_t id) { return x.chart < id; });
    if (at == here.end() || at->chart != uint32_t(c.id)) return;
    const double nz = at->cosine;
    const double wd = pc.share * nz * pc.dirs.solid_angle(pd.d) / pc.send_norm[c.id];
    uint32_t rays = 0;
    Rgb sampled(0.0);
    for (uint32_t k : present) sampled += sample_exitance(pc, g, k, out, rays);
    const Rgb target = pc.senders.unshot[c.id] * wd;
    Rgb scale(0.0), even(0.0);
    for (int ch = 0; ch < 3; ++ch) {
        if (sampled[ch] > 0.0)
            scale[ch] = target[ch] / sampled[ch];
        else if (rays > 0)
            even[ch] = target[ch] / rays;  // no ray sees the unshot texels
        else
            lost.sealed[ch] += target[ch];  // every ray is shut
    }
    for (uint32_t k : present)
        for_fragments(g, {g.face_begin[k], g.face_begin[k + 1]},
                      [&](const Tile&, const Fragment& fr, uint32_t base) {
                          for (uint32_t r = 0; r < fr.covered; ++r)
                              if (g.partner[base + r] != kSealed)
                                  out[base + r] = out[base + r] * scale + even;
                      });
}

// VLF §4.1 line 9 on the N x N grid: a mirror's rays add its unshot radiance
// (`with_unshot`), and each ray's radiance adds to L_T of face f in `maps`.
void store_rays(const PassContext& pc, const PassDirection& pd, size_t f, FragRange frags,
                RadianceMaps& maps, bool with_unshot, std::vector<Rgb>& out) {
    const DirectionGeometry& g = pd.g;
    const double beam = pd.beam;
    const uint64_t mb = maps.begin(pd.d, int(f));
    VLF_CHECK(maps.count(pd.d, int(f)) == pc.coverage(pd.d, int(f)));
    uint64_t kl = 0;
    for_fragments(g, frags, [&](const Tile&, const Fragment& fr, uint32_t base) {
        for (uint32_t k = 0; k < fr.covered; ++k, ++kl) {
            Rgb& o = out[base + k];
            if (with_unshot) o += Rgb(maps.unshot[mb + kl]) * beam;
            maps.total[mb + kl] += RgbF(o / beam);  // VLF §4.1 line 9
        }
    });
}

// Super-sampling (VLF §5): which N x N parent ray a fine ray (i, j) of a face belongs to,
// as the parent's index among the face's rays on the N x N grid (-1: none).
struct ParentMap {
    int s;              // fine rays per parent, per side
    int i0, j0;         // the face's bounding box on the N x N grid
    int width, height;  // (not positive when the face has no ray there)
    const int32_t* index;
    int32_t operator()(int i, int j) const {
        const int ci = i / s - i0, cj = j / s - j0;
        if (ci < 0 || cj < 0 || ci >= width || cj >= height) return -1;
        return index[size_t(cj) * width + ci];
    }
};

// The parents of a face rasterised on the N x N grid (`coarse`, of tile size mc):
// numbered in face-local order, the order of its radiance maps.
ParentMap map_parents(const FaceRaster& coarse, int Nc, int mc, int s,
                      std::vector<int32_t>& index) {
    int ci0 = Nc, cj0 = Nc, ci1 = -1, cj1 = -1;
    for (const FaceFragment& ff : coarse.fragments) {
        ci0 = std::min(ci0, ff.s * mc);
        ci1 = std::max(ci1, ff.s * mc + mc - 1);
        cj0 = std::min(cj0, ff.t * mc + ff.row_begin);
        cj1 = std::max(cj1, ff.t * mc + ff.row_begin + ff.rows - 1);
    }
    const int cw = ci1 - ci0 + 1, ch = cj1 - cj0 + 1;
    index.assign(size_t(std::max(0, cw)) * std::max(0, ch), -1);
    int32_t k = 0;
    for (const FaceFragment& ff : coarse.fragments)
        coarse.edge_table(ff).for_each_ray([&](int u, int v, int) {
            index[size_t(ff.t * mc + v - cj0) * cw + (ff.s * mc + u - ci0)] = k++;
        });
    return ParentMap{s, ci0, cj0, cw, ch, index.data()};
}

// A super-sampled mirror's unshot power in this direction is sent whole: the scale, per
// channel, from what its fine rays reach through their parents to what L_U holds (light
// that no fine ray can carry is lost).
Rgb unshot_scale(const PassContext& pc, const PassDirection& pd, size_t f, FragRange frags,
                 const RadianceMaps& maps, const ParentMap& parent, uint64_t parents,
                 NumericalLoss& lost) {
    const DirectionGeometry& g = pd.g;
    const uint64_t mb = maps.begin(pd.d, int(f));
    const double beam_c = ray_area(pc.Nc) * pc.dirs.solid_angle(pd.d);
    Rgb unshot(0.0), reach(0.0);
    for (uint64_t k = 0; k < parents; ++k) unshot += Rgb(maps.unshot[mb + k]) * beam_c;
    for_fragments(g, frags, [&](const Tile& tile, const Fragment& fr, uint32_t) {
        tile.edge_table(fr).for_each_ray([&](int u, int v, int) {
            const int32_t pk = parent(tile.s * pc.m + u, tile.t * pc.m + v);
            if (pk >= 0) reach += Rgb(maps.unshot[mb + pk]) * pd.beam;
        });
    });
    Rgb scale(0.0);
    for (int c = 0; c < 3; ++c) {
        if (reach[c] > 0.0)
            scale[c] = unshot[c] / reach[c];
        else
            lost.subpixel_mirror[c] += unshot[c];  // no fine ray carries it
    }
    return scale;
}

// VLF §4.1 line 9 on a super-sampled grid (§5): each fine ray takes L_U of its N x N
// parent ray (`with_unshot`, rescaled by unshot_scale); L_T of a parent is the mean
// radiance of its fine rays on the face.
void store_rays_supersampled(const PassContext& pc, const PassDirection& pd, size_t f,
                             FragRange frags, RadianceMaps& maps, bool with_unshot, Scratch& w,
                             NumericalLoss& lost) {
    const DirectionGeometry& g = pd.g;
    const double beam = pd.beam;
    const uint64_t mb = maps.begin(pd.d, int(f));
    rasterise_face(pc.scene.faces[f], pc.rotations[pd.d], pc.Nc, pc.mc, w.coarse);
    VLF_CHECK(maps.count(pd.d, int(f)) == w.coarse.covered);
    const ParentMap parent = map_parents(w.coarse, pc.Nc, pc.mc, pc.s, w.coarse_index);
    const Rgb scale = with_unshot
                          ? unshot_scale(pc, pd, f, frags, maps, parent, w.coarse.covered, lost)
                          : Rgb(0.0);
    w.parent_sum.assign(w.coarse.covered, Rgb(0.0));
    w.parent_count.assign(w.coarse.covered, 0);
    for_fragments(g, frags, [&](const Tile& tile, const Fragment& fr, uint32_t base) {
        tile.edge_table(fr).for_each_ray([&](int u, int v, int k) {
            const int32_t pk = parent(tile.s * pc.m + u, tile.t * pc.m + v);
            Rgb& o = w.out[base + k];
            if (pk < 0) return;
            if (with_unshot) o += Rgb(maps.unshot[mb + pk]) * beam * scale;
            w.parent_sum[pk] += o / beam;
            ++w.parent_count[pk];
        });
    });
    for (uint64_t k = 0; k < w.coarse.covered; ++k)
        if (w.parent_count[k] > 0)
            maps.total[mb + k] += RgbF(w.parent_sum[k] / double(w.parent_count[k]));
}

}  // namespace

// VLF §4.4 eq. (3) and §4.1 line 9: sending charts load their faces' rays; then face by
// face, slivers without fine rays lose their mirror light, stored faces add L_U and
// record L_T.
void send_step(const PassContext& pc, const PassDirection& pd, Scratch& w, ChunkResult& res) {
    const DirectionGeometry& g = pd.g;
    w.out.assign(g.slots(), Rgb(0.0));
    // The sending charts' faces present here, grouped by chart (a direction holds a few
    // thousand faces of a scene's million).
    w.by_chart.clear();
    for (uint32_t k = 0; k < g.faces.size(); ++k)
        if (pc.senders.face_sends[g.faces[k]])
            w.by_chart.push_back({uint32_t(pc.faces[g.faces[k]].chart), k});
    std::sort(w.by_chart.begin(), w.by_chart.end());
    for (size_t a = 0; a < w.by_chart.size();) {
        size_t b = a;
        w.present.clear();
        while (b < w.by_chart.size() && w.by_chart[b].first == w.by_chart[a].first)
            w.present.push_back(w.by_chart[b++].second);
        send_diffuse(pc, pd, pc.scene.charts[w.by_chart[a].first], w.present, w.out, res.lost);
        a = b;
    }
    if (!pc.true_directions) return;
    // Stored faces only (the other faces keep no directional maps), visited as the faces
    // present here: a direction holds a few of a tessellated ball's thousands of small faces.
    // Each face's rays are its own, so the order of the visits changes no value.
    for (size_t k = 0; k < g.faces.size(); ++k) {
        const int f = int(g.faces[k]);
        const bool spec_store = pc.spec.stores(f);
        if (!spec_store && !pc.other.stores(f)) continue;
        const FragRange frags{g.face_begin[k], g.face_begin[k + 1]};
        RadianceMaps& maps = spec_store ? pc.spec : pc.other;
        if (pc.s == 1)
            store_rays(pc, pd, size_t(f), frags, maps, spec_store, w.out);
        else
            store_rays_supersampled(pc, pd, size_t(f), frags, maps, spec_store, w, res.lost);
    }
    // A mirror with rays on the N x N grid but none on the finer exchange grid (a sliver)
    // cannot send its unshot light. Without super-sampling the exchange grid is the grid the
    // coverage was measured on, so there are none (checked in debug builds).
#ifdef NDEBUG
    if (pc.s == 1) return;
#endif
    size_t k = 0;  // one walk: the mirrors ascending, as the faces present here are
    for (const int f : pc.spec.faces) {
        while (k < g.faces.size() && g.faces[k] < uint32_t(f)) ++k;
        if ((k == g.faces.size() || g.faces[k] != uint32_t(f)) && pc.coverage(pd.d, f) > 0) {
            VLF_CHECK(pc.s > 1);
            lose_sliver_light(pc, pd.d, f, res.lost);
        }
    }
}

// Which charts send diffuse power this pass, how much, and their unshot exitance: every
// chart not deferred (VLF §4.5) that holds unshot power and has a direction to send it in.
Senders find_senders(const Scene& scene, const TextureMaps& tex,
                     const std::vector<uint8_t>& deferred, const std::vector<double>& send_norm) {
    const size_t nc = scene.charts.size();
    Senders out;
    out.face_sends.assign(scene.faces.size(), 0);
    out.unshot.assign(nc, Rgb(0.0));
    out.exitance.assign(tex.texels(), Rgb(0.0));
    for (const Chart& c : scene.charts) {
        if (deferred[c.id]) continue;
        const size_t tb = tex.begin(c.id);
        const Rgb u = TextureMaps::sum(tex.current, tb, tex.count(c.id));
        if (!((u.x > 0 || u.y > 0 || u.z > 0) && send_norm[c.id] > 0)) continue;
        out.unshot[c.id] = u;
        for (int f : c.faces) out.face_sends[f] = 1;
        for (size_t t = 0; t < tex.count(c.id); ++t)
            if (c.texel_area[t] > 0.0) out.exitance[tb + t] = tex.current[tb + t] / c.texel_area[t];
    }
    return out;
}

}  // namespace vlf::transport_detail
