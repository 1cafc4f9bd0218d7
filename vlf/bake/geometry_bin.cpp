// geometry_bin.cpp — faces and charts as binary arrays (geometry_bin.hpp).
//
// Layout (little-endian, no padding):
//   "VLFGEO02"                         8 bytes (01: without the vertex normals at the end)
//   u64 faces F, charts C, vertices V, texels T
//   faces:  i32 object[F], material[F], twin[F], chart[F]; u32 vertex_begin[F+1];
//           u64 inner_edges[F]; f64 normal[3F], plane_offset[F], area[F]; f64 vertex[3V]
//          (a dielectric's face is inner, Face::inner, when its twin comes before it)
//   charts: i32 material[C]; u8 planar[C]; f64 normal[3C], area[C]; u32 face_begin[C+1];
//           i32 face[F]; f64 origin[3C], axis_u[3C], axis_v[3C], size[C];
//           i32 width[C], height[C]; f64 texel_area[T]
//   vertex normals (Face::vertex_normals): u64 normals S; u8 smooth[F] (1: the face has one
//           per vertex); f64 normal[3S], the smooth faces' in face order
#include "vlf/bake/geometry_bin.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <type_traits>
#include <vector>

#include "vlf/bake/binary_reader.hpp"
#include "vlf/core/error.hpp"
#include "vlf/scene/charts.hpp"

namespace vlf {

namespace {

constexpr char kGeometryMagic[8] = {'V', 'L', 'F', 'G', 'E', 'O', '0', '2'};
constexpr int kMaxTexelsPerSide = 65536;

static_assert(sizeof(double) == 8 && std::numeric_limits<double>::is_iec559);

class Writer {
  public:
    explicit Writer(size_t bytes) : m_bytes(bytes) {}
    template <class T>
    void put(const T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        VLF_CHECK(m_at + sizeof(T) <= m_bytes.size());
        std::memcpy(m_bytes.data() + m_at, &v, sizeof(T));
        m_at += sizeof(T);
    }
    void put_vec(const Vec3& v) {
        for (int c = 0; c < 3; ++c) put(v[c]);
    }
    const std::vector<char>& bytes() const {
        VLF_CHECK(m_at == m_bytes.size());
        return m_bytes;
    }

  private:
    std::vector<char> m_bytes;
    size_t m_at = 0;
};

// The file's size from its counts (the layout above), S vertex normals.
uint64_t file_bytes(uint64_t F, uint64_t C, uint64_t V, uint64_t T, uint64_t S) {
    return 40 + F * 72 + 4 + V * 24 + C * 129 + 4 + T * 8 + 8 + F + S * 24;
}

uint64_t normal_count(const Scene& s) {
    uint64_t n = 0;
    for (const Face& f : s.faces) n += f.vertex_normals.size();
    return n;
}

void write_normals(Writer& w, const Scene& s) {
    w.put(normal_count(s));
    for (const Face& f : s.faces) w.put(uint8_t(f.vertex_normals.empty() ? 0 : 1));
    for (const Face& f : s.faces)
        for (const Vec3& n : f.vertex_normals) w.put_vec(n);
}

void write_faces(Writer& w, const Scene& s) {
    for (const Face& f : s.faces) w.put(int32_t(f.object));
    for (const Face& f : s.faces) w.put(int32_t(f.material));
    for (const Face& f : s.faces) w.put(int32_t(f.twin));
    for (const Face& f : s.faces) w.put(int32_t(f.chart));
    uint32_t at = 0;
    w.put(at);
    for (const Face& f : s.faces) w.put(at += uint32_t(f.vertices.size()));
    for (const Face& f : s.faces) w.put(f.inner_edges);
    for (const Face& f : s.faces) w.put_vec(f.normal);
    for (const Face& f : s.faces) w.put(f.plane_offset);
    for (const Face& f : s.faces) w.put(f.area);
    for (const Face& f : s.faces)
        for (const Vec3& v : f.vertices) w.put_vec(v);
}

void write_charts(Writer& w, const Scene& s) {
    for (const Chart& c : s.charts) w.put(int32_t(c.material));
    for (const Chart& c : s.charts) w.put(uint8_t(c.planar ? 1 : 0));
    for (const Chart& c : s.charts) w.put_vec(c.normal);
    for (const Chart& c : s.charts) w.put(c.area);
    uint32_t at = 0;
    w.put(at);
    for (const Chart& c : s.charts) w.put(at += uint32_t(c.faces.size()));
    for (const Chart& c : s.charts)
        for (int f : c.faces) w.put(int32_t(f));
    for (const Chart& c : s.charts) w.put_vec(c.texels.origin);
    for (const Chart& c : s.charts) w.put_vec(c.texels.axis_u);
    for (const Chart& c : s.charts) w.put_vec(c.texels.axis_v);
    for (const Chart& c : s.charts) w.put(c.texels.size);
    for (const Chart& c : s.charts) w.put(int32_t(c.texels.width));
    for (const Chart& c : s.charts) w.put(int32_t(c.texels.height));
    for (const Chart& c : s.charts)
        for (double a : c.texel_area) w.put(a);
}

// Offsets [F+1] (or [C+1]) from 0, non-decreasing by at least `min_step`, ending at `total`.
std::vector<uint32_t> read_offsets(BinaryReader& r, const char* what, size_t n, uint64_t total,
                                   uint32_t min_step) {
    std::vector<uint32_t> o(n + 1);
    for (size_t k = 0; k <= n; ++k) o[k] = r.get<uint32_t>(what);
    if (o[0] != 0) r.fail(fmt::format("{} starts at {}, not 0", what, o[0]));
    for (size_t k = 0; k < n; ++k)
        if (o[k + 1] < o[k] + min_step)
            r.fail(fmt::format("{} of {}: {} entries (at least {})", what, k,
                               int64_t(o[k + 1]) - int64_t(o[k]), min_step));
    if (o[n] != total) r.fail(fmt::format("{} ends at {}, the header says {}", what, o[n], total));
    return o;
}

void read_faces(BinaryReader& r, Scene& s, size_t F, size_t C, uint64_t V) {
    const int32_t nf = int32_t(F), nc = int32_t(C);
    s.faces.assign(F, Face());
    for (size_t k = 0; k < F; ++k) s.faces[k].id = int(k);
    const int32_t objects = int32_t(s.objects.size()), materials = int32_t(s.materials.size());
    for (Face& f : s.faces) f.object = r.index("face object", f.id, 0, objects - 1);
    for (Face& f : s.faces) f.material = r.index("face material", f.id, 0, materials - 1);
    for (Face& f : s.faces) f.twin = r.index("face twin", f.id, -1, nf - 1);
    for (Face& f : s.faces) f.chart = r.index("face chart", f.id, 0, nc - 1);
    const std::vector<uint32_t> vb = read_offsets(r, "face vertex offsets", F, V, 3);
    for (Face& f : s.faces) {
        f.inner_edges = r.get<uint64_t>("face inner edges");
        const size_t n = vb[f.id + 1] - vb[f.id];
        if (n < 64 && (f.inner_edges >> n) != 0)
            r.fail(
                fmt::format("face inner edges of {} name an edge past its {} vertices", f.id, n));
    }
    for (Face& f : s.faces) f.normal = r.vec("face normal", f.id);
    for (Face& f : s.faces) f.plane_offset = r.finite("face plane offset", f.id);
    for (Face& f : s.faces) f.area = r.finite("face area", f.id);
    for (Face& f : s.faces) {
        f.vertices.resize(vb[f.id + 1] - vb[f.id]);
        for (Vec3& v : f.vertices) v = r.vec("face vertex", f.id);
    }
    for (const Face& f : s.faces)
        if (f.twin >= 0 && (f.twin == f.id || s.faces[f.twin].twin != f.id))
            r.fail(fmt::format("face twin of {}: face {} does not name it back", f.id, f.twin));
    // A dielectric's faces come in pairs, the outer face first (scene_loader.cpp).
    for (Face& f : s.faces) {
        if (!s.materials[size_t(f.material)].dielectric) continue;
        if (f.twin < 0) r.fail(fmt::format("face twin of {}: a dielectric face has none", f.id));
        f.inner = f.twin < f.id;
    }
}

// Vertex normals: one per vertex of a smooth face, unit, on its front side; a twin's are
// its face's negated, in reverse order (the loader makes them so).
void read_normals(BinaryReader& r, Scene& s, uint64_t S) {
    if (r.get<uint64_t>("the vertex normal count") != S)
        r.fail("the vertex normal count does not match the file's size");
    uint64_t listed = 0;
    for (Face& f : s.faces) {
        const uint8_t smooth = r.get<uint8_t>("face smooth");
        if (smooth > 1)
            r.fail(fmt::format("face smooth of {} is {} (must be 0 or 1)", f.id, smooth));
        if (smooth) f.vertex_normals.resize(f.vertices.size());
        listed += f.vertex_normals.size();
    }
    if (listed != S)
        r.fail(
            fmt::format("the smooth faces have {} vertices, the file holds {} normals", listed, S));
    for (Face& f : s.faces)
        for (Vec3& n : f.vertex_normals) {
            n = r.vec("face vertex normal", f.id);
            if (!(std::abs(glm::length(n) - 1.0) <= 1e-9))
                r.fail(fmt::format("face vertex normal of {} is not unit", f.id));
            if (!(glm::dot(n, f.normal) > 0))
                r.fail(
                    fmt::format("face vertex normal of {} points to the back of the face", f.id));
        }
    for (const Face& f : s.faces) {
        if (f.twin < 0) continue;
        const std::vector<Vec3>& a = f.vertex_normals;
        const std::vector<Vec3>& b = s.faces[size_t(f.twin)].vertex_normals;
        bool mirrored = a.size() == b.size();
        for (size_t k = 0; mirrored && k < a.size(); ++k) mirrored = a[k] == -b[a.size() - 1 - k];
        if (!mirrored)
            r.fail(fmt::format("face vertex normals of {}: its twin {} does not reverse them", f.id,
                               f.twin));
    }
}

void read_charts(BinaryReader& r, Scene& s, size_t C, uint64_t T) {
    const size_t F = s.faces.size();
    s.charts.assign(C, Chart());
    for (size_t k = 0; k < C; ++k) s.charts[k].id = int(k);
    const int32_t materials = int32_t(s.materials.size());
    for (Chart& c : s.charts) c.material = r.index("chart material", c.id, 0, materials - 1);
    for (Chart& c : s.charts) c.planar = r.get<uint8_t>("chart planar") != 0;
    for (Chart& c : s.charts) c.normal = r.vec("chart normal", c.id);
    for (Chart& c : s.charts) c.area = r.finite("chart area", c.id);
    const std::vector<uint32_t> fb = read_offsets(r, "chart face offsets", C, F, 1);
    std::vector<uint8_t> listed(F, 0);
    for (Chart& c : s.charts)
        for (uint32_t k = fb[c.id]; k < fb[c.id + 1]; ++k) {
            const int32_t f = r.index("chart face", c.id, 0, int32_t(F) - 1);
            if (s.faces[f].chart != c.id || listed[f]++)
                r.fail(fmt::format("chart face of {}: face {} names chart {}{}", c.id, f,
                                   s.faces[f].chart, listed[f] > 1 ? " and is listed twice" : ""));
            c.faces.push_back(f);
        }
    for (Chart& c : s.charts) finish_chart(c, s.faces);
    for (Chart& c : s.charts) c.texels.origin = r.vec("chart texel origin", c.id);
    for (Chart& c : s.charts) c.texels.axis_u = r.vec("chart texel axis_u", c.id);
    for (Chart& c : s.charts) c.texels.axis_v = r.vec("chart texel axis_v", c.id);
    for (Chart& c : s.charts) {
        c.texels.size = r.finite("chart texel size", c.id);
        if (!(c.texels.size > 0))
            r.fail(fmt::format("chart texel size of {} is not positive", c.id));
    }
    for (Chart& c : s.charts) c.texels.width = r.index("chart width", c.id, 1, kMaxTexelsPerSide);
    for (Chart& c : s.charts) c.texels.height = r.index("chart height", c.id, 1, kMaxTexelsPerSide);
    uint64_t texels = 0;
    for (const Chart& c : s.charts) texels += uint64_t(c.texels.width) * uint64_t(c.texels.height);
    if (texels != T)
        r.fail(fmt::format("the charts' grids hold {} texels, the header says {}", texels, T));
    for (Chart& c : s.charts) {
        c.texel_area.resize(size_t(c.texels.width) * c.texels.height);
        for (double& a : c.texel_area) {
            a = r.finite("chart texel area", c.id);
            if (a < 0) r.fail(fmt::format("chart texel area of {} is negative", c.id));
        }
    }
}

}  // namespace

void write_geometry(const std::string& file, const Scene& scene) {
    uint64_t vertices = 0, texels = 0;
    for (const Face& f : scene.faces) vertices += f.vertices.size();
    for (const Chart& c : scene.charts) texels += c.texel_area.size();
    Writer w(
        file_bytes(scene.faces.size(), scene.charts.size(), vertices, texels, normal_count(scene)));
    for (char c : kGeometryMagic) w.put(c);
    VLF_CHECK(vertices < (uint64_t(1) << 32) && scene.faces.size() < (size_t(1) << 31));
    w.put(uint64_t(scene.faces.size()));
    w.put(uint64_t(scene.charts.size()));
    w.put(vertices);
    w.put(texels);
    write_faces(w, scene);
    write_charts(w, scene);
    write_normals(w, scene);
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(w.bytes().data(), static_cast<std::streamsize>(w.bytes().size()));
    out.close();
    if (!out) throw Error(fmt::format("{}: cannot be written", file));
}

void read_geometry(const std::string& file, Scene& scene) {
    BinaryReader r(file);
    char magic[8];
    for (char& c : magic) c = r.get<char>("the header");
    if (std::memcmp(magic, kGeometryMagic, 6) != 0) r.fail("not a VLF geometry file (bad magic)");
    if (std::memcmp(magic, kGeometryMagic, 8) != 0)
        r.fail(fmt::format("geometry format {} is not supported (this build reads {})",
                           std::string(magic + 6, 2), std::string(kGeometryMagic + 6, 2)));
    const uint64_t F = r.get<uint64_t>("the header"), C = r.get<uint64_t>("the header");
    const uint64_t V = r.get<uint64_t>("the header"), T = r.get<uint64_t>("the header");
    // The counts fix the file's size: a header that does not match it is refused before
    // anything is allocated.
    if (F == 0 || F >= (uint64_t(1) << 31) || C == 0 || C > F || V < 3 * F ||
        V >= (uint64_t(1) << 32) || T < C || T > (uint64_t(1) << 40))
        r.fail(fmt::format("implausible counts: {} faces, {} charts, {} vertices, {} texels", F, C,
                           V, T));
    // The vertex normals at the end are what the rest leaves, S x 24 bytes: at most V.
    const uint64_t flat = file_bytes(F, C, V, T, 0);
    const uint64_t S = r.size() > flat ? (r.size() - flat) / 24 : 0;
    const uint64_t expect = file_bytes(F, C, V, T, S);
    if (expect != r.size() || S > V)
        r.fail(fmt::format(
            "{} bytes, {} faces, {} charts, {} vertices and {} texels take {} and 24 per vertex "
            "normal (at most {}){}",
            r.size(), F, C, V, T, flat, V, r.size() < flat ? " (truncated)" : ""));
    read_faces(r, scene, size_t(F), size_t(C), V);
    read_charts(r, scene, size_t(C), T);
    read_normals(r, scene, S);
    r.expect_end();
}

}  // namespace vlf
