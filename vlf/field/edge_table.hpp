// edge_table.hpp — the visibility map of one polygon fragment in one tile, coded as an
// Edge Table: per tile row the column span the polygon covers (VLF §3, Fig. 1). Convex
// polygons give at most one span per row ("an Edge Table entry has either 0 or 2 entries
// per row"), so a row is one half-open interval [begin, end) of tile-local columns.
#pragma once

#include <cstdint>

namespace vlf {

struct Span {
    uint16_t begin = 0;  // first covered column (tile-local)
    uint16_t end = 0;    // one past the last; begin == end: row not covered
    int width() const { return end - begin; }
};

// A read-only view of one fragment's edge table: rows [row_begin, row_begin + rows) of the
// tile, spans[r] for row row_begin + r.
struct EdgeTable {
    int row_begin = 0;
    int rows = 0;
    const Span* spans = nullptr;

    int covered() const;  // number of covered rays (set bits of the visibility map)
    bool contains(int u, int v) const {
        const int r = v - row_begin;
        return r >= 0 && r < rows && u >= spans[r].begin && u < spans[r].end;
    }
    // Calls f(u, v, k) for every covered ray in row-major order; k counts 0, 1, 2, ...
    // This order is the index of a ray in the fragment's radiance maps.
    template <class F>
    void for_each_ray(F&& f) const {
        int k = 0;
        for (int r = 0; r < rows; ++r)
            for (int u = spans[r].begin; u < spans[r].end; ++u) f(u, row_begin + r, k++);
    }
};

}  // namespace vlf
