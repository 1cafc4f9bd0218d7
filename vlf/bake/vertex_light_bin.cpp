// vertex_light_bin.cpp — gathered vertex light as binary arrays (vertex_light_bin.hpp).
//
// Layout (little-endian, no padding):
//   "VLFVTX01"                                   8 bytes
//   u64 gathered faces G
//   G x { u32 face, f32 rgb[3 x the face's vertex count] }   in increasing face order
#include "vlf/bake/vertex_light_bin.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <vector>

#include "vlf/bake/binary_reader.hpp"
#include "vlf/core/error.hpp"

namespace vlf {

namespace {

constexpr char kVertexLightMagic[8] = {'V', 'L', 'F', 'V', 'T', 'X', '0', '1'};

}  // namespace

void write_vertex_light(const std::string& file, const Scene& scene, const VertexLight& light) {
    std::vector<char> out(kVertexLightMagic, kVertexLightMagic + 8);
    append_raw(out, uint64_t(light.face_count()));
    for (const Face& f : scene.faces) {
        if (!light.has(f.id)) continue;
        append_raw(out, uint32_t(f.id));
        const RgbF* v = light.incident.data() + light.first[size_t(f.id)];
        for (size_t i = 0; i < f.vertices.size(); ++i)
            for (int c = 0; c < 3; ++c) append_raw(out, float(v[i][c]));
    }
    std::ofstream os(file, std::ios::binary | std::ios::trunc);
    os.write(out.data(), static_cast<std::streamsize>(out.size()));
    os.close();
    if (!os) throw Error(fmt::format("{}: cannot be written", file));
}

VertexLight read_vertex_light(const std::string& file, const Scene& scene) {
    BinaryReader r(file);
    for (char c : kVertexLightMagic)
        if (r.get<char>("the header") != c) r.fail("not a VLF vertex light file (bad magic)");
    const uint64_t G = r.get<uint64_t>("the header");
    if (G > scene.faces.size())
        r.fail(fmt::format("{} gathered faces of {}", G, scene.faces.size()));
    VertexLight light;
    if (G == 0) {
        r.expect_end();
        return light;
    }
    light.first.assign(scene.faces.size(), -1);
    int64_t previous = -1;
    for (uint64_t k = 0; k < G; ++k) {
        const uint32_t id = r.get<uint32_t>("a face index");
        if (id >= scene.faces.size()) r.fail(fmt::format("face index {} out of range", id));
        if (int64_t(id) <= previous)
            r.fail(fmt::format("face {} out of order (after face {})", id, previous));
        previous = id;
        light.first[id] = int64_t(light.incident.size());
        for (size_t i = 0; i < scene.faces[id].vertices.size(); ++i) {
            RgbF v;
            for (int c = 0; c < 3; ++c) {
                v[c] = r.get<float>("vertex light");
                if (!std::isfinite(v[c]) || v[c] < 0.0f)
                    r.fail(
                        fmt::format("face {}: vertex light {} is not a finite, non-negative "
                                    "radiance",
                                    id, v[c]));
            }
            light.incident.push_back(v);
        }
    }
    r.expect_end();
    return light;
}

}  // namespace vlf
