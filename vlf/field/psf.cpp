#include "vlf/field/psf.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "vlf/core/error.hpp"
#include "vlf/core/rotation.hpp"

namespace vlf {

void validate_raster(int resolution, int tile) {
    if (resolution < 1 || resolution > 4096)
        throw ParameterError(
            fmt::format("resolution N = {} is out of range (1 to 4096 rays per side)", resolution));
    if (tile < 1 || tile > resolution)
        throw ParameterError(
            fmt::format("tile size m = {} is out of range (1 to N = {})", tile, resolution));
    if (resolution % tile != 0)
        throw ParameterError(fmt::format(
            "resolution N = {} is not a multiple of the tile size m = {}", resolution, tile));
}

namespace {

// First pixel index whose centre (2i+1)/N - 1 is >= x: the half-open fill rule.
inline int first_centre_at_or_after(double x, int n) {
    const double c = std::ceil((x + 1.0) * 0.5 * n - 0.5);
    if (c <= 0.0) return 0;
    if (c >= n) return n;
    return static_cast<int>(c);
}

struct ScratchTile {
    std::vector<Fragment> fragments;
    std::vector<Span> spans;
    uint32_t covered = 0;
};

}  // namespace

Psf rasterise_psf(const Scene& scene, const Vec3& omega, int direction, int resolution,
                  int tile_size) {
    Psf psf = rasterise_psf(scene, rotation_to_z(omega), direction, resolution, tile_size);
    psf.omega = omega;
    return psf;
}

Psf rasterise_psf(const Scene& scene, const Mat3& rotation, int direction, int resolution,
                  int tile_size, const Coverage* coverage) {
    validate_raster(resolution, tile_size);
    const int N = resolution, m = tile_size, n = N / m;
    Psf psf;
    psf.direction = direction;
    psf.rotation = rotation;
    psf.omega = glm::transpose(rotation) * Vec3(0, 0, 1);
    psf.resolution = N;
    psf.tile_size = m;

    std::vector<ScratchTile> grid(static_cast<size_t>(n) * n);
    FaceRaster fr;
    thread_local TwinRasters twins;
    twins.clear();
    for (const Face& face : scene.faces) {
        if (coverage != nullptr && coverage->measured(face.id) &&
            (*coverage)(direction, face.id) == 0)
            continue;  // count_covered found no ray: rasterise_face would make no fragment
        twins.rasterise(face, rotation, N, m, fr);
        for (const FaceFragment& ff : fr.fragments) {
            ScratchTile& tile = grid[static_cast<size_t>(ff.t) * n + ff.s];
            Fragment frag;
            frag.face = face.id;
            frag.row_begin = ff.row_begin;
            frag.rows = ff.rows;
            frag.span_offset = static_cast<uint32_t>(tile.spans.size());
            frag.ray_offset = tile.covered;
            frag.covered = ff.covered;
            frag.facing = fr.facing;
            tile.spans.insert(tile.spans.end(), fr.spans.begin() + ff.span_offset,
                              fr.spans.begin() + ff.span_offset + ff.rows);
            tile.covered += ff.covered;
            tile.fragments.push_back(frag);
        }
    }

    psf.tile_of.assign(static_cast<size_t>(n) * n, -1);
    for (int t = 0; t < n; ++t) {
        for (int s = 0; s < n; ++s) {
            ScratchTile& st = grid[static_cast<size_t>(t) * n + s];
            if (st.fragments.empty()) continue;
            psf.tile_of[static_cast<size_t>(t) * n + s] = static_cast<int32_t>(psf.tiles.size());
            Tile tile;
            tile.s = static_cast<uint16_t>(s);
            tile.t = static_cast<uint16_t>(t);
            tile.fragments = std::move(st.fragments);
            tile.spans = std::move(st.spans);
            tile.covered = st.covered;
            psf.tiles.push_back(std::move(tile));
        }
    }
    return psf;
}

namespace {

// The face's vertices projected along +z of the rotated frame; their x and y ranges.
void project_face(const Face& face, const Mat3& rotation, std::vector<Vec2>& proj, double& xmin,
                  double& xmax, double& ymin, double& ymax) {
    proj.clear();
    for (const Vec3& v : face.vertices) {
        const Vec3 p = rotation * v;
        proj.emplace_back(p.x, p.y);
        xmin = std::min(xmin, p.x);
        xmax = std::max(xmax, p.x);
        ymin = std::min(ymin, p.y);
        ymax = std::max(ymax, p.y);
    }
}

// Spans per row: the rays [row_i0[j], row_i1[j]) of each row j in [jlo, jhi) whose
// centres the polygon `proj` covers. An edge crosses row y when lo.y <= y < hi.y, with
// (lo, hi) its endpoints in a canonical order, so a shared edge yields the identical x from
// both of its polygons: one takes it as an inclusive left end, the other as an exclusive
// right end, and no ray is lost or counted twice.
void row_spans(const std::vector<Vec2>& proj, int N, int jlo, int jhi, std::vector<int>& row_i0,
               std::vector<int>& row_i1) {
    const size_t nv = proj.size();
    for (int j = jlo; j < jhi; ++j) {
        const double y = (2.0 * j + 1.0) / N - 1.0;
        double xl = 1e300, xr = -1e300;
        int crossings = 0;
        for (size_t k = 0; k < nv; ++k) {
            Vec2 a = proj[k], b = proj[(k + 1) % nv];
            if (b.y < a.y || (b.y == a.y && b.x < a.x)) std::swap(a, b);
            if (!(a.y <= y && y < b.y)) continue;
            const double x = a.x + (y - a.y) * (b.x - a.x) / (b.y - a.y);
            xl = std::min(xl, x);
            xr = std::max(xr, x);
            ++crossings;
        }
        if (crossings < 2) {
            row_i0[j] = row_i1[j] = 0;
            continue;
        }
        row_i0[j] = first_centre_at_or_after(xl, N);
        row_i1[j] = first_centre_at_or_after(xr, N);
    }
}

// The fragment of tile (s, tr): the rows [first, last] within the tile's columns
// [s m, s m + m), its edge table appended to out.
void add_fragment(const std::vector<int>& row_i0, const std::vector<int>& row_i1, int s, int tr,
                  int m, int first, int last, FaceRaster& out) {
    const int c0 = s * m, c1 = c0 + m;
    FaceFragment frag;
    frag.s = static_cast<uint16_t>(s);
    frag.t = static_cast<uint16_t>(tr);
    frag.row_begin = static_cast<uint16_t>(first - tr * m);
    frag.rows = static_cast<uint16_t>(last - first + 1);
    frag.span_offset = static_cast<uint32_t>(out.spans.size());
    uint32_t covered = 0;
    for (int j = first; j <= last; ++j) {
        const int b = std::max(row_i0[j], c0), e = std::min(row_i1[j], c1);
        Span span;
        if (b < e) {
            span.begin = static_cast<uint16_t>(b - c0);
            span.end = static_cast<uint16_t>(e - c0);
            covered += static_cast<uint32_t>(e - b);
        }
        out.spans.push_back(span);
    }
    frag.covered = covered;
    out.covered += covered;
    out.fragments.push_back(frag);
}

// Cuts the rows [r0, r1) of tile row tr into fragments: one per tile the polygon touches,
// left to right.
void cut_tile_row(const std::vector<int>& row_i0, const std::vector<int>& row_i1, int n, int m,
                  int tr, int r0, int r1, FaceRaster& out) {
    int smin = n, smax = -1;
    for (int j = r0; j < r1; ++j) {
        if (row_i1[j] <= row_i0[j]) continue;
        smin = std::min(smin, row_i0[j] / m);
        smax = std::max(smax, (row_i1[j] - 1) / m);
    }
    for (int s = smin; s <= smax; ++s) {
        const int c0 = s * m, c1 = c0 + m;
        int first = -1, last = -1;
        for (int j = r0; j < r1; ++j) {
            if (std::max(row_i0[j], c0) < std::min(row_i1[j], c1)) {
                if (first < 0) first = j;
                last = j;
            }
        }
        if (first >= 0) add_fragment(row_i0, row_i1, s, tr, m, first, last, out);
    }
}

// The face's rows in this thread's t_row_i0/t_row_i1: rows [jlo, jhi) of an N x N grid
// with their spans (row_spans); false when the face covers no ray centre for certain (no
// row's centre line or no column's centre line crosses its projection).
thread_local std::vector<int> t_row_i0, t_row_i1;
bool face_rows(const Face& face, const Mat3& rotation, int N, int& jlo, int& jhi) {
    thread_local std::vector<Vec2> proj;
    t_row_i0.resize(N);
    t_row_i1.resize(N);
    double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
    project_face(face, rotation, proj, xmin, xmax, ymin, ymax);
    jlo = first_centre_at_or_after(ymin, N);
    jhi = first_centre_at_or_after(ymax, N);  // exclusive
    if (jlo >= jhi) return false;
    // No column's centre near [xmin, xmax): every row's span would be empty (a facet smaller
    // than a ray, as most of a tessellated ball's are, usually covers no centre). The margin
    // covers an edge crossing that rounds an ulp past its end points.
    constexpr double kMargin = 1e-9;
    if (first_centre_at_or_after(xmin - kMargin, N) >= first_centre_at_or_after(xmax + kMargin, N))
        return false;
    row_spans(proj, N, jlo, jhi, t_row_i0, t_row_i1);
    return true;
}

}  // namespace

void rasterise_face(const Face& face, const Mat3& rotation, int resolution, int tile_size,
                    FaceRaster& out) {
    const int N = resolution, m = tile_size, n = N / m;
    out.fragments.clear();
    out.spans.clear();
    out.covered = 0;
    out.facing = 0;
    const Vec3 nr = rotation * face.normal;
    if (std::abs(nr.z) < kEdgeOnCosine) return;  // edge-on: covers no ray
    out.facing = nr.z > 0 ? 1 : -1;

    int jlo = 0, jhi = 0;
    if (!face_rows(face, rotation, N, jlo, jhi)) return;
    // Cut the rows into tiles, row-major.
    for (int tr = jlo / m; tr <= (jhi - 1) / m; ++tr)
        cut_tile_row(t_row_i0, t_row_i1, n, m, tr, std::max(jlo, tr * m), std::min(jhi, tr * m + m),
                     out);
}

uint32_t count_covered(const Face& face, const Mat3& rotation, int resolution) {
    const int N = resolution;
    if (std::abs((rotation * face.normal).z) < kEdgeOnCosine) return 0;  // as rasterise_face
    int jlo = 0, jhi = 0;
    if (!face_rows(face, rotation, N, jlo, jhi)) return 0;
    // Every covered ray of a row lies in one of the tiles rasterise_face cuts it into.
    uint32_t covered = 0;
    for (int j = jlo; j < jhi; ++j)
        if (t_row_i1[j] > t_row_i0[j]) covered += uint32_t(t_row_i1[j] - t_row_i0[j]);
    return covered;
}

void TwinRasters::rasterise(const Face& face, const Mat3& rotation, int resolution, int tile_size,
                            FaceRaster& out) {
    const int twin = face.twin;
    if (twin >= 0 && twin < face.id && size_t(twin) < m_kept_at.size() &&
        m_kept_at[size_t(twin)] >= 0) {
        const FaceRaster& kept = m_kept[size_t(m_kept_at[size_t(twin)])];
        const double z = (rotation * face.normal).z;
        // Each face's own normal decides edge-on (the two normals are computed apart).
        if (std::abs(z) >= kEdgeOnCosine) {
            out.fragments.assign(kept.fragments.begin(), kept.fragments.end());
            out.spans.assign(kept.spans.begin(), kept.spans.end());
            out.covered = kept.covered;
            out.facing = z > 0 ? 1 : -1;
            return;
        }
    }
    rasterise_face(face, rotation, resolution, tile_size, out);
    if (twin <= face.id || out.facing == 0) return;
    if (m_kept_at.size() <= size_t(twin)) m_kept_at.resize(size_t(twin) + 1, -1);
    if (m_count == m_kept.size()) m_kept.emplace_back();
    FaceRaster& keep = m_kept[m_count];
    keep.fragments.assign(out.fragments.begin(), out.fragments.end());
    keep.spans.assign(out.spans.begin(), out.spans.end());
    keep.covered = out.covered;
    keep.facing = out.facing;
    m_kept_at[size_t(face.id)] = int32_t(m_count++);
    m_kept_faces.push_back(face.id);
}

void TwinRasters::clear() {
    for (int32_t f : m_kept_faces) m_kept_at[size_t(f)] = -1;
    m_kept_faces.clear();
    m_count = 0;
}

PsfMemory memory_of(const Psf& psf) {
    PsfMemory mem;
    mem.tiles = sizeof(Psf) + psf.tile_of.capacity() * sizeof(int32_t) +
                psf.tiles.capacity() * sizeof(Tile);
    for (const Tile& t : psf.tiles) {
        mem.fragments += t.fragments.capacity() * sizeof(Fragment);
        mem.edge_tables += t.spans.capacity() * sizeof(Span);
    }
    return mem;
}

}  // namespace vlf
