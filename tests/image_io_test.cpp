// Walkthrough images on disk (render/image_io.hpp): EXR round trip, PNG, bad paths.
#include "vlf/render/image_io.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <memory>
#include <string>
#include <utility>

#include "test_util.hpp"
#include "vlf/core/error.hpp"
#include "vlf/core/parallel.hpp"
#include "vlf/render/image_metrics.hpp"
#include "vlf/scene/scene_loader.hpp"

namespace vlf {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------
// Image I/O

class ImageIo : public ::testing::Test {
  protected:
    void SetUp() override {
        m_dir = fs::temp_directory_path() / ("vlf-image-" + std::to_string(::getpid()));
        fs::create_directories(m_dir);
    }
    void TearDown() override { fs::remove_all(m_dir); }
    fs::path m_dir;
};

TEST_F(ImageIo, ExrRoundTripWithinHalfPrecision) {
    const Image im = test::gradient(37, 23);
    const std::string p = (m_dir / "a.exr").string();
    write_image(p, im);
    EXPECT_FALSE(fs::exists(p + ".partial"));
    const Image back = read_exr(p);
    ASSERT_EQ(back.width, im.width);
    ASSERT_EQ(back.height, im.height);
    for (size_t k = 0; k < im.pixels.size(); ++k)
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(back.pixels[k][c], im.pixels[k][c],
                        1e-3 * std::abs(im.pixels[k][c]) + 1e-7);
    EXPECT_LT(relative_rmse(back, im), 1e-3);
}

TEST_F(ImageIo, PngWrittenAndNonEmpty) {
    const std::string p = (m_dir / "a.png").string();
    write_image(p, test::gradient(16, 8), 1.0);
    ASSERT_TRUE(fs::exists(p));
    EXPECT_GT(fs::file_size(p), 8u);
    EXPECT_EQ(test::read_text(p).substr(1, 3), "PNG");
    const auto bytes = tone_map_srgb8(test::gradient(16, 8), 0.0);
    EXPECT_EQ(bytes.size(), 16u * 8u * 3u);
    // Reinhard + sRGB: radiance 1 -> 0.5 -> sRGB 188.
    Image one;
    one.width = one.height = 1;
    one.pixels = {Rgb(1.0, 0.0, 3.0)};
    const auto b = tone_map_srgb8(one, 0.0);
    EXPECT_EQ(b[0], 188);
    EXPECT_EQ(b[1], 0);
    EXPECT_EQ(tone_map_srgb8(one, -1.0)[0], 156);  // 0.5 -> 1/3 -> sRGB 156
}

TEST_F(ImageIo, UnknownExtensionAndBadPathsThrow) {
    EXPECT_THROW(write_image((m_dir / "a.tiff").string(), test::gradient(4, 4)), Error);
    EXPECT_THROW(write_image((m_dir / "no-such-dir" / "a.exr").string(), test::gradient(4, 4)),
                 Error);
    EXPECT_THROW(write_image((m_dir / "no-such-dir" / "a.png").string(), test::gradient(4, 4)),
                 Error);
    EXPECT_THROW(read_exr((m_dir / "missing.exr").string()), Error);
    const std::string junk = (m_dir / "junk.exr").string();
    std::FILE* f = std::fopen(junk.c_str(), "wb");
    std::fputs("not an exr", f);
    std::fclose(f);
    EXPECT_THROW(read_exr(junk), Error);
}

}  // namespace
}  // namespace vlf
