// imprint.cpp — cutting faces along the contact lines of faces that run across them
// (imprint.hpp).
#include "vlf/scene/imprint.hpp"

#include <algorithm>
#include <cmath>

#include "vlf/core/parallel.hpp"
#include "vlf/scene/primitives.hpp"

namespace vlf {

namespace {

// A convex polygon being cut, with its per-vertex attributes and per-edge contact flags.
struct Piece {
    std::vector<Vec3> v;
    std::vector<Vec2> uv;   // empty, or one per vertex
    std::vector<Vec3> n;    // vertex normals: empty, or one per vertex
    std::vector<char> cut;  // per edge e (v[e] -> v[e+1]): it lies on a contact line
};

struct Box {
    Vec3 lo{0.0}, hi{0.0};
};

Box box_of(const Face& f, double tol) {
    Box b{f.vertices[0], f.vertices[0]};
    for (const Vec3& p : f.vertices) {
        b.lo = glm::min(b.lo, p);
        b.hi = glm::max(b.hi, p);
    }
    b.lo -= Vec3(tol);
    b.hi += Vec3(tol);
    return b;
}

bool overlaps(const Box& a, const Box& b) {
    return a.lo.x <= b.hi.x && b.lo.x <= a.hi.x && a.lo.y <= b.hi.y && b.lo.y <= a.hi.y &&
           a.lo.z <= b.hi.z && b.lo.z <= a.hi.z;
}

// Whether x, a point of b's plane, lies inside the convex face b or within tol of it.
bool inside(const Face& b, const Vec3& x, double tol) {
    const size_t m = b.vertices.size();
    for (size_t i = 0; i < m; ++i) {
        const Vec3& p = b.vertices[i];
        const Vec3 e = b.vertices[(i + 1) % m] - p;
        const double len = glm::length(e);
        if (glm::dot(glm::cross(b.normal, e), x - p) < -tol * len) return false;
    }
    return true;
}

// A vertex of a cut piece: where it came from, for its attributes and its edges' flags.
struct Corner {
    Vec3 p{0.0};
    Vec2 uv{0.0};
    Vec3 n{0.0};
    bool on = false;  // on the cutting plane
    int edge_a = -1;  // the original edges it lies on (a kept vertex: two)
    int edge_b = -1;
};

// The part of P on side `sign` (+1 or -1) of the plane; s[i] the signed distances, side[i]
// their classification (0 within tol of the plane).
Piece clip(const Piece& P, const std::vector<double>& s, const std::vector<int>& side, int sign) {
    const size_t m = P.v.size();
    std::vector<Corner> out;
    for (size_t i = 0; i < m; ++i) {
        const size_t j = (i + 1) % m;
        if (side[i] * sign >= 0) {
            Corner c;
            c.p = P.v[i];
            if (!P.uv.empty()) c.uv = P.uv[i];
            if (!P.n.empty()) c.n = P.n[i];
            c.on = side[i] == 0;
            c.edge_a = int((i + m - 1) % m);
            c.edge_b = int(i);
            out.push_back(c);
        }
        if (side[i] * side[j] < 0) {  // the edge crosses the plane
            const double t = s[i] / (s[i] - s[j]);
            Corner c;
            c.p = P.v[i] + t * (P.v[j] - P.v[i]);
            if (!P.uv.empty()) c.uv = P.uv[i] + t * (P.uv[j] - P.uv[i]);
            if (!P.n.empty()) c.n = glm::normalize(P.n[i] + t * (P.n[j] - P.n[i]));
            c.on = true;
            c.edge_a = c.edge_b = int(i);
            out.push_back(c);
        }
    }
    Piece q;
    const size_t k = out.size();
    for (size_t a = 0; a < k; ++a) {
        const Corner& x = out[a];
        const Corner& y = out[(a + 1) % k];
        q.v.push_back(x.p);
        if (!P.uv.empty()) q.uv.push_back(x.uv);
        if (!P.n.empty()) q.n.push_back(x.n);
        // Both ends on the plane: the new edge along the contact line. Else the edge runs
        // along the original edge the two ends share.
        char flag = 1;
        if (!(x.on && y.on)) {
            int shared = -1;
            for (int e : {x.edge_a, x.edge_b})
                if (e >= 0 && (e == y.edge_a || e == y.edge_b)) shared = e;
            flag = shared >= 0 ? P.cut[size_t(shared)] : 0;
        }
        q.cut.push_back(flag);
    }
    return q;
}

// Cuts P by the plane of B when P straddles it and B covers the whole crossing segment.
bool cut(const Piece& P, const Face& B, double tol, Piece& pos, Piece& neg) {
    const size_t m = P.v.size();
    std::vector<double> s(m);
    std::vector<int> side(m);
    double lo = 0.0, hi = 0.0;
    for (size_t i = 0; i < m; ++i) {
        s[i] = glm::dot(B.normal, P.v[i]) - B.plane_offset;
        side[i] = s[i] > tol ? 1 : (s[i] < -tol ? -1 : 0);
        lo = std::min(lo, s[i]);
        hi = std::max(hi, s[i]);
    }
    if (!(hi > tol && lo < -tol)) return false;
    // The crossing segment: vertices on the plane and edge crossings (two on a convex face).
    std::vector<Vec3> ends;
    for (size_t i = 0; i < m; ++i) {
        const size_t j = (i + 1) % m;
        if (side[i] == 0) ends.push_back(P.v[i]);
        if (side[i] * side[j] < 0)
            ends.push_back(P.v[i] + s[i] / (s[i] - s[j]) * (P.v[j] - P.v[i]));
    }
    if (ends.size() != 2) return false;
    for (const Vec3& e : ends)
        if (!inside(B, e, tol)) return false;
    pos = clip(P, s, side, +1);
    neg = clip(P, s, side, -1);
    return pos.v.size() >= 3 && neg.v.size() >= 3;
}

bool cuttable(const Scene& scene, const Face& f, double min_area) {
    const Material& m = scene.material_of(f);
    return f.twin < 0 && !m.is_emitter() && !m.is_specular() && !m.dielectric &&
           f.area >= min_area && f.vertices.size() <= 64;
}

}  // namespace

ImprintResult imprint_contacts(Scene& scene, double min_area, double tol) {
    ImprintResult result;
    std::vector<Face>& faces = scene.faces;
    const size_t F = faces.size();
    std::vector<int> targets;
    for (const Face& f : faces)
        if (cuttable(scene, f, min_area)) targets.push_back(f.id);
    if (targets.empty()) return result;
    std::vector<Box> box(F);
    parallel_for(
        0, long(F), [&](long i) { box[size_t(i)] = box_of(faces[size_t(i)], tol); }, 1024);

    // Per target face: its pieces when it was cut, else empty.
    std::vector<std::vector<Piece>> pieces(targets.size());
    parallel_for(0, long(targets.size()), [&](long t) {
        const Face& A = faces[size_t(targets[size_t(t)])];
        std::vector<Piece> work(1);
        work[0].v = A.vertices;
        work[0].uv = A.uv;
        work[0].n = A.vertex_normals;
        work[0].cut.assign(A.vertices.size(), 0);
        bool any = false;
        for (const Face& B : faces) {
            if (B.id == A.id || !overlaps(box[size_t(A.id)], box[size_t(B.id)])) continue;
            if (std::abs(glm::dot(A.normal, B.normal)) > 1.0 - 1e-9) continue;  // parallel
            std::vector<Piece> next;
            for (const Piece& P : work) {
                Piece p, q;
                if (cut(P, B, tol, p, q)) {
                    next.push_back(std::move(p));
                    next.push_back(std::move(q));
                    any = true;
                } else {
                    next.push_back(P);
                }
            }
            work = std::move(next);
        }
        if (any) pieces[size_t(t)] = std::move(work);
    });

    std::vector<int> cut_index(F, -1);
    for (size_t t = 0; t < targets.size(); ++t)
        if (!pieces[t].empty()) {
            cut_index[size_t(targets[t])] = int(t);
            ++result.cut_faces;
            result.pieces += int(pieces[t].size());
        }
    if (result.cut_faces == 0) return result;

    // The new face list, object by object, in the old order.
    std::vector<Face> out;
    out.reserve(F + size_t(result.pieces - result.cut_faces));
    std::vector<int> new_id(F, -1);
    for (SceneObject& o : scene.objects) {
        const int first = int(out.size());
        for (int f = o.first_face; f < o.first_face + o.face_count; ++f) {
            const Face& old = faces[size_t(f)];
            if (cut_index[size_t(f)] < 0) {
                new_id[size_t(f)] = int(out.size());
                out.push_back(old);
                out.back().id = int(out.size()) - 1;
                continue;
            }
            for (const Piece& p : pieces[size_t(cut_index[size_t(f)])]) {
                Face g = old;
                g.id = int(out.size());
                g.vertices = p.v;
                g.uv = p.uv;
                g.vertex_normals = p.n;
                g.cut_edges = 0;
                for (size_t e = 0; e < p.cut.size(); ++e)
                    if (p.cut[e]) g.cut_edges |= uint64_t(1) << e;
                g.area = polygon_area(p.v);
                out.push_back(std::move(g));
            }
        }
        o.first_face = first;
        o.face_count = int(out.size()) - first;
    }
    for (Face& f : out)
        if (f.twin >= 0) f.twin = new_id[size_t(f.twin)];
    faces = std::move(out);
    return result;
}

}  // namespace vlf
