// test_util.hpp — small helpers shared by the tests: scenes built in code, file paths.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "vlf/bake/bake.hpp"
#include "vlf/render/image_io.hpp"
#include "vlf/scene/scene.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/transport/parameters.hpp"
#include "vlf/transport/transport.hpp"

namespace vlf::test {

// A scratch directory under the test temp dir, removed with its files at the end.
struct TempDir {
    std::filesystem::path path;
    explicit TempDir(const std::string& name) {
        path = std::filesystem::path(::testing::TempDir()) /
               ("vlf_" + name + "_" + std::to_string(::getpid()));
        std::filesystem::create_directories(path);
    }
    ~TempDir() { std::filesystem::remove_all(path); }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    // Writes `text` (bytes as they are) to `file` in the directory; returns its path.
    std::string write(const std::string& file, const std::string& text) const {
        std::ofstream(path / file, std::ios::binary) << text;
        return (path / file).string();
    }
};

inline std::string source_path(const std::string& rel) {
    return std::string(VLF_SOURCE_DIR) + "/" + rel;
}

inline std::string read_text(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// A face from vertices already in normalised coordinates (counter-clockwise = front),
// with a single texel; enough for rasterisation and exchange tests.
inline Face make_face(const std::vector<Vec3>& vertices, int material = 0) {
    Face f;
    f.vertices = vertices;
    Vec3 n(0.0);
    for (size_t i = 0; i < vertices.size(); ++i) {  // Newell's method
        const Vec3& a = vertices[i];
        const Vec3& b = vertices[(i + 1) % vertices.size()];
        n += Vec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    f.area = 0.5 * glm::length(n);
    f.normal = glm::normalize(n);
    f.plane_offset = glm::dot(f.normal, vertices[0]);
    f.material = material;
    return f;
}

inline Scene make_scene(const std::vector<std::vector<Vec3>>& polygons) {
    Scene s;
    s.source = "test";
    Material m;
    m.name = "white";
    m.diffuse = Rgb(0.5);
    s.materials.push_back(m);
    for (const auto& p : polygons) {
        Face f = make_face(p);
        f.id = static_cast<int>(s.faces.size());
        s.faces.push_back(f);
    }
    return s;
}

inline  // A bake holding only a scene (zero light maps, no rays): enough for the path tracer.
    Bake
    scene_only_bake(const Scene& scene) {
    Bake b;
    b.scene = scene;
    b.texel_offset.assign(scene.charts.size() + 1, 0);
    for (size_t f = 0; f < scene.charts.size(); ++f)
        b.texel_offset[f + 1] = b.texel_offset[f] + size_t(scene.charts[f].texels.count());
    b.lightmap_radiance.assign(b.texel_offset.back(), Rgb(0.0));
    return b;
}

// A smooth test image with every pixel different.
inline Image gradient(int w, int h) {
    Image im;
    im.width = w;
    im.height = h;
    im.pixels.resize(size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) im.at(x, y) = Rgb(0.01 * x, 0.5 + y, 1000.0 / (1 + x + y));
    return im;
}

// A small run: l directions, N x N rays in m x m tiles, `cycles` cycles, no resampling.
inline PropagateParams params(int l, int N, int m, int cycles, bool deferred = false) {
    PropagateParams p;
    p.field.directions = l;
    p.field.resolution = N;
    p.field.tile = m;
    p.cycles = cycles;
    p.deferred = deferred;
    p.resample = false;
    return p;
}

// Runs p.cycles cycles of the transport (the last one shoots everything).
inline std::unique_ptr<Transport> run_transport(const Scene& scene, const PropagateParams& p) {
    auto t = std::make_unique<Transport>(scene, p);
    for (int c = 1; c <= p.cycles; ++c) t->run_cycle(c == p.cycles);
    return t;
}

// Midpoint subdivision of an OBJ of triangles (`v` and `f` lines), `levels` times: every
// triangle becomes four on the same plane, numbered after their parent.
inline void subdivide_obj(const std::filesystem::path& in, const std::filesystem::path& out,
                          int levels) {
    std::vector<Vec3> v;
    std::vector<std::array<int, 3>> f;
    std::ifstream is(in);
    for (std::string line; std::getline(is, line);) {
        std::istringstream ls(line);
        std::string tag;
        ls >> tag;
        if (tag == "v") {
            Vec3 p;
            ls >> p.x >> p.y >> p.z;
            v.push_back(p);
        } else if (tag == "f") {
            std::array<int, 3> t{};
            ls >> t[0] >> t[1] >> t[2];
            f.push_back({t[0] - 1, t[1] - 1, t[2] - 1});
        }
    }
    for (int l = 0; l < levels; ++l) {
        std::map<std::pair<int, int>, int> mid;
        auto m = [&](int a, int b) {
            const auto key = std::minmax(a, b);
            const auto it = mid.find(key);
            if (it != mid.end()) return it->second;
            v.push_back(0.5 * (v[a] + v[b]));
            return mid[key] = int(v.size()) - 1;
        };
        std::vector<std::array<int, 3>> g;
        for (const auto& t : f) {
            const int ab = m(t[0], t[1]), bc = m(t[1], t[2]), ca = m(t[2], t[0]);
            g.push_back({t[0], ab, ca});
            g.push_back({ab, t[1], bc});
            g.push_back({ca, bc, t[2]});
            g.push_back({ab, bc, ca});
        }
        f.swap(g);
    }
    std::ofstream os(out);
    os.precision(17);
    for (const Vec3& p : v) os << "v " << p.x << " " << p.y << " " << p.z << "\n";
    for (const auto& t : f) os << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
}

// A scene from JSON text, its files relative to scenes/.
inline Scene scene_from_json(const std::string& text) {
    return load_scene_from_string(text, "test.json", source_path("scenes"));
}

// The object of that name (a test failure, and the first object, where there is none).
inline const SceneObject& object_named(const Scene& s, const std::string& name) {
    for (const SceneObject& o : s.objects)
        if (o.name == name) return o;
    ADD_FAILURE() << "no object " << name;
    return s.objects.front();
}

// The irradiance a texel of a diffuse chart of rho_d 0.5 received in cycle 1, W per square
// unit (its P^T after one cycle is rho_d E A).
inline double texel_irradiance(const Transport& t, const Chart& c, size_t k) {
    const size_t at = t.texture_maps().begin(c.id) + k;
    return t.texture_maps().total[at].x / (0.5 * c.texel_area[k]);
}

// A vertex as an exact key: shared vertices of closed surfaces are bit-identical.
using VertexKey = std::tuple<double, double, double>;
inline VertexKey vertex_key(const Vec3& v) {
    return {v.x, v.y, v.z};
}

}  // namespace vlf::test
