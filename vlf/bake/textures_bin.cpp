// textures_bin.cpp — textures and texture coordinates as binary arrays (textures_bin.hpp).
//
// Layout (little-endian, no padding):
//   "VLFTEX01"                                   8 bytes
//   u64 textures T
//   T x { u32 name length L, L bytes of name, i32 width, i32 height, width*height*3 bytes }
//   u64 faces with texture coordinates U
//   U x { u32 face, f64 uv[2 x the face's vertex count] }
#include "vlf/bake/textures_bin.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include "vlf/bake/binary_reader.hpp"
#include "vlf/core/error.hpp"

namespace vlf {

namespace {

constexpr char kTexturesMagic[8] = {'V', 'L', 'F', 'T', 'E', 'X', '0', '1'};

}  // namespace

void write_textures(const std::string& file, const Scene& scene) {
    std::vector<char> out(kTexturesMagic, kTexturesMagic + 8);
    append_raw(out, uint64_t(scene.textures.size()));
    for (const Texture& t : scene.textures) {
        append_raw(out, uint32_t(t.name.size()));
        out.insert(out.end(), t.name.begin(), t.name.end());
        append_raw(out, int32_t(t.width));
        append_raw(out, int32_t(t.height));
        out.insert(out.end(), t.srgb.begin(), t.srgb.end());
    }
    uint64_t with_uv = 0;
    for (const Face& f : scene.faces) with_uv += f.uv.empty() ? 0 : 1;
    append_raw(out, with_uv);
    for (const Face& f : scene.faces) {
        if (f.uv.empty()) continue;
        VLF_CHECK(f.uv.size() == f.vertices.size());
        append_raw(out, uint32_t(f.id));
        for (const Vec2& uv : f.uv) append_raw(out, uv.x), append_raw(out, uv.y);
    }
    std::ofstream os(file, std::ios::binary | std::ios::trunc);
    os.write(out.data(), static_cast<std::streamsize>(out.size()));
    os.close();
    if (!os) throw Error(fmt::format("{}: cannot be written", file));
}

void read_textures(const std::string& file, Scene& scene) {
    BinaryReader r(file);
    for (char c : kTexturesMagic)
        if (r.get<char>("the header") != c) r.fail("not a VLF textures file (bad magic)");
    const uint64_t T = r.get<uint64_t>("the header");
    if (T > 1u << 20) r.fail(fmt::format("implausible texture count {}", T));
    scene.textures.assign(size_t(T), Texture{});
    for (size_t k = 0; k < T; ++k) {
        Texture& t = scene.textures[k];
        const uint32_t L = r.get<uint32_t>("a texture name");
        if (L > kMaxTextureName)
            r.fail(fmt::format("texture {}: implausible name length {}", k, L));
        t.name.resize(L);
        r.bytes(t.name.data(), L, "a texture name");
        t.width = r.get<int32_t>("a texture size");
        t.height = r.get<int32_t>("a texture size");
        if (t.width <= 0 || t.height <= 0 || int64_t(t.width) * t.height > kMaxTextureTexels)
            r.fail(fmt::format("texture {}: implausible size {} x {}", k, t.width, t.height));
        if (r.left() < size_t(t.width) * size_t(t.height) * 3)
            r.fail(fmt::format("texture {}: truncated in its texels", k));
        t.srgb.resize(size_t(t.width) * size_t(t.height) * 3);
        r.bytes(t.srgb.data(), t.srgb.size(), "texture texels");
        t.finish();
    }
    for (size_t m = 0; m < scene.materials.size(); ++m) {
        const int tex = scene.materials[m].diffuse_texture;
        if (tex < -1 || tex >= int(T))
            r.fail(fmt::format("material {} names texture {} of {}", m, tex, T));
    }
    const uint64_t U = r.get<uint64_t>("the face count");
    if (U > scene.faces.size())
        r.fail(fmt::format("{} faces with coordinates of {}", U, scene.faces.size()));
    for (uint64_t k = 0; k < U; ++k) {
        const uint32_t id = r.get<uint32_t>("a face index");
        if (id >= scene.faces.size()) r.fail(fmt::format("face index {} out of range", id));
        Face& f = scene.faces[id];
        if (!f.uv.empty()) r.fail(fmt::format("face {} has texture coordinates twice", id));
        f.uv.resize(f.vertices.size());
        for (Vec2& uv : f.uv) {
            uv.x = r.get<double>("texture coordinates");
            uv.y = r.get<double>("texture coordinates");
            if (!std::isfinite(uv.x) || !std::isfinite(uv.y))
                r.fail(fmt::format("face {}: texture coordinates are not finite", id));
        }
    }
    r.expect_end();
}

}  // namespace vlf
