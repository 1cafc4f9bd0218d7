// radiance_maps.hpp — the directional radiance maps of VLF §4.1: for a stored face P and
// direction omega, L_U (unshot) and L_T (total) over the rays P covers in that PSF, in the
// order of P's fragments in tile row-major order and, within each, its edge table.
// Specular faces need both (their light is directional); with --store-all-rays every face
// keeps L_T for the pure render-from-rays walkthrough (§6.1).
//
// The layout (`dir_first`, `within`) covers every direction; the arrays hold only the rays of the
// directions [first, last), from ray `base` on (an MPI rank's own directions, issue 13;
// all of them in one process). begin() is an index into the held arrays.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <vector>

#include "vlf/field/coverage.hpp"
#include "vlf/scene/scene.hpp"

namespace vlf {

using RgbF = glm::vec3;  // radiance maps are single precision (memory; DESIGN §4)

struct RadianceMaps {
    int directions = 0;
    std::vector<int> slot;   // per face: stored index or -1
    std::vector<int> faces;  // stored index -> face id
    // The layout: direction d's rays begin at ray dir_first[d] (one extra: the end), and
    // (d, slot)'s within them at within[d * (stored + 1) + slot] (one extra per direction:
    // its count). A direction's rays fit 32 bits (a PSF holds a few rays a pixel), so the
    // per-face table takes half the memory a 64-bit one would (2,049 directions of a
    // 10,240-face glass ball: 84 MB).
    std::vector<uint64_t> dir_first;
    std::vector<uint32_t> within;
    bool with_unshot = false;
    std::vector<RgbF> unshot;       // L_U, read by the current cycle
    std::vector<RgbF> unshot_next;  // L_U being written for the next cycle
    std::vector<RgbF> total;        // L_T
    int first = 0, last = 0;        // the directions held
    uint64_t base = 0;              // their first ray (= ray_begin(first))

    // coverage(d, f) = rays face f covers in PSF d (measured for every stored face). Holds
    // the directions [first, last) (last < 0: to the end).
    RadianceMaps(const Scene& scene, const std::vector<bool>& stored, int directions,
                 const Coverage& coverage, bool with_unshot, int first = 0, int last = -1);
    RadianceMaps() = default;

    // Holds the directions [d0, d1) instead: the values of those held before are kept, the
    // others are zero; the arrays are reallocated to exactly that size.
    void hold(int d0, int d1);
    bool holds(int d) const { return d >= first && d < last; }
    // The first ray of direction d in the whole layout (d = directions: the end).
    uint64_t ray_begin(int d) const { return dir_first[size_t(d)]; }

    bool stores(int face) const { return face < static_cast<int>(slot.size()) && slot[face] >= 0; }
    // Index of (d, face)'s first ray in the held arrays; d must be held.
    uint64_t begin(int d, int face) const {
        return dir_first[size_t(d)] + within[size_t(d) * (faces.size() + 1) + slot[face]] - base;
    }
    uint64_t count(int d, int face) const {
        const size_t k = size_t(d) * (faces.size() + 1) + slot[face];
        return within[k + 1] - within[k];
    }
    // Rays of every direction (held or not).
    uint64_t rays() const { return dir_first.empty() ? 0 : dir_first.back(); }
    int64_t bytes() const;
};

}  // namespace vlf
