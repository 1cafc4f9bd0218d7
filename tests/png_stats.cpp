// png_stats — prints what the interactive-window test needs to tell a rendered screenshot
// from a blank one: the fraction of non-black pixels and the number of distinct colours.
// Usage: png_stats image.png  ->  "nonblack=0.8731 colours=4213 size=320x240", exit 0;
// exit 2 with one line on stderr when the image cannot be read.
#include <stb_image.h>  // implementation lives in libstb: do not define the macro

#include <cstdint>
#include <cstdio>
#include <unordered_set>

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: png_stats image.png\n");
        return 2;
    }
    int w = 0, h = 0, n = 0;
    unsigned char* px = stbi_load(argv[1], &w, &h, &n, 3);
    if (!px) {
        std::fprintf(stderr, "png_stats: %s: %s\n", argv[1], stbi_failure_reason());
        return 2;
    }
    // "Non-black": any channel above 8/255, so a near-black clear colour does not count.
    size_t nonblack = 0;
    std::unordered_set<uint32_t> colours;
    const size_t count = size_t(w) * size_t(h);
    for (size_t i = 0; i < count; ++i) {
        const unsigned char* p = px + 3 * i;
        if (p[0] > 8 || p[1] > 8 || p[2] > 8) ++nonblack;
        colours.insert(uint32_t(p[0]) << 16 | uint32_t(p[1]) << 8 | p[2]);
    }
    stbi_image_free(px);
    std::printf("nonblack=%.4f colours=%zu size=%dx%d\n",
                count ? double(nonblack) / double(count) : 0.0, colours.size(), w, h);
    return 0;
}
