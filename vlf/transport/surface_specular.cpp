#include "vlf/transport/surface_specular.hpp"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "vlf/core/error.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/field/psf.hpp"
#include "vlf/scene/specular_turn.hpp"

namespace vlf {

namespace {

// A surface's point is on the sheet a source pixel saw when their depths along the source
// direction agree within this many pixel widths (a ball's near and far sides differ by its
// chord, more than this except within a pixel or two of the silhouette).
constexpr double kSheetPixels = 4.0;

std::array<float, 9> to_floats(const Mat3& m) {
    std::array<float, 9> r{};
    for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) r[size_t(row * 3 + col)] = float(m[col][row]);
    return r;
}

// r * x and r^T * x for a row-major float rotation.
Vec3 rotate(const std::array<float, 9>& r, const Vec3& x) {
    return {r[0] * x.x + r[1] * x.y + r[2] * x.z, r[3] * x.x + r[4] * x.y + r[5] * x.z,
            r[6] * x.x + r[7] * x.y + r[8] * x.z};
}
Vec3 rotate_back(const std::array<float, 9>& r, const Vec3& x) {
    return {r[0] * x.x + r[3] * x.y + r[6] * x.z, r[1] * x.x + r[4] * x.y + r[7] * x.z,
            r[2] * x.x + r[5] * x.y + r[8] * x.z};
}

struct Entry {
    int direction, surface, sense;
    uint32_t ray;  // in the surface's rays
    double part;
};

// A layer's window: per pixel, whether the layer has a ray there.
struct Window {
    int i0 = 0, j0 = 0, width = 0, height = 0;
    std::vector<uint8_t> ray;
    bool covers(int i, int j) const {
        const int a = i - i0, b = j - j0;
        return a >= 0 && b >= 0 && a < width && b < height &&
               ray[size_t(b) * size_t(width) + size_t(a)] != 0;
    }
};

// What of a ray's power a branch of its turn carries: rho_s at a mirror, the Fresnel part
// (`part`, already in the entry) at glass.
Rgb power_factor(const Scene& scene, int face) {
    const Material& mat = scene.material_of(scene.faces[size_t(face)]);
    return mat.dielectric ? Rgb(1.0) : mat.specular;
}

// Orders entries by (direction, surface, sense, ray), as a stable sort by that would: they are
// made in ray order, so a stable counting sort by (direction, surface, sense) is enough.
void sort_entries(const SmoothSurfaces& surfaces, std::vector<Entry>& entries) {
    auto key = [&](const Entry& e) {
        return (size_t(e.direction) * size_t(surfaces.size()) + size_t(e.surface)) * 2 +
               (e.sense > 0 ? 1 : 0);
    };
    thread_local std::vector<uint32_t> count;  // per key; zero between calls
    thread_local std::vector<size_t> used;     // the keys met
    thread_local std::vector<Entry> sorted;
    count.resize(size_t(surfaces.directions) * size_t(surfaces.size()) * 2, 0u);
    used.clear();
    uint32_t last = 0;
    for (const Entry& e : entries) {
        VLF_CHECK(e.ray >= last);  // made in ray order
        last = e.ray;
        if (count[key(e)]++ == 0) used.push_back(key(e));
    }
    // The keys met, ascending: sorted where they are few, else read off the counts in order
    // (a ball's reflections reach every direction: thousands of keys of a few thousand).
    if (used.size() * 16 < count.size()) {
        std::sort(used.begin(), used.end());
    } else {
        used.clear();
        for (size_t k = 0; k < count.size(); ++k)
            if (count[k] != 0) used.push_back(k);
    }
    uint32_t at = 0;
    for (size_t k : used) at += std::exchange(count[k], at);  // counts -> first places
    sorted.resize(entries.size());
    for (const Entry& e : entries) sorted[count[key(e)]++] = e;
    for (size_t k : used) count[k] = 0;
    entries.swap(sorted);
}

// One layer of a surface's rays (indices into `rays`): at most one ray per pixel (a torus
// seen edge-on has two sheets facing the same way; each makes its own targets).
void plan_layer(const Scene& scene, const DirectionSet& dirs, const SmoothSurfaces& surfaces,
                int surface, const Vec3& incoming, const std::vector<SurfaceRay>& rays,
                const std::vector<uint32_t>& layer, SurfacePlan& plan) {
    Window w;
    int imin = std::numeric_limits<int>::max(), imax = -1;
    int jmin = std::numeric_limits<int>::max(), jmax = -1;
    for (uint32_t k : layer) {
        imin = std::min(imin, rays[k].i), imax = std::max(imax, rays[k].i);
        jmin = std::min(jmin, rays[k].j), jmax = std::max(jmax, rays[k].j);
    }
    w.i0 = imin, w.j0 = jmin, w.width = imax - imin + 1, w.height = jmax - jmin + 1;
    w.ray.assign(size_t(w.width) * size_t(w.height), 0);
    std::vector<Entry> entries;
    // Ray `at` leaves `onto`'s front along `out` with the part `frac` of what it received:
    // to the three enclosing directions the surface has rays in. Neighbouring rays turn
    // into neighbouring directions: each branch starts its search at the last one's triangle.
    int hints[2] = {-1, -1};  // the reflections', the refractions'
    auto branch = [&](int onto, const Vec3& dir, double frac, uint32_t at, int& hint) {
        const EnclosingTriangle tri = dirs.enclosing(dir, hint);
        double sum = 0.0;
        for (int i = 0; i < 3; ++i)
            if (tri.weight[i] > 0.0 && surfaces.carried(onto, tri.index[i], tri.sense[i]) > 0)
                sum += tri.weight[i];
        if (sum <= 0.0) {
            plan.lost.push_back({at, power_factor(scene, rays[at].face) * frac});  // no PSF
            return;
        }
        for (int i = 0; i < 3; ++i) {
            if (!(tri.weight[i] > 0.0) || surfaces.carried(onto, tri.index[i], tri.sense[i]) == 0)
                continue;
            entries.push_back({tri.index[i], onto, tri.sense[i], at, frac * tri.weight[i] / sum});
        }
    };
    for (uint32_t k : layer) {
        const SurfaceRay& r = rays[k];
        w.ray[size_t(r.j - w.j0) * size_t(w.width) + size_t(r.i - w.i0)] = 1;
        const Face& face = scene.faces[size_t(r.face)];
        const SpecularTurn t = specular_turn(scene, face, r.point, incoming);
        if (!scene.material_of(face).dielectric) {
            branch(surface, t.reflected, 1.0, k, hints[0]);
            continue;
        }
        if (t.refracts)
            branch(surfaces.of_face[size_t(face.twin)], t.refracted, 1.0 - t.R, k, hints[1]);
        branch(surface, t.reflected, t.R, k, hints[0]);
    }
    sort_entries(surfaces, entries);
    std::vector<SurfacePlan::Pixel>& pixels = plan.pixels;
    constexpr uint32_t kUnknown = ~0u;  // (a 5 x 5 mask has 25 bits)
    std::vector<uint32_t> arounds(rays.size(), kUnknown);
    for (size_t e = 0; e < entries.size();) {
        const Entry& first = entries[e];
        SurfacePlan::Target t{first.surface, first.direction, first.sense, uint32_t(pixels.size()),
                              0};
        for (; e < entries.size() && entries[e].direction == first.direction &&
               entries[e].surface == first.surface && entries[e].sense == first.sense;
             ++e) {
            if (pixels.size() > t.begin && pixels.back().ray == entries[e].ray) {
                pixels.back().part += entries[e].part;  // the same line twice (near the equator)
                continue;
            }
            const SurfaceRay& r = rays[entries[e].ray];
            uint32_t& around = arounds[entries[e].ray];  // once per ray, for its targets
            if (around == kUnknown) {
                around = 0;
                for (int b = -2; b <= 2; ++b)
                    for (int a = -2; a <= 2; ++a)
                        if (w.covers(r.i + a, r.j + b)) around |= 1u << ((b + 2) * 5 + (a + 2));
            }
            pixels.push_back({entries[e].ray, around, entries[e].part});
        }
        t.end = uint32_t(pixels.size());
        plan.targets.push_back(t);
    }
}

}  // namespace

SurfaceFrame surface_frame(const Mat3& rotation, int N, int direction) {
    VLF_CHECK(N <= std::numeric_limits<int16_t>::max());  // (SurfacePixel's i, j)
    return {to_floats(rotation), N, direction};
}

void make_surface_plan(const Scene& scene, const DirectionSet& dirs, const SmoothSurfaces& surfaces,
                       int surface, const Vec3& incoming, const std::vector<SurfaceRay>& rays,
                       SurfacePlan& plan) {
    plan = SurfacePlan{};
    plan.rays = uint32_t(rays.size());
    plan.built = true;
    if (rays.empty()) return;
    // Layers: each ray goes to the first layer whose pixel it finds free.
    int imin = std::numeric_limits<int>::max(), imax = -1;
    int jmin = std::numeric_limits<int>::max(), jmax = -1;
    for (const SurfaceRay& r : rays) {
        imin = std::min(imin, r.i), imax = std::max(imax, r.i);
        jmin = std::min(jmin, r.j), jmax = std::max(jmax, r.j);
    }
    const size_t w = size_t(imax - imin + 1), n = w * size_t(jmax - jmin + 1);
    std::vector<uint8_t> layers_at(n, 0);  // layers already holding each pixel
    std::vector<std::vector<uint32_t>> layers;
    for (uint32_t k = 0; k < rays.size(); ++k) {
        uint8_t& at = layers_at[size_t(rays[k].j - jmin) * w + size_t(rays[k].i - imin)];
        if (at == layers.size()) layers.emplace_back();
        layers[at++].push_back(k);
    }
    for (const auto& layer : layers)
        plan_layer(scene, dirs, surfaces, surface, incoming, rays, layer, plan);
}

void apply_surface_plan(const SurfacePlan& plan, const std::vector<SurfaceRay>& rays, Rgb& lost,
                        SurfaceSources& out) {
    VLF_CHECK(plan.built && plan.rays == rays.size());
    for (const auto& [ray, part] : plan.lost) lost += rays[ray].power * part;
    const uint32_t first = uint32_t(out.power.size());
    for (const SurfaceRay& r : rays) out.power.push_back(r.power);
    for (const SurfacePlan::Target& pt : plan.targets) {
        const uint32_t group = uint32_t(pt.surface) * 2u + (pt.sense > 0 ? 1u : 0u);
        out.targets.push_back({group, pt.direction, uint32_t(out.pixels.size())});
        for (uint32_t k = pt.begin; k < pt.end; ++k) {
            const SurfacePlan::Pixel& p = plan.pixels[k];
            const SurfaceRay& r = rays[p.ray];
            out.pixels.push_back({int16_t(r.i), int16_t(r.j), r.face, float(r.depth), p.around,
                                  p.part, first + p.ray});
        }
    }
}

bool index_arrivals(const std::vector<SurfacePlan>& plans, SurfaceArrivals& arrivals) {
    arrivals.ready = false;
    arrivals.first.assign(plans.size() + 1, 0);
    for (size_t k = 0; k < plans.size(); ++k)
        arrivals.first[k + 1] = arrivals.first[k] + plans[k].rays;
    if (arrivals.first.back() > std::numeric_limits<uint32_t>::max()) {
        arrivals = SurfaceArrivals{};
        return false;
    }
    arrivals.power.assign(arrivals.first.back(), ArrivalPower{Rgb(0.0)});
    return true;
}

void power_to_arrivals(const SmoothSurfaces& surfaces, std::vector<SurfaceSources>& sources,
                       SurfaceArrivals& arrivals) {
    for (SurfaceSources& from : sources) {
        const int d = from.frame.direction;
        const uint64_t b = arrivals.first[surfaces.pass_slot(d, 0, 0)];
        VLF_CHECK(from.power.size() == arrivals.first[surfaces.pass_slot(d + 1, 0, 0)] - b);
        for (size_t k = 0; k < from.power.size(); ++k) arrivals.power[b + k].rgb = from.power[k];
        std::vector<Rgb>().swap(from.power);
    }
}

void plan_losses(const SurfacePlan& plan, const ArrivalPower* power, Rgb& lost) {
    for (const auto& [ray, part] : plan.lost) lost += power[ray].rgb * part;
}

int64_t SurfacePlan::bytes() const {
    return int64_t(targets.capacity() * sizeof(Target) + pixels.capacity() * sizeof(Pixel) +
                   lost.capacity() * sizeof(lost[0]));
}

int64_t SurfaceRayCache::bytes() const {
    int64_t b = int64_t(rays.size() * sizeof(SurfaceRays) + built.size());
    for (const SurfaceRays& r : rays)
        b += int64_t(r.rays.capacity() * sizeof(SurfaceRays::Ray) +
                     (r.head.capacity() + r.next.capacity()) * sizeof(int32_t));
    return b;
}

int64_t SurfaceRayCache::plan_bytes() const {
    int64_t b = 0;
    for (const SurfaceGatherPlan& g : gathers)
        b += int64_t(g.groups.capacity() * sizeof(SurfaceGatherPlan::Group) +
                     (g.pixel_begin.capacity() + g.entry_begin.capacity()) * sizeof(uint32_t) +
                     g.pixels.capacity() * sizeof(GatherPixel) +
                     g.entries.capacity() * sizeof(GatherEntry));
    return b;
}

namespace {

// A target of the first gather: its source and how many pixels it has (they follow the
// previous target's in its Segment).
struct Ref {
    uint32_t source;  // in the pass's sources
    uint32_t n;       // pixels
};

// The targets a block of sources sends to one direction: per group (target surface and
// sense) in source order, with their pixels in the same order.
struct Segment {
    std::vector<uint32_t> ref_begin, pixel_begin;  // per group, and one past the end
    std::vector<Ref> refs;
    std::vector<SurfacePixel> pixels;
};

// The first gather's input laid out by target direction, block of sources by block: per
// held direction its segments, in block order. The layout is made a block at a time and
// each block's sources are released as soon as it is made, and a direction's segments are
// released as soon as its gather is done: the allocator gives the memory freed at each
// step to the next (sources to segments, segments to the gathers' kept plans), so the
// three are never all resident and few fresh pages are touched.
struct ByTarget {
    std::vector<std::vector<Segment>> segments;  // per direction, per block that sends to it
};
constexpr size_t kBlock = 64;  // sources per block

// Moves the targets of the held directions out of `sources` (in source order) into the
// layout by target direction, releasing each block's targets and pixels (their frames and
// power stay).
ByTarget by_target(const SmoothSurfaces& surfaces, int directions, const RadianceMaps& maps,
                   std::vector<SurfaceSources>& sources) {
    ByTarget out;
    const size_t G = size_t(surfaces.size()) * 2;  // groups: (target surface, sense)
    out.segments.resize(size_t(directions));
    auto end_of = [](const SurfaceSources& s, size_t k) {
        return k + 1 < s.targets.size() ? s.targets[k + 1].begin : uint32_t(s.pixels.size());
    };
    std::vector<uint32_t> refs(size_t(directions) * G), pixels(size_t(directions) * G);
    for (size_t b0 = 0; b0 < sources.size(); b0 += kBlock) {
        const size_t b1 = std::min(sources.size(), b0 + kBlock);
        std::fill(refs.begin(), refs.end(), 0u);
        std::fill(pixels.begin(), pixels.end(), 0u);
        for (size_t s = b0; s < b1; ++s)
            for (size_t k = 0; k < sources[s].targets.size(); ++k) {
                const SurfaceTarget& t = sources[s].targets[k];
                if (!maps.holds(t.direction)) continue;
                VLF_CHECK(t.group < G);
                const size_t slot = size_t(t.direction) * G + t.group;
                ++refs[slot];
                pixels[slot] += end_of(sources[s], k) - t.begin;
            }
        // Two halves of the directions at once, so both threads allocate segments where the
        // passes' threads allocated the sources (with glibc, each thread in an arena of its
        // own) and the memory the block frees is reused on both.
        parallel_for(0, 2, [&](long half) {
            const int d0 = int(half * directions / 2), d1 = int((half + 1) * directions / 2);
            std::vector<Segment*> seg(size_t(d1 - d0), nullptr);
            // Where each (direction, group)'s next ref and pixel go in its segment.
            std::vector<uint32_t> ref_at(size_t(d1 - d0) * G), pixel_at(size_t(d1 - d0) * G);
            for (int d = d0; d < d1; ++d) {
                const size_t at = size_t(d) * G, local = size_t(d - d0) * G;
                uint32_t nr = 0, np = 0;
                for (size_t g = 0; g < G; ++g) {
                    ref_at[local + g] = nr, pixel_at[local + g] = np;
                    nr += refs[at + g], np += pixels[at + g];
                }
                if (nr == 0) continue;
                Segment& sg = out.segments[size_t(d)].emplace_back();
                sg.ref_begin.assign(ref_at.begin() + int64_t(local),
                                    ref_at.begin() + int64_t(local + G));
                sg.ref_begin.push_back(nr);
                sg.pixel_begin.assign(pixel_at.begin() + int64_t(local),
                                      pixel_at.begin() + int64_t(local + G));
                sg.pixel_begin.push_back(np);
                sg.refs.resize(nr);
                sg.pixels.resize(np);
                seg[size_t(d - d0)] = &sg;
            }
            for (size_t s = b0; s < b1; ++s) {
                const SurfaceSources& from = sources[s];
                for (size_t k = 0; k < from.targets.size(); ++k) {
                    const SurfaceTarget& t = from.targets[k];
                    if (t.direction < d0 || t.direction >= d1 || !maps.holds(t.direction)) continue;
                    const size_t slot = size_t(t.direction - d0) * G + t.group;
                    Segment& sg = *seg[size_t(t.direction - d0)];
                    const uint32_t n = end_of(from, k) - t.begin;
                    sg.refs[ref_at[slot]++] = {uint32_t(s), n};
                    std::copy_n(from.pixels.data() + t.begin, n, sg.pixels.data() + pixel_at[slot]);
                    pixel_at[slot] += n;
                }
            }
        });
        for (size_t s = b0; s < b1; ++s) {
            std::vector<SurfaceTarget>().swap(sources[s].targets);
            std::vector<SurfacePixel>().swap(sources[s].pixels);
        }
    }
    return out;
}

// Whether the surface covers source pixel (i, j), known from a sending pixel p within one
// pixel of it (its 5 x 5 neighbourhood holds (i, j)'s 3 x 3).
bool covered_near(const SurfacePixel& p, int i, int j) {
    return (p.around >> ((j - p.j + 2) * 5 + (i - p.i + 2))) & 1u;
}

// What a target ray (`ray`) landing on source pixel (i, j) at depth z gathers, as entries
// (ray, sending pixel, weight): a sending pixel's value when the ray is on its sheet; where
// the ray falls just outside the surface's pixels, the mean over the covered 8-neighbours
// (sending ones on the same sheet bring their value, the others nothing).
void sample(const SurfacePixel* px, uint32_t n, int i, int j, double z, double tol, int32_t ray,
            std::vector<GatherEntry>& out) {
    const SurfacePixel* near = nullptr;
    for (uint32_t e = 0; e < n; ++e) {
        if (px[e].i == i && px[e].j == j) {
            if (std::abs(double(px[e].depth) - z) <= tol) out.push_back({ray, e, 1.0f});
            return;
        }
        if (std::abs(px[e].i - i) <= 1 && std::abs(px[e].j - j) <= 1) near = &px[e];
    }
    if (near == nullptr || covered_near(*near, i, j)) return;
    int count = 0;
    for (int b = j - 1; b <= j + 1; ++b)
        for (int a = i - 1; a <= i + 1; ++a)
            count += (a != i || b != j) && covered_near(*near, a, b);
    if (count == 0) return;
    for (uint32_t e = 0; e < n; ++e)
        if (std::abs(px[e].i - i) <= 1 && std::abs(px[e].j - j) <= 1 &&
            std::abs(double(px[e].depth) - z) <= tol)
            out.push_back({ray, e, 1.0f / float(count)});
}

// The ray of `rays` nearest to scene point x: rings of pixels around x's pixel on the target
// grid, out to one ring past the first that holds a ray, else all of them. `points`: each
// ray's surface_ray_point.
size_t nearest_ray(const SurfaceRays& rays, const std::vector<Vec3>& points, const Mat3& rot, int N,
                   const Vec3& x) {
    const Vec3 q = rot * x;
    const int ci = int(std::floor((q.x + 1.0) * 0.5 * N)) - rays.i0;
    const int cj = int(std::floor((q.y + 1.0) * 0.5 * N)) - rays.j0;
    size_t best = 0;
    double dist = std::numeric_limits<double>::infinity();
    auto visit = [&](int a, int b) {
        if (a < 0 || b < 0 || a >= rays.width || b >= rays.height) return;
        for (int32_t r = rays.head[size_t(b) * size_t(rays.width) + size_t(a)]; r >= 0;
             r = rays.next[size_t(r)]) {
            const Vec3 e = points[size_t(r)] - x;
            const double d2 = glm::dot(e, e);
            if (d2 < dist) dist = d2, best = size_t(r);
        }
    };
    const int reach = std::max(rays.width, rays.height) + std::max(std::abs(ci), std::abs(cj));
    int stop = reach;
    for (int ring = 0; ring <= stop; ++ring) {
        for (int a = ci - ring; a <= ci + ring; ++a) {
            visit(a, cj - ring);
            if (ring > 0) visit(a, cj + ring);
        }
        for (int b = cj - ring + 1; b <= cj + ring - 1; ++b) {
            visit(ci - ring, b);
            visit(ci + ring, b);
        }
        if (dist < std::numeric_limits<double>::infinity() && stop == reach) stop = ring + 1;
    }
    return best;
}

// The backward mapping of target t (VLF §4.3): the rays of `rays` whose centres lie in the
// sending pixels' footprints, each with the sending pixels whose values it takes. Appends to
// `out`.
void plan_gather(const Scene& scene, const SurfaceFrame& src, uint32_t n, const SurfacePixel* px,
                 const Mat3& rot, int N, const SurfaceRays& rays, const std::vector<Vec3>& points,
                 std::vector<GatherEntry>& out) {
    // The source frame to the target's: A = rot * R_src^T (its first two rows: the target
    // grid's x and y), once per target rather than two rotations per footprint corner.
    const std::array<float, 9>& r = src.rotation;
    double A[2][3];
    for (int row = 0; row < 2; ++row)
        for (int k = 0; k < 3; ++k)
            A[row][k] = rot[0][row] * r[size_t(k * 3)] + rot[1][row] * r[size_t(k * 3 + 1)] +
                        rot[2][row] * r[size_t(k * 3 + 2)];
    const double h = 2.0 / src.resolution;  // a source pixel's width
    double lo_i = 1e300, hi_i = -1e300, lo_j = 1e300, hi_j = -1e300;
    bool rim = false;  // a sending pixel beside one the surface does not cover
    int32_t last_face = -1;
    double c[2][3] = {};  // per target axis: the grid coordinate's x, y and constant terms
    bool steep = false;
    for (uint32_t e = 0; e < n; ++e) {
        const SurfacePixel& p = px[e];
        rim |= (p.around & 0x739c0u) != 0x739c0u;  // its 3 x 3 (bits 6-8, 11-13, 16-18)
        if (p.face != last_face) {
            // On face f's plane z = (offset - n.x x - n.y y) / n.z (n: its normal in the
            // source frame), so a target coordinate A.(x, y, z) is affine in x and y.
            last_face = p.face;
            const Face& f = scene.faces[size_t(p.face)];
            const Vec3 fn = rotate(r, f.normal);
            steep = std::abs(fn.z) < 1e-3;
            for (int row = 0; row < 2; ++row) {
                c[row][0] = A[row][0] - A[row][2] * fn.x / fn.z;
                c[row][1] = A[row][1] - A[row][2] * fn.y / fn.z;
                c[row][2] = A[row][2] * f.plane_offset / fn.z;
            }
        }
        // The pixel's corners (a steep face's pixel: its centre), as the target grid sees
        // them: an affine map's extremes over the pixel's square are at its corners.
        const double x0 = h * (p.i + (steep ? 0.5 : 0.0)) - 1.0;
        const double y0 = h * (p.j + (steep ? 0.5 : 0.0)) - 1.0;
        const double w = steep ? 0.0 : h;
        double lo[2], hi[2];
        for (int row = 0; row < 2; ++row) {
            const double base = c[row][0] * x0 + c[row][1] * y0 + c[row][2];
            const double dx = c[row][0] * w, dy = c[row][1] * w;
            lo[row] = (base + std::min(0.0, dx) + std::min(0.0, dy) + 1.0) * 0.5 * N;
            hi[row] = (base + std::max(0.0, dx) + std::max(0.0, dy) + 1.0) * 0.5 * N;
        }
        lo_i = std::min(lo_i, lo[0]), hi_i = std::max(hi_i, hi[0]);
        lo_j = std::min(lo_j, lo[1]), hi_j = std::max(hi_j, hi[1]);
    }
    // Rays whose centres lie in the footprints' box; a pixel wider where the neighbour rule
    // (sample) can reach a rim pixel from outside the surface.
    const int margin = rim ? 1 : 0;
    const int i0 = std::max(rays.i0, int(std::ceil(lo_i - 0.5)) - margin);
    const int i1 = std::min(rays.i0 + rays.width - 1, int(std::floor(hi_i - 0.5)) + margin);
    const int j0 = std::max(rays.j0, int(std::ceil(lo_j - 0.5)) - margin);
    const int j1 = std::min(rays.j0 + rays.height - 1, int(std::floor(hi_j - 0.5)) + margin);
    const double tol = kSheetPixels * 2.0 / src.resolution;
    for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i)
            for (int32_t r =
                     rays.head[size_t(j - rays.j0) * size_t(rays.width) + size_t(i - rays.i0)];
                 r >= 0; r = rays.next[size_t(r)]) {
                const Vec3 q = rotate(src.rotation, points[size_t(r)]);
                const int si = int(std::floor((q.x + 1.0) * 0.5 * src.resolution));
                const int sj = int(std::floor((q.y + 1.0) * 0.5 * src.resolution));
                sample(px, n, si, sj, q.z, tol, r, out);
            }
}

// Deposits one target into acc (per ray of `rays`, radiance units) by its plan: pixels
// [p, p + n) with their powers `power(e)`, entries [e0, e1). Each entry's ray takes its
// pixel's value (power times part) times its weight, and the pattern is scaled so the target
// receives exactly its power (`factor` times the pixels' values), channel by channel
// (DESIGN §5). Where no entry takes a pixel's value it goes to the ray nearest its point.
template <class Power>
void apply_target(const GatherPixel* p, uint32_t n, Power&& power, const GatherEntry* e0,
                  const GatherEntry* e1, const Rgb& factor, double beam, std::vector<Rgb>& acc) {
    if (n == 1) {  // most targets: the pattern is the entries' weights
        const Rgb value = power(0) * p[0].part;
        const Rgb target = value * factor;
        if (target.x <= 0 && target.y <= 0 && target.z <= 0) return;
        double weights = 0.0;
        for (const GatherEntry* g = e0; g != e1; ++g) weights += double(g->weight);
        if (weights <= 0.0) {
            for (int c = 0; c < 3; ++c)
                if (target[c] > 0.0) acc[size_t(p[0].nearest)][c] += target[c] / beam;
            return;
        }
        // One pass for the three channels; a channel with nothing to send scales by 0 (its
        // sums take +0, which changes no value: they start at +0 and only grow; powers and
        // weights are finite and not negative).
        Rgb scale(0.0);
        for (int c = 0; c < 3; ++c)
            if (target[c] > 0.0) scale[c] = target[c] / (weights * beam);
        for (const GatherEntry* g = e0; g != e1; ++g)
            acc[size_t(g->ray)] += double(g->weight) * scale;
        return;
    }
    constexpr uint32_t kSmall = 16;
    Rgb small[kSmall];
    std::vector<Rgb> large;
    Rgb* value = small;
    if (n > kSmall) large.resize(n), value = large.data();
    Rgb sum(0.0);
    for (uint32_t e = 0; e < n; ++e) {
        value[e] = power(e) * p[e].part;
        sum += value[e];
    }
    const Rgb target = sum * factor;
    if (target.x <= 0 && target.y <= 0 && target.z <= 0) return;
    Rgb total(0.0);
    for (const GatherEntry* g = e0; g != e1; ++g) total += value[g->pixel] * double(g->weight);
    Rgb scale(0.0);  // as above: 0 where a channel sends nothing through the entries
    for (int c = 0; c < 3; ++c)
        if (target[c] > 0.0 && total[c] > 0.0) scale[c] = target[c] / (total[c] * beam);
    if (scale.x > 0.0 || scale.y > 0.0 || scale.z > 0.0)
        for (const GatherEntry* g = e0; g != e1; ++g)
            acc[size_t(g->ray)] += value[g->pixel] * double(g->weight) * scale;
    for (int c = 0; c < 3; ++c) {
        if (target[c] <= 0.0 || total[c] > 0.0) continue;
        // No target ray's centre lies in the footprints of the pixels that send this
        // channel, on their sheet (the footprints are smaller than the target's rays there):
        // each pixel's share goes to the target ray nearest its point. Energy stays exact.
        for (uint32_t e = 0; e < n; ++e) {
            if (!(value[e][c] > 0.0)) continue;
            // (A pixel that entries take has no nearest ray; its value reaches here only
            // where value times weight underflows: its first entry's ray takes it.)
            int32_t at = p[e].nearest;
            for (const GatherEntry* g = e0; at < 0 && g != e1; ++g)
                if (g->pixel == e) at = g->ray;
            acc[size_t(at)][c] += target[c] * (value[e][c] / sum[c]) / beam;
        }
    }
}

// Plans the gather of a target (its n pixels px from source frame src): its pixels (with
// where their power is: `first` plus their rays' index) and entries, appended to `plan`.
// `points`: the scene point of each of `rays` (surface_ray_point), made once per group of a
// direction for all the group's targets.
void plan_target(const Scene& scene, const SurfaceFrame& src, uint32_t n, const SurfacePixel* px,
                 const Mat3& rot, int N, const SurfaceRays& rays, const std::vector<Vec3>& points,
                 uint64_t first, SurfaceGatherPlan& plan) {
    const size_t e0 = plan.entries.size();
    plan.pixel_begin.push_back(uint32_t(plan.pixels.size()));
    plan.entry_begin.push_back(uint32_t(e0));
    plan_gather(scene, src, n, px, rot, N, rays, points, plan.entries);
    constexpr uint32_t kSmall = 64;
    uint8_t small[kSmall] = {};
    std::vector<uint8_t> large;
    uint8_t* taken = small;
    if (n > kSmall) large.assign(n, 0), taken = large.data();
    for (size_t e = e0; e < plan.entries.size(); ++e) taken[plan.entries[e].pixel] = 1;
    for (uint32_t e = 0; e < n; ++e) {
        const SurfacePixel& q = px[e];
        int32_t nearest = -1;
        if (!taken[e]) {
            const Vec3 x = rotate_back(
                src.rotation, Vec3(2.0 * (q.i + 0.5) / src.resolution - 1.0,
                                   2.0 * (q.j + 0.5) / src.resolution - 1.0, double(q.depth)));
            nearest = int32_t(nearest_ray(rays, points, rot, N, x));
        }
        plan.pixels.push_back({uint32_t(first + q.ray), nearest, q.part});
    }
}

// Deposits acc (per ray of `rays`) into direction d's unshot maps; adds what single precision
// rounds away to `rounding`.
void deposit(const std::vector<Rgb>& acc, const SurfaceRays& rays, int d, double beam,
             RadianceMaps& maps, Rgb& rounding) {
    for (size_t k = 0; k < rays.rays.size(); ++k) {
        if (acc[k].x == 0.0 && acc[k].y == 0.0 && acc[k].z == 0.0) continue;
        const SurfaceRays::Ray& ray = rays.rays[k];
        const uint64_t at = maps.begin(d, ray.face) + ray.k;
        const RgbF before = maps.unshot_next[at];
        maps.unshot_next[at] += RgbF(acc[k]);
        rounding += (acc[k] - (Rgb(maps.unshot_next[at]) - Rgb(before))) * beam;
    }
}

// The rays of `surface` in direction d along `sense` (built the first time they are asked
// for; only d's task asks for them).
SurfaceRays& rays_of(const Scene& scene, const DirectionSet& dirs, const SmoothSurfaces& surfaces,
                     const RadianceMaps& maps, const Mat3& rot, int N, int m, int surface, int d,
                     int sense, TwinRasters& twins, SurfaceRayCache& cache) {
    const size_t slot = surfaces.slot(surface, d, sense);
    SurfaceRays& rays = cache.rays[slot];
    if (!cache.built[slot]) {
        surface_rays(scene, surfaces, maps, surface, d, rot, dirs.direction(d) * double(sense), N,
                     m, twins, rays);
        cache.built[slot] = 1;
    }
    return rays;
}

// Runs direction d's gathers by `plan`; `power(target, e)` is the power of the target's
// pixel e, `ahead(target, e)` where it lies, fetched a few targets early: the
// powers come from every direction's rays, a cache miss each without it. (The prefetch is
// made here: in a function of its own the compiler finds no effect and drops the call.)
template <class Power, class Ahead>
Rgb run_plan(const Scene& scene, const SmoothSurfaces& surfaces, const SurfaceGatherPlan& plan,
             const std::vector<SurfaceRays*>& group_rays, int d, double beam, Power&& power,
             Ahead&& ahead, RadianceMaps& maps) {
    constexpr uint32_t kAhead = 40;  // targets (most have one pixel)
    const uint32_t targets = uint32_t(plan.pixel_begin.size() - 1);
    Rgb rounding(0.0);
    std::vector<Rgb> acc;
    uint32_t t = 0;
    for (size_t g = 0; g < plan.groups.size(); ++g) {
        const SurfaceGatherPlan::Group& group = plan.groups[g];
        const SurfaceRays& rays = *group_rays[g];
        const Rgb factor = power_factor(scene, surfaces.faces[size_t(group.surface)][0]);
        acc.assign(rays.rays.size(), Rgb(0.0));
        for (; t < group.end; ++t) {
            if (const uint32_t ta = t + kAhead; ta < targets)
                for (uint32_t e = plan.pixel_begin[ta]; e < plan.pixel_begin[ta + 1]; ++e) {
                    const char* at = static_cast<const char*>(ahead(ta, e - plan.pixel_begin[ta]));
                    __builtin_prefetch(at);
                    // A source's power may straddle two cache lines (an arrival's never does).
                    if ((reinterpret_cast<uintptr_t>(at) & 63u) > 64u - sizeof(Rgb))
                        __builtin_prefetch(at + sizeof(Rgb) - 1);
                }
            const uint32_t p0 = plan.pixel_begin[t];
            apply_target(
                plan.pixels.data() + p0, plan.pixel_begin[t + 1] - p0,
                [&](uint32_t e) { return power(t, e); }, plan.entries.data() + plan.entry_begin[t],
                plan.entries.data() + plan.entry_begin[t + 1], factor, beam, acc);
        }
        deposit(acc, rays, d, beam, maps, rounding);
    }
    return rounding;
}

}  // namespace

void SurfaceGatherPlan::clear() {
    groups.clear();
    pixel_begin.clear();
    entry_begin.clear();
    pixels.clear();
    entries.clear();
}

std::vector<Rgb> gather_surface_sources(const Scene& scene, const DirectionSet& dirs,
                                        const std::vector<Mat3>& rotations, int N, int m,
                                        const SmoothSurfaces& surfaces,
                                        std::vector<SurfaceSources>& sources,
                                        SurfaceArrivals* arrivals, SurfaceRayCache& cache,
                                        RadianceMaps& maps) {
    const size_t slots = size_t(surfaces.size()) * size_t(dirs.size()) * 2;
    if (cache.rays.size() != slots) {
        cache.rays.assign(slots, SurfaceRays{});
        cache.built.assign(slots, 0);
        cache.gathers.assign(size_t(dirs.size()), SurfaceGatherPlan{});
    }
    const bool keep = arrivals != nullptr;
    // Where no source brings any power (cycle 1 when the lamp caustics' shot carries the
    // lamps' light on smooth surfaces, lamp_caustics.hpp), the plans are made but not run:
    // every target would send nothing (apply_target), after a read of each pixel's power
    // at random. The first power that can send (apply_target's test) ends the search.
    auto lit = [](const Rgb& p) { return p.x > 0.0 || p.y > 0.0 || p.z > 0.0; };
    const bool any_power =
        keep ? std::any_of(arrivals->power.begin(), arrivals->power.end(),
                           [&](const ArrivalPower& a) { return lit(a.rgb); })
             : std::any_of(sources.begin(), sources.end(), [&](const SurfaceSources& s) {
                   return std::any_of(s.power.begin(), s.power.end(), lit);
               });
    ByTarget in = by_target(surfaces, dirs.size(), maps, sources);
    const size_t G = size_t(surfaces.size()) * 2;
    const double a = ray_area(N);
    std::vector<Rgb> rounding(size_t(maps.last - maps.first), Rgb(0.0));
    // Each thread builds its plans in a scratch plan that keeps its memory from direction to
    // direction; a kept plan is copied out at its exact size (growing each one in place
    // would copy it and fault in fresh pages at every doubling).
    tbb::enumerable_thread_specific<SurfaceGatherPlan> scratch;
    tbb::enumerable_thread_specific<std::vector<Vec3>> scratch_points;
    tbb::enumerable_thread_specific<TwinRasters> scratch_twins;
    parallel_for(maps.first, maps.last, [&](long d) {
        std::vector<Segment>& segments = in.segments[size_t(d)];
        TwinRasters& twins = scratch_twins.local();  // this direction's rasters
        twins.clear();
        if (keep) cache.gathers[size_t(d)].clear();
        SurfaceGatherPlan& plan = scratch.local();
        plan.clear();
        if (segments.empty()) return;
        const Mat3& rot = rotations[size_t(d)];
        std::vector<SurfaceRays*> group_rays;
        std::vector<uint32_t> source;                        // per target: its source
        std::vector<Vec3>& points = scratch_points.local();  // the group's rays' points
        for (size_t g = 0; g < G; ++g) {
            uint32_t n = 0;  // the group's targets
            for (const Segment& sg : segments) n += sg.ref_begin[g + 1] - sg.ref_begin[g];
            if (n == 0) continue;
            const int surface = int(g / 2), sense = (g & 1u) ? 1 : -1;
            const SurfaceRays& rays = *group_rays.emplace_back(&rays_of(
                scene, dirs, surfaces, maps, rot, N, m, surface, int(d), sense, twins, cache));
            points.resize(rays.rays.size());
            for (size_t k = 0; k < rays.rays.size(); ++k)
                points[k] = surface_ray_point(scene, rot, N, rays.rays[k]);
            plan.groups.push_back({surface, sense, uint32_t(source.size() + n)});
            for (const Segment& sg : segments) {
                const SurfacePixel* px = sg.pixels.data() + sg.pixel_begin[g];
                for (uint32_t r = sg.ref_begin[g]; r < sg.ref_begin[g + 1]; ++r) {
                    const Ref& ref = sg.refs[r];
                    const SurfaceFrame& src = sources[ref.source].frame;
                    const uint64_t first =
                        keep ? arrivals->first[surfaces.pass_slot(src.direction, 0, 0)] : 0;
                    plan_target(scene, src, ref.n, px, rot, N, rays, points, first, plan);
                    px += ref.n;
                    source.push_back(ref.source);
                }
            }
        }
        // This direction's share of the layout is not read again.
        std::vector<Segment>().swap(segments);
        plan.pixel_begin.push_back(uint32_t(plan.pixels.size()));
        plan.entry_begin.push_back(uint32_t(plan.entries.size()));
        // The power of a target's pixel: in the arrivals (kept plans), else in its source's.
        auto at = [&](uint32_t t, uint32_t e) -> const Rgb* {
            const uint32_t k = plan.pixels[plan.pixel_begin[t] + e].arrival;
            return keep ? &arrivals->power[k].rgb : &sources[source[t]].power[k];
        };
        if (any_power)
            rounding[size_t(d - maps.first)] = run_plan(
                scene, surfaces, plan, group_rays, int(d), a * dirs.solid_angle(int(d)),
                [&](uint32_t t, uint32_t e) { return *at(t, e); },
                [&](uint32_t t, uint32_t e) -> const void* { return at(t, e); }, maps);
        if (keep) cache.gathers[size_t(d)] = plan;  // (a copy holds just the sizes)
    });
    if (keep) arrivals->ready = true;
    return rounding;
}

std::vector<Rgb> gather_surface_arrivals(const Scene& scene, const DirectionSet& dirs, int N,
                                         const SmoothSurfaces& surfaces,
                                         const SurfaceArrivals& arrivals, SurfaceRayCache& cache,
                                         RadianceMaps& maps) {
    VLF_CHECK(arrivals.ready);
    const double a = ray_area(N);
    std::vector<Rgb> rounding(size_t(maps.last - maps.first), Rgb(0.0));
    parallel_for(maps.first, maps.last, [&](long d) {
        const SurfaceGatherPlan& plan = cache.gathers[size_t(d)];
        if (plan.groups.empty()) return;
        std::vector<SurfaceRays*> group_rays;
        for (const SurfaceGatherPlan::Group& g : plan.groups) {
            const size_t slot = surfaces.slot(g.surface, int(d), g.sense);
            group_rays.push_back(&cache.rays[slot]);
        }
        rounding[size_t(d - maps.first)] = run_plan(
            scene, surfaces, plan, group_rays, int(d), a * dirs.solid_angle(int(d)),
            [&](uint32_t t, uint32_t e) {
                return arrivals.power[plan.pixels[plan.pixel_begin[t] + e].arrival].rgb;
            },
            [&](uint32_t t, uint32_t e) -> const void* {
                return &arrivals.power[plan.pixels[plan.pixel_begin[t] + e].arrival];
            },
            maps);
    });
    return rounding;
}

}  // namespace vlf
