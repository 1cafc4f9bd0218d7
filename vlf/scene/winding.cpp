// winding.cpp — consistent winding of imported faces (winding.hpp).
#include "vlf/scene/winding.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <map>

namespace vlf {

namespace {

// One face of one of the meshes.
struct FaceRef {
    int mesh = 0;
    int face = 0;
};

// One face's pass through an edge between welded vertices lo < hi.
struct EdgeUse {
    uint64_t key = 0;      // lo << 32 | hi
    int face = 0;          // index into the FaceRef list
    bool forward = false;  // the face runs lo -> hi
};

// A neighbour across a manifold edge; `agrees` when the two faces run through it in
// opposite directions (as the file has them).
struct Link {
    int face = 0;
    bool agrees = false;
};

// The faces as polygons of welded vertex ids and positions.
struct Surface {
    std::vector<FaceRef> faces;
    std::vector<std::vector<int>> welded;  // per face
    std::vector<Vec3> points;              // per welded id
    // A face on the vertices of an earlier one (in either order: a repeat, or the back of a
    // two-sided sheet) is no one's neighbour and keeps its winding relative to that face:
    // copies[f] lists the copies of f; copy[f] says f is one.
    std::vector<std::vector<int>> copies;
    std::vector<bool> copy;
};

Surface weld(const std::vector<ImportedMesh*>& meshes) {
    Surface s;
    std::map<std::array<double, 3>, int> ids;  // exact position -> welded id
    for (size_t m = 0; m < meshes.size(); ++m) {
        const ImportedMesh& mesh = *meshes[m];
        std::vector<int> id(mesh.vertices.size());
        for (size_t v = 0; v < mesh.vertices.size(); ++v) {
            const Vec3& p = mesh.vertices[v];
            // +0.0 turns -0.0 into +0.0 so the two are one key.
            const auto [it, fresh] =
                ids.try_emplace({p.x + 0.0, p.y + 0.0, p.z + 0.0}, int(s.points.size()));
            if (fresh) s.points.push_back(p);
            id[v] = it->second;
        }
        for (size_t f = 0; f < mesh.faces.size(); ++f) {
            s.faces.push_back({int(m), int(f)});
            std::vector<int> w;
            w.reserve(mesh.faces[f].size());
            for (int v : mesh.faces[f]) w.push_back(id[size_t(v)]);
            s.welded.push_back(std::move(w));
        }
    }
    std::map<std::vector<int>, int> first;  // sorted welded ids -> the first face on them
    s.copies.assign(s.welded.size(), {});
    s.copy.assign(s.welded.size(), false);
    for (size_t f = 0; f < s.welded.size(); ++f) {
        std::vector<int> key = s.welded[f];
        std::sort(key.begin(), key.end());
        const auto [it, fresh] = first.try_emplace(std::move(key), int(f));
        if (!fresh) s.copies[size_t(it->second)].push_back(int(f)), s.copy[f] = true;
    }
    return s;
}

// Twice the vector area (Newell) of face f as the file winds it.
Vec3 newell(const Surface& s, int f) {
    const std::vector<int>& w = s.welded[size_t(f)];
    Vec3 n(0.0);
    for (size_t k = 0; k < w.size(); ++k) {
        const Vec3& a = s.points[size_t(w[k])];
        const Vec3& b = s.points[size_t(w[(k + 1) % w.size()])];
        n += glm::cross(a, b);
    }
    return n;
}

// Six times the signed volume of the cone from `c` over face f (a fan from its first vertex).
double cone_volume(const Surface& s, int f, const Vec3& c) {
    const std::vector<int>& w = s.welded[size_t(f)];
    double v = 0.0;
    const Vec3 a = s.points[size_t(w[0])] - c;
    for (size_t k = 1; k + 1 < w.size(); ++k)
        v += glm::dot(a, glm::cross(s.points[size_t(w[k])] - c, s.points[size_t(w[k + 1])] - c));
    return v;
}

// The solid angle face f subtends at q (sr), positive when q sees its back (Van Oosterom and
// Strackee's formula per fan triangle): over a closed outward surface it sums to 4π at an
// inside point and 0 outside.
double solid_angle(const Surface& s, int f, const Vec3& q) {
    const std::vector<int>& w = s.welded[size_t(f)];
    double total = 0.0;
    const Vec3 a = s.points[size_t(w[0])] - q;
    const double la = glm::length(a);
    for (size_t k = 1; k + 1 < w.size(); ++k) {
        const Vec3 b = s.points[size_t(w[k])] - q, c = s.points[size_t(w[k + 1])] - q;
        const double lb = glm::length(b), lc = glm::length(c);
        const double num = glm::dot(a, glm::cross(b, c));
        const double den =
            la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
        total += 2.0 * std::atan2(num, den);
    }
    return total;
}

// The faces' neighbours across manifold edges; `open[f]` when face f has an edge that is not
// manifold (a border, or shared by more than two faces or twice by one face).
void link_faces(const Surface& s, std::vector<std::vector<Link>>& links, std::vector<bool>& open) {
    std::vector<EdgeUse> uses;
    for (size_t f = 0; f < s.welded.size(); ++f) {
        if (s.copy[f]) continue;
        const std::vector<int>& w = s.welded[f];
        for (size_t k = 0; k < w.size(); ++k) {
            const int a = w[k], b = w[(k + 1) % w.size()];
            if (a == b) continue;  // a repeated vertex: no edge
            const uint64_t lo = uint64_t(std::min(a, b)), hi = uint64_t(std::max(a, b));
            uses.push_back({lo << 32 | hi, int(f), a < b});
        }
    }
    std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
        return x.key != y.key ? x.key < y.key : x.face < y.face;
    });
    links.assign(s.welded.size(), {});
    open.assign(s.welded.size(), false);
    for (size_t i = 0; i < uses.size();) {
        size_t j = i;
        while (j < uses.size() && uses[j].key == uses[i].key) ++j;
        if (j - i == 2 && uses[i].face != uses[i + 1].face) {
            const bool agrees = uses[i].forward != uses[i + 1].forward;
            links[size_t(uses[i].face)].push_back({uses[i + 1].face, agrees});
            links[size_t(uses[i + 1].face)].push_back({uses[i].face, agrees});
        } else {
            for (size_t k = i; k < j; ++k) open[size_t(uses[k].face)] = true;
        }
        i = j;
    }
}

}  // namespace

std::vector<WindingChanges> orient_faces(const std::vector<ImportedMesh*>& meshes,
                                         const std::vector<Vec3>& viewpoints) {
    std::vector<WindingChanges> out(meshes.size());
    for (size_t m = 0; m < meshes.size(); ++m) out[m].faces = meshes[m]->faces.size();
    const Surface s = weld(meshes);
    std::vector<std::vector<Link>> links;
    std::vector<bool> open;
    link_faces(s, links, open);

    const int n = int(s.faces.size());
    std::vector<int8_t> flip(size_t(n), -1);  // -1: not reached yet
    std::vector<int> part;
    for (int seed = 0; seed < n; ++seed) {
        if (flip[size_t(seed)] >= 0) continue;
        // Step 2: a breadth-first walk makes the part agree with its seed.
        part.clear();
        size_t conflicts = 0;
        bool closed = true;
        flip[size_t(seed)] = 0;
        std::deque<int> queue{seed};
        while (!queue.empty()) {
            const int f = queue.front();
            queue.pop_front();
            part.push_back(f);
            for (int c : s.copies[size_t(f)]) {
                flip[size_t(c)] = flip[size_t(f)];
                part.push_back(c);
            }
            closed = closed && !open[size_t(f)];
            for (const Link& l : links[size_t(f)]) {
                const int8_t want = int8_t(flip[size_t(f)] ^ (l.agrees ? 0 : 1));
                if (flip[size_t(l.face)] < 0) {
                    flip[size_t(l.face)] = want;
                    queue.push_back(l.face);
                } else if (flip[size_t(l.face)] != want) {
                    ++conflicts;  // seen from both faces: counted twice
                }
            }
        }
        conflicts /= 2;

        // Step 3: which side the part faces.
        double area_kept = 0.0, area_turned = 0.0;
        // The part without its copies (they would count one sheet twice, or cancel it).
        std::vector<int> sheet;
        for (int f : part)
            if (!s.copy[size_t(f)]) sheet.push_back(f);
        for (int f : sheet)
            (flip[size_t(f)] ? area_turned : area_kept) += glm::length(newell(s, f));
        enum class Turn { None, Outward, Inward } whole = Turn::None;
        bool invert = area_turned > area_kept;
        if (closed && conflicts == 0) {
            Vec3 lo(std::numeric_limits<double>::infinity()), hi = -lo, c(0.0);
            size_t corners = 0;
            for (int f : sheet)
                for (int v : s.welded[size_t(f)]) {
                    const Vec3& p = s.points[size_t(v)];
                    lo = glm::min(lo, p), hi = glm::max(hi, p), c += p, ++corners;
                }
            c /= double(corners);
            double volume = 0.0;  // x 6, with the walk's turns
            for (int f : sheet) volume += (flip[size_t(f)] ? -1.0 : 1.0) * cone_volume(s, f, c);
            const double size = glm::length(hi - lo);
            // A closed part that encloses no volume (two faces back to back) has no outside.
            if (std::abs(volume) > 1e-9 * size * size * size) {
                bool around = false;
                for (const Vec3& q : viewpoints) {
                    double w = 0.0;
                    for (int f : sheet) w += (flip[size_t(f)] ? -1.0 : 1.0) * solid_angle(s, f, q);
                    if (std::abs(w) > 2.0 * kPi) around = true;  // winding number +-1, not 0
                }
                invert = around ? volume > 0 : volume < 0;
                if (invert ? area_kept > area_turned : area_turned > area_kept)
                    whole = around ? Turn::Inward : Turn::Outward;
            }
        }
        if (invert)
            for (int f : part) flip[size_t(f)] ^= 1;

        // Count per mesh; a part is counted once in each mesh it touches.
        std::vector<bool> touched(meshes.size(), false);
        for (int f : part) {
            const size_t m = size_t(s.faces[size_t(f)].mesh);
            touched[m] = true;
            if (!flip[size_t(f)]) continue;
            if (whole == Turn::Outward)
                ++out[m].outward_faces;
            else if (whole == Turn::Inward)
                ++out[m].inward_faces;
            else
                ++out[m].agreed;
        }
        for (size_t m = 0; m < meshes.size(); ++m) {
            if (!touched[m]) continue;
            if (whole == Turn::Outward) ++out[m].outward_parts;
            if (whole == Turn::Inward) ++out[m].inward_parts;
            if (conflicts) ++out[m].non_orientable, out[m].disagreeing_edges += conflicts;
        }
    }

    for (int f = 0; f < n; ++f)
        if (flip[size_t(f)]) {
            std::vector<int>& idx =
                meshes[size_t(s.faces[size_t(f)].mesh)]->faces[size_t(s.faces[size_t(f)].face)];
            std::reverse(idx.begin(), idx.end());
        }
    return out;
}

}  // namespace vlf
