#include "vlf/render/image_io.hpp"

#include <Iex.h>
#include <Imath/half.h>
#include <OpenEXR/ImfArray.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfRgbaFile.h>
#include <fmt/format.h>
#include <stb_image_write.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "vlf/core/error.hpp"
#include "vlf/core/files.hpp"

namespace vlf {

namespace fs = std::filesystem;

namespace {

double srgb_encode(double c) {
    return c <= 0.0031308 ? 12.92 * c : 1.055 * std::pow(c, 1.0 / 2.4) - 0.055;
}

void write_exr(const std::string& file, const Image& im) {
    constexpr float kHalfMax = 65504.0f;
    std::vector<Imf::Rgba> px(size_t(im.width) * im.height);
    for (size_t k = 0; k < px.size(); ++k) {
        const Rgb& v = im.pixels[k];
        auto h = [&](double x) {
            return half(std::isfinite(x) ? std::clamp(float(x), -kHalfMax, kHalfMax) : 0.0f);
        };
        px[k] = Imf::Rgba(h(v.x), h(v.y), h(v.z), half(1.0f));
    }
    Imf::Header header(im.width, im.height);
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::RgbaOutputFile out(file.c_str(), header, Imf::WRITE_RGB);
    out.setFrameBuffer(px.data(), 1, size_t(im.width));
    out.writePixels(im.height);
}

}  // namespace

std::vector<uint8_t> tone_map_srgb8(const Image& im, double exposure) {
    const double scale = std::exp2(exposure);
    std::vector<uint8_t> out(size_t(im.width) * im.height * 3);
    for (size_t k = 0; k < im.pixels.size(); ++k)
        for (int c = 0; c < 3; ++c) {
            double x = im.pixels[k][c] * scale;
            if (!std::isfinite(x) || x < 0.0) x = x > 0.0 ? 1e30 : 0.0;
            const double mapped = x / (1.0 + x);
            out[k * 3 + c] = static_cast<uint8_t>(
                std::clamp(std::lround(srgb_encode(mapped) * 255.0), 0L, 255L));
        }
    return out;
}

void write_image(const std::string& path, const Image& image, double exposure) {
    const std::string ext = lower_extension(path);
    if (ext != ".exr" && ext != ".png")
        throw Error(fmt::format("{}: unknown image extension '{}' (use .exr or .png)", path, ext));
    if (image.width < 1 || image.height < 1 ||
        image.pixels.size() != size_t(image.width) * size_t(image.height))
        throw Error(path + ": empty or inconsistent image");
    write_atomically(path, [&](const std::string& partial) {
        if (ext == ".exr") {
            write_exr(partial, image);
        } else {
            const std::vector<uint8_t> bytes = tone_map_srgb8(image, exposure);
            if (!stbi_write_png(partial.c_str(), image.width, image.height, 3, bytes.data(),
                                image.width * 3))
                throw Error("cannot write PNG");
        }
    });
}

Image read_exr(const std::string& path) {
    try {
        Imf::RgbaInputFile in(path.c_str());
        const Imath::Box2i dw = in.dataWindow();
        const int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
        if (w < 1 || h < 1) throw Error("empty data window");
        std::vector<Imf::Rgba> px(size_t(w) * h);
        in.setFrameBuffer(px.data() - dw.min.x - size_t(dw.min.y) * w, 1, size_t(w));
        in.readPixels(dw.min.y, dw.max.y);
        Image im;
        im.width = w;
        im.height = h;
        im.pixels.resize(px.size());
        for (size_t k = 0; k < px.size(); ++k)
            im.pixels[k] = Rgb(float(px[k].r), float(px[k].g), float(px[k].b));
        return im;
    } catch (const Error& e) {
        throw Error(path + ": " + e.what());
    } catch (const std::exception& e) {
        throw Error(path + ": cannot read EXR: " + e.what());
    }
}

}  // namespace vlf
