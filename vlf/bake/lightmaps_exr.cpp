// lightmaps_exr.cpp — the lightmap atlas as a single-part scanline half-RGB OpenEXR file
// (lightmaps_exr.hpp).
#include "vlf/bake/lightmaps_exr.hpp"

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace vlf {

namespace {

const char* const kLightmapChannels[3] = {"R", "G", "B"};

}  // namespace

void write_lightmaps_exr(const std::string& file, const Atlas& atlas,
                         const std::vector<Rgb>& radiance,
                         const std::vector<size_t>& texel_offset) {
    const size_t w = size_t(atlas.width), h = size_t(atlas.height);
    std::vector<half> rgb[3];
    for (auto& c : rgb) c.assign(w * h, half(0.0f));
    const float kHalfMax = 65504.0f;
    for (const AtlasRect& r : atlas.rects) {
        const size_t base = texel_offset[r.chart];
        for (int j = 0; j < r.height; ++j)
            for (int i = 0; i < r.width; ++i) {
                const Rgb& v = radiance[base + size_t(j) * r.width + i];
                const size_t px = size_t(r.y + j) * w + size_t(r.x + i);
                for (int c = 0; c < 3; ++c)
                    rgb[c][px] = half(std::clamp(float(v[c]), -kHalfMax, kHalfMax));
            }
    }
    Imf::Header header(atlas.width, atlas.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::FrameBuffer fb;
    for (int c = 0; c < 3; ++c) {
        header.channels().insert(kLightmapChannels[c], Imf::Channel(Imf::HALF));
        fb.insert(kLightmapChannels[c],
                  Imf::Slice(Imf::HALF, reinterpret_cast<char*>(rgb[c].data()), sizeof(half),
                             sizeof(half) * w));
    }
    header.insert("vlfContent", Imf::StringAttribute("diffuse total radiance P^T, W m^-2 sr^-1"));
    Imf::OutputFile out(file.c_str(), header);
    out.setFrameBuffer(fb);
    out.writePixels(atlas.height);
}

std::vector<Rgb> read_lightmaps_exr(const std::string& file, const std::vector<AtlasRect>& rects,
                                    int atlas_width, int atlas_height,
                                    const std::vector<size_t>& texel_offset,
                                    const BundleErrors& errors) {
    const char* part = kLightmapsFile;
    Imf::InputFile in(file.c_str());
    const Imath::Box2i dw = in.header().dataWindow();
    const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
    if (dw.min.x != 0 || dw.min.y != 0 || w <= 0 || h <= 0)
        errors.mismatch(part, "unexpected data window");
    if (w != atlas_width || h != atlas_height)
        errors.mismatch(part, fmt::format("the atlas is {}x{}, the manifest says {}x{}", w, h,
                                          atlas_width, atlas_height));
    for (const char* n : kLightmapChannels)
        if (!in.header().channels().findChannel(n))
            errors.fail(part, fmt::format("channel {} is missing", n));
    for (const AtlasRect& a : rects)
        if (a.x < 0 || a.y < 0 || a.x + a.width > w || a.y + a.height > h)
            errors.mismatch(
                part, fmt::format("chart {}: rectangle outside the {}x{} atlas", a.chart, w, h));
    std::vector<float> rgb[3];
    Imf::FrameBuffer fb;
    for (int c = 0; c < 3; ++c) {
        rgb[c].assign(size_t(w) * h, 0.0f);
        fb.insert(kLightmapChannels[c],
                  Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(rgb[c].data()), sizeof(float),
                             sizeof(float) * size_t(w)));
    }
    in.setFrameBuffer(fb);
    in.readPixels(0, h - 1);
    std::vector<Rgb> radiance(texel_offset.back(), Rgb(0.0));
    for (const AtlasRect& a : rects) {
        const size_t base = texel_offset[a.chart];
        for (int j = 0; j < a.height; ++j)
            for (int i = 0; i < a.width; ++i) {
                const size_t px = size_t(a.y + j) * w + size_t(a.x + i);
                Rgb& v = radiance[base + size_t(j) * a.width + i];
                for (int c = 0; c < 3; ++c) {
                    v[c] = rgb[c][px];
                    if (!std::isfinite(v[c]))
                        errors.fail(part, fmt::format("chart {}: non-finite radiance", a.chart));
                }
            }
    }
    return radiance;
}

}  // namespace vlf
