#include "vlf/bake/bake.hpp"

#include <Iex.h>
#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDeepFrameBuffer.h>
#include <OpenEXR/ImfDeepTiledInputPart.h>
#include <OpenEXR/ImfDeepTiledOutputPart.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfMatrixAttribute.h>
#include <OpenEXR/ImfMultiPartInputFile.h>
#include <OpenEXR/ImfMultiPartOutputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfPartType.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTileDescription.h>
#include <OpenEXR/ImfVecAttribute.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>

#include "vlf/core/checksum.hpp"
#include "vlf/core/error.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/field/psf.hpp"
#include "vlf/transport/transport.hpp"

namespace vlf {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kManifest = "manifest.json";
constexpr const char* kSceneFile = "scene.json";
constexpr const char* kLightmaps = "lightmaps.exr";
constexpr const char* kLightfield = "lightfield.exr";
constexpr int kGutter = 1;  // texels between atlas rectangles (and after the last)

// ---------------------------------------------------------------------------------------
// JSON helpers

json vec_json(const Vec3& v) {
    return json::array({v.x, v.y, v.z});
}

Vec3 vec_from(const json& j) {
    if (!j.is_array() || j.size() != 3) throw Error("expected an array of 3 numbers");
    return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

std::string part_name(int d) {
    return fmt::format("dir{}", d);
}

std::string strip_slashes(std::string p) {
    while (p.size() > 1 && p.back() == '/') p.pop_back();
    return p;
}

// ---------------------------------------------------------------------------------------
// Lightmap atlas: shelf packing, tallest faces first (ties by width, then id), so the
// layout is a pure function of the texel grids.

struct AtlasRect {
    int face = 0, x = 0, y = 0, width = 0, height = 0;
};

struct Atlas {
    int width = 1, height = 1;
    std::vector<AtlasRect> rects;  // per face, in face order
};

Atlas pack_atlas(const Scene& scene) {
    Atlas a;
    const int nf = static_cast<int>(scene.faces.size());
    a.rects.resize(nf);
    std::vector<int> order(nf);
    double cells = 0.0;
    int widest = 1;
    for (int f = 0; f < nf; ++f) {
        order[f] = f;
        const TexelFrame& t = scene.faces[f].texels;
        cells += double(t.width + kGutter) * double(t.height + kGutter);
        widest = std::max(widest, t.width + kGutter);
    }
    std::sort(order.begin(), order.end(), [&](int p, int q) {
        const TexelFrame &a1 = scene.faces[p].texels, &b1 = scene.faces[q].texels;
        if (a1.height != b1.height) return a1.height > b1.height;
        if (a1.width != b1.width) return a1.width > b1.width;
        return p < q;
    });
    a.width = std::max(widest, static_cast<int>(std::ceil(std::sqrt(cells))));
    int x = 0, y = 0, shelf = 0;
    for (int f : order) {
        const TexelFrame& t = scene.faces[f].texels;
        if (x + t.width + kGutter > a.width) {  // next shelf
            y += shelf;
            x = 0;
            shelf = 0;
        }
        a.rects[f] = {f, x, y, t.width, t.height};
        x += t.width + kGutter;
        shelf = std::max(shelf, t.height + kGutter);
    }
    a.height = std::max(1, y + shelf);
    return a;
}

// ---------------------------------------------------------------------------------------
// File writing

void write_text(const fs::path& file, const std::string& text) {
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    if (!out) throw Error("cannot be created");
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) throw Error("write failed");
}

void write_lightmaps(const fs::path& file, const Bake& bake, const Atlas& atlas) {
    const size_t w = size_t(atlas.width), h = size_t(atlas.height);
    std::vector<half> rgb[3];
    for (auto& c : rgb) c.assign(w * h, half(0.0f));
    const float kHalfMax = 65504.0f;
    for (const AtlasRect& r : atlas.rects) {
        const size_t base = bake.texel_offset[r.face];
        for (int j = 0; j < r.height; ++j)
            for (int i = 0; i < r.width; ++i) {
                const Rgb& v = bake.lightmap_radiance[base + size_t(j) * r.width + i];
                const size_t px = size_t(r.y + j) * w + size_t(r.x + i);
                for (int c = 0; c < 3; ++c)
                    rgb[c][px] = half(std::clamp(float(v[c]), -kHalfMax, kHalfMax));
            }
    }
    Imf::Header header(atlas.width, atlas.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    const char* names[3] = {"R", "G", "B"};
    Imf::FrameBuffer fb;
    for (int c = 0; c < 3; ++c) {
        header.channels().insert(names[c], Imf::Channel(Imf::HALF));
        fb.insert(names[c], Imf::Slice(Imf::HALF, reinterpret_cast<char*>(rgb[c].data()),
                                       sizeof(half), sizeof(half) * w));
    }
    header.insert("vlfContent", Imf::StringAttribute("diffuse total radiance P^T, W m^-2 sr^-1"));
    Imf::OutputFile out(file.c_str(), header);
    out.setFrameBuffer(fb);
    out.writePixels(atlas.height);
}

// Returns the number of samples written.
uint64_t write_lightfield(const fs::path& file, const Bake& bake, const RaySource& source) {
    const PropagateParams& params = bake.params;
    const int N = params.field.resolution, m = params.field.tile, l = params.field.directions;
    std::unique_ptr<Imf::MultiPartOutputFile> out;
    {
        std::vector<Imf::Header> headers;  // the library keeps its own copies
        headers.reserve(l);
        for (int d = 0; d < l; ++d) {
            Imf::Header h(N, N);
            h.setName(part_name(d));
            h.setType(Imf::DEEPTILE);
            h.setTileDescription(Imf::TileDescription(m, m, Imf::ONE_LEVEL));
            h.compression() = Imf::ZIPS_COMPRESSION;  // ZIP and PIZ are rejected for deep data
            h.channels().insert("face", Imf::Channel(Imf::UINT));
            h.channels().insert("R", Imf::Channel(Imf::FLOAT));
            h.channels().insert("G", Imf::Channel(Imf::FLOAT));
            h.channels().insert("B", Imf::Channel(Imf::FLOAT));
            const Vec3 w = bake.directions.direction(d);
            h.insert("vlfDirectionIndex", Imf::IntAttribute(d));
            h.insert("vlfDirection", Imf::V3dAttribute(Imath::V3d(w.x, w.y, w.z)));
            h.insert("vlfSolidAngle", Imf::DoubleAttribute(bake.directions.solid_angle(d)));
            headers.push_back(h);
        }
        out = std::make_unique<Imf::MultiPartOutputFile>(file.c_str(), headers.data(), l);
    }
    const size_t px = size_t(N) * N;
    DirectionRays rays;
    std::vector<char*> face_ptr(px), ptr[3];
    for (auto& p : ptr) p.resize(px);
    uint64_t samples = 0;
    for (int d = 0; d < l; ++d) {
        source(d, rays);
        VLF_CHECK(rays.counts.size() == px && rays.face.size() == rays.radiance.size());
        uint64_t at = 0;
        for (size_t k = 0; k < px; ++k) {
            if (rays.counts[k] == 0) {
                face_ptr[k] = ptr[0][k] = ptr[1][k] = ptr[2][k] = nullptr;
                continue;
            }
            face_ptr[k] = reinterpret_cast<char*>(&rays.face[at]);
            float* rad = &rays.radiance[at].x;
            for (int c = 0; c < 3; ++c) ptr[c][k] = reinterpret_cast<char*>(rad + c);
            at += rays.counts[k];
        }
        VLF_CHECK(at == rays.face.size());
        samples += at;
        Imf::DeepFrameBuffer fb;
        fb.insertSampleCountSlice(Imf::Slice(Imf::UINT, reinterpret_cast<char*>(rays.counts.data()),
                                             sizeof(uint32_t), sizeof(uint32_t) * N));
        fb.insert("face", Imf::DeepSlice(Imf::UINT, reinterpret_cast<char*>(face_ptr.data()),
                                         sizeof(char*), sizeof(char*) * N, sizeof(int32_t)));
        const char* names[3] = {"R", "G", "B"};
        for (int c = 0; c < 3; ++c)
            fb.insert(names[c], Imf::DeepSlice(Imf::FLOAT, reinterpret_cast<char*>(ptr[c].data()),
                                               sizeof(char*), sizeof(char*) * N, sizeof(RgbF)));
        Imf::DeepTiledOutputPart part(*out, d);
        part.setFrameBuffer(fb);
        part.writeTiles(0, part.numXTiles() - 1, 0, part.numYTiles() - 1);
    }
    return samples;
}

}  // namespace

RaySource ray_source(const RayImages& rays) {
    return [&rays](int d, DirectionRays& out) {
        const size_t px = size_t(rays.resolution) * rays.resolution;
        const uint64_t b = rays.pixel_offset[size_t(d) * px];
        const uint64_t e = rays.pixel_offset[size_t(d + 1) * px];
        out.counts.resize(px);
        for (size_t k = 0; k < px; ++k)
            out.counts[k] = static_cast<uint32_t>(rays.pixel_offset[size_t(d) * px + k + 1] -
                                                  rays.pixel_offset[size_t(d) * px + k]);
        out.face.assign(rays.face.begin() + b, rays.face.begin() + e);
        out.radiance.assign(rays.radiance.begin() + b, rays.radiance.begin() + e);
    };
}

RaySource ray_source(const Scene& scene, const PropagateParams& params,
                     const Transport& transport) {
    // The radiance maps hold L_T in each face's local ray order (its fragments in tile
    // row-major order, each in edge-table order); rasterising the face alone with the
    // same rotation recovers the pixel of every entry. A counting sort by pixel (stable:
    // each pixel keeps ascending face order) gives the layered depth image.
    struct Sample {
        uint32_t pixel;
        int32_t face;
        RgbF radiance;
    };
    struct State {
        FaceRaster raster;
        std::vector<Sample> samples;
        std::vector<uint32_t> cursor;
    };
    auto state = std::make_shared<State>();
    return [&scene, &params, &transport, state](int d, DirectionRays& out) {
        const int N = params.field.resolution, m = params.field.tile;
        const size_t px = size_t(N) * N;
        const RadianceMaps& spec = transport.specular_maps();
        const RadianceMaps& other = transport.other_maps();
        State& st = *state;
        st.samples.clear();
        for (const Face& f : scene.faces) {  // ascending face id: per-pixel order is by face
            const RadianceMaps* maps = spec.stores(f.id)    ? &spec
                                       : other.stores(f.id) ? &other
                                                            : nullptr;
            if (!maps) continue;
            const uint64_t begin = maps->begin(d, f.id), count = maps->count(d, f.id);
            rasterise_face(f, transport.rotations()[d], N, m, st.raster);
            VLF_CHECK(st.raster.covered == count);
            uint64_t k = begin;
            for (const FaceFragment& frag : st.raster.fragments)
                st.raster.edge_table(frag).for_each_ray([&](int u, int v, int) {
                    const uint32_t i = uint32_t(frag.s) * m + u, j = uint32_t(frag.t) * m + v;
                    st.samples.push_back({j * uint32_t(N) + i, f.id, maps->total[k++]});
                });
        }
        out.counts.assign(px, 0);
        for (const Sample& s : st.samples) ++out.counts[s.pixel];
        st.cursor.resize(px);
        uint32_t at = 0;
        for (size_t p = 0; p < px; ++p) {
            st.cursor[p] = at;
            at += out.counts[p];
        }
        out.face.resize(st.samples.size());
        out.radiance.resize(st.samples.size());
        for (const Sample& s : st.samples) {
            const uint32_t k = st.cursor[s.pixel]++;
            out.face[k] = s.face;
            out.radiance[k] = s.radiance;
        }
    };
}

namespace {

// ---------------------------------------------------------------------------------------
// Reading

struct Reader {
    std::string bundle;  // as given, for messages
    fs::path dir;

    [[noreturn]] void fail(const std::string& part, const std::string& what) const {
        throw Error(fmt::format("{}: {}: {}", bundle, part, what));
    }
    [[noreturn]] void mismatch(const std::string& part, const std::string& what) const {
        fail(part, "manifest does not match its files: " + what);
    }
};

json read_manifest(const Reader& r) {
    const fs::path file = r.dir / kManifest;
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) r.fail(kManifest, "is missing");
    std::ifstream in(file, std::ios::binary);
    if (!in) r.fail(kManifest, "cannot be opened");
    json m;
    try {
        m = json::parse(in);
    } catch (const json::exception& e) {
        r.fail(kManifest, fmt::format("not valid JSON ({})", e.what()));
    }
    if (!m.is_object() || !m.contains("format") || !m["format"].is_string() ||
        m["format"].get<std::string>() != kBakeFormat)
        r.fail(kManifest, fmt::format("not a {} manifest", kBakeFormat));
    if (!m.contains("version") || !m["version"].is_number_integer())
        r.fail(kManifest, "format version is missing");
    const auto version = m["version"].get<int64_t>();
    if (version != kBakeVersion)
        r.fail(kManifest, fmt::format("format version {} is not supported (this build reads {})",
                                      version, kBakeVersion));
    return m;
}

void verify_files(const Reader& r, const json& manifest) {
    if (!manifest.contains("files") || !manifest["files"].is_object())
        r.fail(kManifest, "files: missing");
    const json& files = manifest["files"];
    for (const char* required : {kSceneFile, kLightmaps, kLightfield})
        if (!files.contains(required))
            r.fail(kManifest, fmt::format("files: {} is not listed", required));
    for (const auto& [name, entry] : files.items()) {
        if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..")
            r.fail(kManifest, fmt::format("files: '{}' is not a file name", name));
        uint64_t want_bytes = 0;
        std::string want_sha;
        try {
            want_bytes = entry.at("bytes").get<uint64_t>();
            want_sha = entry.at("sha256").get<std::string>();
        } catch (const json::exception& e) {
            r.fail(kManifest, fmt::format("files.{}: {}", name, e.what()));
        }
        const fs::path file = r.dir / name;
        std::error_code ec;
        if (!fs::is_regular_file(file, ec)) r.fail(name, "is missing");
        const uint64_t size = fs::file_size(file, ec);
        if (ec) r.fail(name, "cannot be read");
        if (size != want_bytes)
            r.fail(name, fmt::format("{} bytes, the manifest says {} ({})", size, want_bytes,
                                     size < want_bytes ? "truncated" : "overlong"));
        uint64_t hashed = 0;
        std::string sha;
        try {
            sha = sha256_file(file.string(), hashed);
        } catch (const Error&) {
            r.fail(name, "cannot be read");
        }
        if (hashed != want_bytes) r.fail(name, "changed while being read");
        if (sha != want_sha)
            r.fail(name, "checksum mismatch (sha256 " + sha + ", the manifest says " + want_sha +
                             "): the file is corrupted");
    }
}

std::vector<AtlasRect> manifest_rects(const Reader& r, const json& manifest, const Scene& scene) {
    if (!manifest.contains("lightmaps") || !manifest["lightmaps"].is_array())
        r.fail(kManifest, "lightmaps: missing");
    const json& list = manifest["lightmaps"];
    if (list.size() != scene.faces.size())
        r.mismatch(kLightmaps, fmt::format("{} atlas rectangles for {} faces", list.size(),
                                           scene.faces.size()));
    std::vector<AtlasRect> rects(list.size());
    try {
        for (size_t k = 0; k < list.size(); ++k) {
            const json& e = list[k];
            AtlasRect a{e.at("face").get<int>(), e.at("x").get<int>(), e.at("y").get<int>(),
                        e.at("width").get<int>(), e.at("height").get<int>()};
            if (a.face != static_cast<int>(k))
                r.mismatch(kLightmaps, fmt::format("lightmaps[{}] is face {}", k, a.face));
            const TexelFrame& t = scene.faces[k].texels;
            if (a.width != t.width || a.height != t.height)
                r.mismatch(kLightmaps,
                           fmt::format("face {}: atlas rectangle {}x{}, texel grid {}x{}", k,
                                       a.width, a.height, t.width, t.height));
            rects[k] = a;
        }
    } catch (const json::exception& e) {
        r.fail(kManifest, fmt::format("lightmaps: {}", e.what()));
    }
    return rects;
}

void read_lightmaps(const Reader& r, const std::vector<AtlasRect>& rects, Bake& bake) {
    const fs::path file = r.dir / kLightmaps;
    Imf::InputFile in(file.c_str());
    const Imath::Box2i dw = in.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    if (dw.min.x != 0 || dw.min.y != 0 || w <= 0 || h <= 0)
        r.mismatch(kLightmaps, "unexpected data window");
    const char* names[3] = {"R", "G", "B"};
    for (const char* n : names)
        if (!in.header().channels().findChannel(n))
            r.fail(kLightmaps, fmt::format("channel {} is missing", n));
    for (const AtlasRect& a : rects)
        if (a.x < 0 || a.y < 0 || a.x + a.width > w || a.y + a.height > h)
            r.mismatch(kLightmaps,
                       fmt::format("face {}: rectangle outside the {}x{} atlas", a.face, w, h));
    std::vector<float> rgb[3];
    Imf::FrameBuffer fb;
    for (int c = 0; c < 3; ++c) {
        rgb[c].assign(size_t(w) * h, 0.0f);
        fb.insert(names[c], Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(rgb[c].data()),
                                       sizeof(float), sizeof(float) * size_t(w)));
    }
    in.setFrameBuffer(fb);
    in.readPixels(0, h - 1);
    bake.lightmap_radiance.assign(bake.texel_offset.back(), Rgb(0.0));
    for (const AtlasRect& a : rects) {
        const size_t base = bake.texel_offset[a.face];
        for (int j = 0; j < a.height; ++j)
            for (int i = 0; i < a.width; ++i) {
                const size_t px = size_t(a.y + j) * w + size_t(a.x + i);
                Rgb& v = bake.lightmap_radiance[base + size_t(j) * a.width + i];
                for (int c = 0; c < 3; ++c) {
                    v[c] = rgb[c][px];
                    if (!std::isfinite(v[c]))
                        r.fail(kLightmaps, fmt::format("face {}: non-finite radiance", a.face));
                }
            }
    }
}

void read_lightfield(const Reader& r, const std::vector<bool>& stored, Bake& bake) {
    const fs::path file = r.dir / kLightfield;
    const int l = bake.params.field.directions, N = bake.params.field.resolution,
              m = bake.params.field.tile;
    const int faces = static_cast<int>(bake.scene.faces.size());
    Imf::MultiPartInputFile in(file.c_str());
    if (in.parts() != l)
        r.mismatch(kLightfield,
                   fmt::format("{} parts, the parameters say {} directions", in.parts(), l));
    RayImages& rays = bake.rays;
    rays.directions = l;
    rays.resolution = N;
    rays.tile = m;
    const size_t px = size_t(N) * N;
    rays.pixel_offset.assign(size_t(l) * px + 1, 0);
    rays.face.clear();
    rays.radiance.clear();
    std::vector<uint32_t> counts(px);
    std::vector<char*> face_ptr(px), ptr[3];
    for (auto& p : ptr) p.resize(px);
    std::vector<uint32_t> face_buf;
    std::vector<RgbF> rad_buf;
    const char* names[3] = {"R", "G", "B"};
    for (int d = 0; d < l; ++d) {
        const std::string part = fmt::format("{}: part {}", kLightfield, d);
        try {
            const Imf::Header& h = in.header(d);
            if (!h.hasName() || h.name() != part_name(d))
                r.fail(part, fmt::format("is not named {} (part {} is missing)", part_name(d), d));
            if (!h.hasType() || h.type() != Imf::DEEPTILE) r.fail(part, "is not a deep tiled part");
            const Imath::Box2i dw = h.dataWindow();
            if (dw.min.x != 0 || dw.min.y != 0 || dw.max.x != N - 1 || dw.max.y != N - 1)
                r.mismatch(part, fmt::format("data window is not {}x{}", N, N));
            if (!h.hasTileDescription()) r.mismatch(part, "no tile description");
            const Imf::TileDescription td = h.tileDescription();
            if (int(td.xSize) != m || int(td.ySize) != m || td.mode != Imf::ONE_LEVEL)
                r.mismatch(part, fmt::format("tiles are {}x{}, the parameters say {}x{}", td.xSize,
                                             td.ySize, m, m));
            const Imf::Channel* fc = h.channels().findChannel("face");
            if (!fc || fc->type != Imf::UINT) r.fail(part, "channel 'face' (UINT) is missing");
            for (const char* n : names) {
                const Imf::Channel* c = h.channels().findChannel(n);
                if (!c || c->type != Imf::FLOAT)
                    r.fail(part, fmt::format("channel '{}' (FLOAT) is missing", n));
            }
            if (!in.partComplete(d)) r.fail(part, "is incomplete");

            Imf::DeepTiledInputPart tp(in, d);
            Imf::DeepFrameBuffer fb;
            fb.insertSampleCountSlice(Imf::Slice(Imf::UINT, reinterpret_cast<char*>(counts.data()),
                                                 sizeof(uint32_t), sizeof(uint32_t) * N));
            fb.insert("face", Imf::DeepSlice(Imf::UINT, reinterpret_cast<char*>(face_ptr.data()),
                                             sizeof(char*), sizeof(char*) * N, sizeof(uint32_t)));
            for (int c = 0; c < 3; ++c)
                fb.insert(names[c],
                          Imf::DeepSlice(Imf::FLOAT, reinterpret_cast<char*>(ptr[c].data()),
                                         sizeof(char*), sizeof(char*) * N, sizeof(RgbF)));
            tp.setFrameBuffer(fb);
            const int nx = tp.numXTiles(), ny = tp.numYTiles();
            tp.readPixelSampleCounts(0, nx - 1, 0, ny - 1);
            uint64_t total = 0;
            for (uint32_t c : counts) {
                // A ray crosses each stored face at most once.
                if (c > uint32_t(faces))
                    r.fail(part, "a pixel holds more samples than there are faces");
                total += c;
            }
            face_buf.assign(total, 0);
            rad_buf.assign(total, RgbF(0.0f));
            uint64_t at = 0;
            for (size_t k = 0; k < px; ++k) {
                if (counts[k] == 0) {
                    face_ptr[k] = ptr[0][k] = ptr[1][k] = ptr[2][k] = nullptr;
                    continue;
                }
                face_ptr[k] = reinterpret_cast<char*>(&face_buf[at]);
                for (int c = 0; c < 3; ++c) ptr[c][k] = reinterpret_cast<char*>(&rad_buf[at].x + c);
                at += counts[k];
            }
            tp.readTiles(0, nx - 1, 0, ny - 1);
            // Validate the samples: faces in range, stored, strictly ascending per pixel.
            at = 0;
            const size_t base = rays.face.size();
            for (size_t k = 0; k < px; ++k) {
                rays.pixel_offset[size_t(d) * px + k] = base + at;
                for (uint32_t s = 0; s < counts[k]; ++s, ++at) {
                    const uint32_t f = face_buf[at];
                    if (f >= uint32_t(faces))
                        r.fail(part,
                               fmt::format("sample of face {} (the scene has {} faces)", f, faces));
                    if (!stored[f]) r.mismatch(part, fmt::format("face {} has no stored rays", f));
                    if (s > 0 && face_buf[at - 1] >= f)
                        r.fail(part, "samples of a pixel are not in ascending face order");
                    const RgbF& v = rad_buf[at];
                    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
                        r.fail(part, "non-finite radiance");
                }
            }
            rays.face.insert(rays.face.end(), face_buf.begin(), face_buf.end());
            rays.radiance.insert(rays.radiance.end(), rad_buf.begin(), rad_buf.end());
        } catch (const Error&) {
            throw;
        } catch (const std::exception& e) {  // Iex::BaseExc: damaged tiles, short file
            r.fail(part, e.what());
        }
    }
    rays.pixel_offset.back() = rays.face.size();
}

}  // namespace

// -----------------------------------------------------------------------------------------

bool RayImages::lookup(int d, int i, int j, int face_id, RgbF& out) const {
    if (d < 0 || d >= directions || i < 0 || j < 0 || i >= resolution || j >= resolution)
        return false;
    const size_t p = (size_t(d) * resolution + size_t(j)) * resolution + size_t(i);
    for (uint64_t k = pixel_offset[p]; k < pixel_offset[p + 1]; ++k)
        if (face[k] == face_id) {
            out = radiance[k];
            return true;
        }
    return false;
}

json scene_to_json(const Scene& scene) {
    json materials = json::array();
    for (const Material& m : scene.materials)
        materials.push_back({{"name", m.name},
                             {"diffuse", vec_json(m.diffuse)},
                             {"specular", vec_json(m.specular)},
                             {"emission", vec_json(m.emission)}});
    json objects = json::array();
    for (const SceneObject& o : scene.objects)
        objects.push_back({{"name", o.name},
                           {"type", o.type},
                           {"first_face", o.first_face},
                           {"face_count", o.face_count}});
    json faces = json::array();
    for (const Face& f : scene.faces) {
        json verts = json::array();
        for (const Vec3& v : f.vertices) verts.push_back(vec_json(v));
        const TexelFrame& t = f.texels;
        faces.push_back({{"id", f.id},
                         {"object", f.object},
                         {"material", f.material},
                         {"vertices", verts},
                         {"normal", vec_json(f.normal)},
                         {"plane_offset", f.plane_offset},
                         {"area", f.area},
                         {"texels",
                          {{"origin", vec_json(t.origin)},
                           {"axis_u", vec_json(t.axis_u)},
                           {"axis_v", vec_json(t.axis_v)},
                           {"size", t.size},
                           {"width", t.width},
                           {"height", t.height}}},
                         {"texel_area", f.texel_area}});
    }
    json cameras = json::array();
    for (const Camera& c : scene.cameras)
        cameras.push_back({{"name", c.name},
                           {"eye", vec_json(c.eye)},
                           {"look_at", vec_json(c.look_at)},
                           {"up", vec_json(c.up)},
                           {"fov_y_deg", c.fov_y_deg}});
    // nlohmann writes doubles with the shortest text that round-trips exactly.
    return {
        {"units", scene.units},
        {"normalisation",
         {{"center", vec_json(scene.normalisation.center)}, {"scale", scene.normalisation.scale}}},
        {"user_bounds_min", vec_json(scene.user_bounds_min)},
        {"user_bounds_max", vec_json(scene.user_bounds_max)},
        {"texel_size_user", scene.texel_size_user},
        {"materials", materials},
        {"objects", objects},
        {"faces", faces},
        {"cameras", cameras}};
}

Scene scene_from_json(const json& j, const std::string& name) {
    Scene s;
    s.source = name;
    std::string where;  // the JSON place being read, for messages
    try {
        where = "units";
        s.units = j.at("units").get<std::string>();
        where = "normalisation";
        s.normalisation.center = vec_from(j.at("normalisation").at("center"));
        s.normalisation.scale = j.at("normalisation").at("scale").get<double>();
        if (!(s.normalisation.scale > 0) || !std::isfinite(s.normalisation.scale))
            throw Error("scale must be positive");
        where = "user_bounds";
        s.user_bounds_min = vec_from(j.at("user_bounds_min"));
        s.user_bounds_max = vec_from(j.at("user_bounds_max"));
        where = "texel_size_user";
        s.texel_size_user = j.at("texel_size_user").get<double>();
        const json& mats = j.at("materials");
        for (size_t k = 0; k < mats.size(); ++k) {
            where = fmt::format("materials[{}]", k);
            const json& m = mats.at(k);
            Material mat;
            mat.name = m.at("name").get<std::string>();
            mat.diffuse = vec_from(m.at("diffuse"));
            mat.specular = vec_from(m.at("specular"));
            mat.emission = vec_from(m.at("emission"));
            s.materials.push_back(mat);
        }
        const json& objs = j.at("objects");
        for (size_t k = 0; k < objs.size(); ++k) {
            where = fmt::format("objects[{}]", k);
            const json& o = objs.at(k);
            SceneObject obj;
            obj.name = o.at("name").get<std::string>();
            obj.type = o.at("type").get<std::string>();
            obj.first_face = o.at("first_face").get<int>();
            obj.face_count = o.at("face_count").get<int>();
            s.objects.push_back(obj);
        }
        const json& faces = j.at("faces");
        const int nm = static_cast<int>(s.materials.size()),
                  no = static_cast<int>(s.objects.size());
        for (size_t k = 0; k < faces.size(); ++k) {
            where = fmt::format("faces[{}]", k);
            const json& fj = faces.at(k);
            Face f;
            f.id = fj.at("id").get<int>();
            if (f.id != static_cast<int>(k))
                throw Error(fmt::format("id {} is not its index", f.id));
            f.object = fj.at("object").get<int>();
            f.material = fj.at("material").get<int>();
            if (f.object < 0 || f.object >= no) throw Error("object index out of range");
            if (f.material < 0 || f.material >= nm) throw Error("material index out of range");
            for (const json& v : fj.at("vertices")) f.vertices.push_back(vec_from(v));
            if (f.vertices.size() < 3) throw Error("fewer than 3 vertices");
            f.normal = vec_from(fj.at("normal"));
            f.plane_offset = fj.at("plane_offset").get<double>();
            f.area = fj.at("area").get<double>();
            const json& t = fj.at("texels");
            f.texels.origin = vec_from(t.at("origin"));
            f.texels.axis_u = vec_from(t.at("axis_u"));
            f.texels.axis_v = vec_from(t.at("axis_v"));
            f.texels.size = t.at("size").get<double>();
            f.texels.width = t.at("width").get<int>();
            f.texels.height = t.at("height").get<int>();
            if (f.texels.width < 1 || f.texels.height < 1 || f.texels.width > 65536 ||
                f.texels.height > 65536 || !(f.texels.size > 0))
                throw Error("invalid texel grid");
            f.texel_area = fj.at("texel_area").get<std::vector<double>>();
            if (f.texel_area.size() != size_t(f.texels.width) * size_t(f.texels.height))
                throw Error(fmt::format("texel_area has {} entries for a {}x{} grid",
                                        f.texel_area.size(), f.texels.width, f.texels.height));
            s.faces.push_back(std::move(f));
        }
        for (size_t k = 0; k < s.objects.size(); ++k) {
            const SceneObject& o = s.objects[k];
            where = fmt::format("objects[{}]", k);
            if (o.first_face < 0 || o.face_count < 0 ||
                size_t(o.first_face) + size_t(o.face_count) > s.faces.size())
                throw Error("face range out of range");
        }
        const json& cams = j.at("cameras");
        for (size_t k = 0; k < cams.size(); ++k) {
            where = fmt::format("cameras[{}]", k);
            const json& c = cams.at(k);
            Camera cam;
            cam.name = c.at("name").get<std::string>();
            cam.eye = vec_from(c.at("eye"));
            cam.look_at = vec_from(c.at("look_at"));
            cam.up = vec_from(c.at("up"));
            cam.fov_y_deg = c.at("fov_y_deg").get<double>();
            s.cameras.push_back(cam);
        }
        where.clear();
        if (s.faces.empty()) throw Error("no faces");
    } catch (const json::exception& e) {
        throw Error(fmt::format("{}: {}{}{}", name, where, where.empty() ? "" : ": ", e.what()));
    } catch (const Error& e) {
        throw Error(fmt::format("{}: {}{}{}", name, where, where.empty() ? "" : ": ", e.what()));
    }
    return s;
}

Bake make_bake(const Scene& scene, const PropagateParams& params, const Transport& transport,
               const json& report, bool with_rays) {
    Bake b;
    b.scene = scene;
    b.params = params;
    b.directions = transport.directions();
    auto from_report = [&](const char* key) {
        return report.is_object() && report.contains(key) ? report[key] : json(nullptr);
    };
    b.manifest = {
        {"format", kBakeFormat},
        {"version", kBakeVersion},
        {"parameters", to_json(params)},
        {"scene_transform",
         {{"center", vec_json(scene.normalisation.center)}, {"scale", scene.normalisation.scale}}},
        {"units", scene.units},
        {"ledger", from_report("ledger")},
        {"timings_s", from_report("timings_s")},
        {"memory_bytes", from_report("memory_bytes")},
        {"files", json::object()}};

    // Diffuse total radiance per texel (VLF §4.1 P^T, DESIGN §6 lightmaps).
    const TextureMaps& tex = transport.texture_maps();
    b.texel_offset = tex.offset;
    b.lightmap_radiance.resize(tex.texels());
    for (const Face& f : scene.faces)
        for (size_t t = 0; t < tex.count(f.id); ++t)
            b.lightmap_radiance[tex.begin(f.id) + t] = tex.radiance(f, t);

    // Stored rays as layered depth images, one direction at a time.
    if (!with_rays) return b;
    const int l = transport.directions().size();
    const int N = params.field.resolution;
    const size_t px = size_t(N) * N;
    RayImages& rays = b.rays;
    rays.directions = l;
    rays.resolution = N;
    rays.tile = params.field.tile;
    rays.pixel_offset.assign(size_t(l) * px + 1, 0);
    const RaySource source = ray_source(scene, params, transport);
    DirectionRays dr;
    uint64_t at = 0;
    for (int d = 0; d < l; ++d) {
        source(d, dr);
        for (size_t p = 0; p < px; ++p) {
            rays.pixel_offset[size_t(d) * px + p] = at;
            at += dr.counts[p];
        }
        rays.face.insert(rays.face.end(), dr.face.begin(), dr.face.end());
        rays.radiance.insert(rays.radiance.end(), dr.radiance.begin(), dr.radiance.end());
    }
    rays.pixel_offset.back() = at;
    return b;
}

void write_bake(const std::string& path_in, const Bake& bake, const RaySource& rays) {
    const std::string path = strip_slashes(path_in);
    const fs::path dest(path);
    const fs::path partial(path + ".partial");
    std::string step = "creating " + partial.filename().string();
    try {
        std::error_code ec;
        // A bundle being replaced must be one: never delete an unrelated directory.
        if (fs::exists(dest, ec) && fs::is_directory(dest, ec) && !fs::is_empty(dest, ec) &&
            !fs::exists(dest / kManifest, ec))
            throw Error("exists and is not a bake bundle (no manifest.json); not replacing it");
        if (fs::exists(dest, ec) && !fs::is_directory(dest, ec))
            throw Error("exists and is not a directory");
        fs::remove_all(partial);  // a stale attempt
        fs::create_directories(partial);

        nlohmann::json manifest = bake.manifest;
        step = kSceneFile;
        write_text(partial / kSceneFile, scene_to_json(bake.scene).dump(1) + "\n");

        step = kLightmaps;
        const Atlas atlas = pack_atlas(bake.scene);
        write_lightmaps(partial / kLightmaps, bake, atlas);
        json rects = json::array();
        for (const AtlasRect& r : atlas.rects)
            rects.push_back({{"face", r.face},
                             {"x", r.x},
                             {"y", r.y},
                             {"width", r.width},
                             {"height", r.height}});
        manifest["lightmaps"] = rects;
        manifest["lightmap_atlas"] = {{"width", atlas.width}, {"height", atlas.height}};

        step = kLightfield;
        const uint64_t samples =
            write_lightfield(partial / kLightfield, bake, rays ? rays : ray_source(bake.rays));
        manifest["lightfield"] = {{"directions", bake.params.field.directions},
                                  {"resolution", bake.params.field.resolution},
                                  {"tile", bake.params.field.tile},
                                  {"samples", samples}};

        step = kManifest;
        json files = json::object();
        for (const char* name : {kSceneFile, kLightmaps, kLightfield}) {
            uint64_t bytes = 0;
            const std::string sha = sha256_file((partial / name).string(), bytes);
            files[name] = {{"bytes", bytes}, {"sha256", sha}};
        }
        manifest["files"] = files;
        write_text(partial / kManifest, manifest.dump(1) + "\n");

        step = "renaming " + partial.filename().string();
        // Move the old bundle aside first (a directory cannot be renamed over a non-empty
        // one); if the final rename fails, the old bundle is put back.
        const fs::path old(path + ".old");
        const bool replacing = fs::exists(dest);
        if (replacing) {
            fs::remove_all(old);
            fs::rename(dest, old);
        }
        fs::rename(partial, dest, ec);
        if (ec) {
            std::error_code ignored;
            if (replacing) fs::rename(old, dest, ignored);
            throw fs::filesystem_error("rename", partial, dest, ec);
        }
        if (replacing) fs::remove_all(old);
    } catch (const Error& e) {
        std::error_code ec;
        fs::remove_all(partial, ec);
        throw Error(fmt::format("{}: {}: {}", path, step, e.what()));
    } catch (const fs::filesystem_error& e) {
        std::error_code ec;
        fs::remove_all(partial, ec);
        throw Error(fmt::format("{}: {}: {}", path, step, e.code().message()));
    } catch (const std::exception& e) {  // Iex::BaseExc derives from std::exception
        std::error_code ec;
        fs::remove_all(partial, ec);
        throw Error(fmt::format("{}: {}: {}", path, step, e.what()));
    }
}

Bake read_bake(const std::string& path_in) {
    Reader r;
    r.bundle = strip_slashes(path_in);
    r.dir = fs::path(r.bundle);
    {
        std::error_code ec;
        if (!fs::exists(r.dir, ec)) throw Error(fmt::format("{}: no such bundle", r.bundle));
        if (!fs::is_directory(r.dir, ec))
            throw Error(fmt::format("{}: not a bundle directory", r.bundle));
    }
    Bake bake;
    std::string step = kManifest;
    try {
        bake.manifest = read_manifest(r);
        verify_files(r, bake.manifest);

        step = kSceneFile;
        {
            std::ifstream in(r.dir / kSceneFile, std::ios::binary);
            json sj;
            try {
                sj = json::parse(in);
            } catch (const json::exception& e) {
                r.fail(kSceneFile, fmt::format("not valid JSON ({})", e.what()));
            }
            bake.scene = scene_from_json(sj, r.bundle + ": " + kSceneFile);
        }
        const size_t nf = bake.scene.faces.size();
        bake.texel_offset.assign(nf + 1, 0);
        for (size_t f = 0; f < nf; ++f)
            bake.texel_offset[f + 1] = bake.texel_offset[f] + bake.scene.faces[f].texel_area.size();

        step = kManifest;
        if (!bake.manifest.contains("parameters")) r.fail(kManifest, "parameters: missing");
        try {
            bake.params = propagate_params_from_json(bake.manifest["parameters"]);
        } catch (const Error& e) {
            r.fail(kManifest, e.what());
        }
        try {
            const json& st = bake.manifest.at("scene_transform");
            const Vec3 c = vec_from(st.at("center"));
            const double s = st.at("scale").get<double>();
            if (c != bake.scene.normalisation.center || s != bake.scene.normalisation.scale)
                r.mismatch(kSceneFile, "scene_transform differs from the scene's normalisation");
        } catch (const json::exception& e) {
            r.fail(kManifest, fmt::format("scene_transform: {}", e.what()));
        }
        bake.directions = DirectionSet(bake.params.field.directions, bake.params.field.scheme);

        step = kLightmaps;
        const std::vector<AtlasRect> rects = manifest_rects(r, bake.manifest, bake.scene);
        read_lightmaps(r, rects, bake);

        step = kLightfield;
        std::vector<bool> stored(nf);
        for (size_t f = 0; f < nf; ++f)
            stored[f] = bake.params.store_all_rays ||
                        bake.scene.material_of(bake.scene.faces[f]).is_specular();
        read_lightfield(r, stored, bake);
        if (bake.manifest.contains("lightfield") &&
            bake.manifest["lightfield"].contains("samples")) {
            const json& s = bake.manifest["lightfield"]["samples"];
            if (!s.is_number_unsigned() || s.get<uint64_t>() != bake.rays.face.size())
                r.mismatch(kLightfield, fmt::format("{} samples, the manifest says {}",
                                                    bake.rays.face.size(), s.dump()));
        }
    } catch (const Error&) {
        throw;                           // already names the bundle and the part
    } catch (const std::exception& e) {  // OpenEXR (Iex::BaseExc), filesystem, allocation
        throw Error(fmt::format("{}: {}: {}", r.bundle, step, e.what()));
    }
    return bake;
}

}  // namespace vlf
