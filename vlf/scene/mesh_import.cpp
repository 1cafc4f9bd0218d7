// mesh_import.cpp — OpenMesh readers to a plain vertex/face list.
//
// The IO header must come before the mesh header: including MeshIO.hh registers the
// readers (OpenMesh's documented pitfall).
#include "vlf/scene/mesh_import.hpp"

#include <fmt/core.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/PolyMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <mutex>
#include <sstream>

#include "vlf/core/error.hpp"
#include "vlf/core/files.hpp"

namespace vlf {

namespace {

// Double-precision points: the readers parse floats, but nothing after them loses more.
struct DoubleTraits : public OpenMesh::DefaultTraits {
    using Point = OpenMesh::Vec3d;
    using Normal = OpenMesh::Vec3d;
};
using ReadMesh = OpenMesh::PolyMesh_ArrayKernelT<DoubleTraits>;

// OpenMesh reports dropped faces only on its global omerr() stream, which writes to
// std::cerr. While a mesh is read, std::cerr is pointed at a string buffer so a dropped face
// becomes an error instead of a stray line on stderr and a hole. (mostream::disconnect()
// leaks its target, so the stream is redirected rather than re-plumbed.)
class CaptureStderr {
  public:
    CaptureStderr() : m_old(std::cerr.rdbuf(m_text.rdbuf())) {}
    ~CaptureStderr() {
        ::omerr().flush();
        std::cerr.rdbuf(m_old);
    }
    CaptureStderr(const CaptureStderr&) = delete;
    CaptureStderr& operator=(const CaptureStderr&) = delete;
    std::string text() {
        ::omerr().flush();
        return m_text.str();
    }

  private:
    std::ostringstream m_text;
    std::streambuf* m_old;
};

std::mutex g_openmesh_mutex;  // omerr() and std::cerr are process-global

}  // namespace

// OBJ text, line by line: every vertex has three coordinates that are finite in single
// precision (the readers parse floats and drop, or shift the indices past, such vertices),
// and with `faces`, every face has at least 3 vertices and no repeated index (OpenMesh
// drops such faces without a word).
void check_obj_text(const std::string& path, bool faces) {
    std::ifstream in(path);
    std::string line;
    long vertices = 0;
    for (size_t number = 1; std::getline(in, line); ++number) {
        if (line.size() < 2 || (line[1] != ' ' && line[1] != '\t')) continue;
        if (line[0] == 'v') {
            ++vertices;
            const char* s = line.c_str() + 1;
            for (int k = 0; k < 3; ++k) {
                while (*s == ' ' || *s == '\t') ++s;
                char* end = nullptr;
                const double v = std::strtod(s, &end);
                if (end == s)
                    throw Error(fmt::format("{}:{}: vertex has {} coordinate{} (needs 3 numbers)",
                                            path, number, k, k == 1 ? "" : "s"));
                if (!std::isfinite(v) || std::abs(v) > std::numeric_limits<float>::max())
                    throw Error(fmt::format("{}:{}: vertex coordinate '{}' is not a finite number",
                                            path, number, std::string(s, size_t(end - s))));
                s = end;
            }
        } else if (line[0] == 'f' && faces) {
            std::istringstream words(line.substr(2));
            std::vector<long> idx;
            for (std::string w; words >> w;) {
                if (w[0] == '#') break;
                char* end = nullptr;
                const long i = std::strtol(w.c_str(), &end, 10);
                const long v = i < 0 ? vertices + 1 + i : i;  // 1-based; negative: relative
                if (end == w.c_str() || v < 1 || v > vertices)
                    throw Error(
                        fmt::format("{}:{}: face vertex '{}' is not one of the {} "
                                    "vertices so far",
                                    path, number, w, vertices));
                idx.push_back(v);
            }
            if (idx.size() < 3)
                throw Error(fmt::format("{}:{}: face has {} vertex index(es) (needs at least 3)",
                                        path, number, idx.size()));
            std::vector<long> sorted = idx;
            std::sort(sorted.begin(), sorted.end());
            if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
                throw Error(fmt::format("{}:{}: face repeats a vertex index", path, number));
        }
    }
}

// An OFF file's header counts against its body (OpenMesh pads a short face list with copies
// of the last face), and the face and element lines a binary STL's or PLY's reader would
// misread or skip without a word.
void check_off_text(const std::string& path) {
    std::ifstream in(path);
    std::vector<std::string> words;
    std::string line;
    for (std::string w; std::getline(in, line);) {
        const size_t hash = line.find('#');
        std::istringstream ls(line.substr(0, hash));
        while (ls >> w) words.push_back(w);
    }
    size_t at = 0;
    if (at < words.size() && words[at] == "OFF")
        ++at;
    else
        return;  // COFF, NOFF, binary, ...: their extra columns are OpenMesh's to read
    if (words.size() < at + 3) throw Error(fmt::format("'{}': OFF header has no counts", path));
    const long nv = std::strtol(words[at].c_str(), nullptr, 10);
    const long nf = std::strtol(words[at + 1].c_str(), nullptr, 10);
    if (nv < 0 || nf < 0) throw Error(fmt::format("'{}': OFF header counts are negative", path));
    if (size_t(nv) > words.size() / 3)
        throw Error(
            fmt::format("'{}': OFF header says {} vertices, the file ends before them", path, nv));
    // Vertex lines may carry colours or normals; count the faces from the end instead:
    // each face is "n i_1 .. i_n [colour]". Walk faces forwards after the vertices when the
    // vertex lines have exactly 3 numbers (the common case).
    size_t p = at + 3 + size_t(nv) * 3;
    if (p > words.size())
        throw Error(
            fmt::format("'{}': OFF header says {} vertices, the file ends before them", path, nv));
    long faces = 0;
    while (p < words.size() && faces < nf) {
        const long n = std::strtol(words[p].c_str(), nullptr, 10);
        if (n < 1) break;
        p += size_t(n) + 1;
        if (p > words.size()) break;
        ++faces;
    }
    if (faces < nf)
        throw Error(
            fmt::format("'{}': OFF header says {} faces, the file has {}", path, nf, faces));
}

void check_stl_size(const std::string& path) {
    std::error_code ec;
    const auto bytes = std::filesystem::file_size(path, ec);
    std::ifstream in(path, std::ios::binary);
    char head[84] = {};
    in.read(head, 84);
    if (ec || in.gcount() < 84) return;  // short: OpenMesh will say what it is
    if (std::string(head, 5) == "solid") {
        // ASCII unless the size says binary.
        std::string text(head, 84);
        if (text.find("facet") != std::string::npos || bytes < 84) return;
    }
    uint32_t count = 0;
    std::memcpy(&count, head + 80, 4);
    if (uint64_t(bytes) != 84 + 50 * uint64_t(count) && std::string(head, 5) != "solid")
        throw Error(fmt::format("'{}': binary STL says {} triangles, its {} bytes hold {}", path,
                                count, bytes, bytes >= 84 ? (bytes - 84) / 50 : 0));
}

void check_ply_header(const std::string& path) {
    std::ifstream in(path);
    std::string line;
    for (int k = 0; k < 64 && std::getline(in, line); ++k) {
        if (line.rfind("end_header", 0) == 0) return;
        std::istringstream ls(line);
        std::string word, element;
        long n = 0;
        ls >> word >> element >> n;
        if (word == "element" && (element == "tristrips" || element == "triangle_strips"))
            throw Error(
                fmt::format("'{}': PLY triangle strips ('element {}') are not read; "
                            "write the mesh as faces ('element face')",
                            path, element));
    }
}

namespace {

// An OBJ file's normals belong to face corners (`f v/vt/vn`), OpenMesh's to vertices: a
// vertex whose corners name different normals (a hard edge on shared vertices) would keep
// one of them. Returns why the normals cannot be kept per vertex, or "".
std::string obj_corner_normal_conflict(const std::string& path) {
    std::ifstream in(path);
    std::string line;
    std::vector<Vec3> vn;
    std::vector<long> chosen;  // per vertex: its normal's index, -1 none yet
    long vertices = 0;
    for (size_t number = 1; std::getline(in, line); ++number) {
        if (line.rfind("v ", 0) == 0 || line.rfind("v\t", 0) == 0) {
            ++vertices;
        } else if (line.rfind("vn", 0) == 0 && line.size() > 2 && std::isspace(line[2])) {
            std::istringstream ls(line.substr(2));
            Vec3 n(0.0);
            ls >> n.x >> n.y >> n.z;
            vn.push_back(n);
        } else if (line.rfind("f ", 0) == 0 || line.rfind("f\t", 0) == 0) {
            std::istringstream words(line.substr(2));
            for (std::string w; words >> w;) {
                if (w[0] == '#') break;
                const size_t a = w.find('/');
                if (a == std::string::npos) continue;
                const size_t b = w.find('/', a + 1);
                if (b == std::string::npos || b + 1 >= w.size()) continue;
                long v = std::strtol(w.c_str(), nullptr, 10);
                long n = std::strtol(w.c_str() + b + 1, nullptr, 10);
                v = v < 0 ? vertices + v : v - 1;
                n = n < 0 ? long(vn.size()) + n : n - 1;
                if (v < 0 || n < 0 || size_t(n) >= vn.size()) continue;
                if (chosen.size() <= size_t(v)) chosen.resize(size_t(v) + 1, -1);
                long& c = chosen[size_t(v)];
                if (c < 0)
                    c = n;
                else if (c != n && vn[size_t(c)] != vn[size_t(n)])
                    return fmt::format(
                        "vertex {} has different normals in different faces (line {}; a hard "
                        "edge: \"type\": \"import\" keeps normals per face corner)",
                        v + 1, number);
            }
        }
    }
    return "";
}

}  // namespace

bool is_supported_mesh_file(const std::string& path) {
    const std::string ext = lower_extension(path);
    return ext == ".obj" || ext == ".ply" || ext == ".off" || ext == ".stl";
}

ImportedMesh import_mesh(const std::string& path) {
    check_input_file(path, "mesh file");
    if (!is_supported_mesh_file(path))
        throw Error(fmt::format(
            "mesh file '{}' has an unsupported extension (use .obj, .ply, .off or .stl)", path));

    const std::string ext = lower_extension(path);
    if (ext == ".obj") check_obj_text(path, true);
    if (ext == ".off") check_off_text(path);
    if (ext == ".stl") check_stl_size(path);
    if (ext == ".ply") check_ply_header(path);

    ReadMesh mesh;
    std::string log;
    bool ok = false, has_normals = false;
    {
        std::lock_guard<std::mutex> lock(g_openmesh_mutex);
        CaptureStderr capture;
        mesh.request_vertex_normals();
        OpenMesh::IO::Options opt =
            ext == ".stl" ? OpenMesh::IO::Options::Default : OpenMesh::IO::Options::VertexNormal;
        ok = OpenMesh::IO::read_mesh(mesh, path, opt);
        has_normals = ok && ext != ".stl" && opt.vertex_has_normal();
        log = capture.text();
    }
    auto first_line = [&](const std::string& needle) {
        size_t at = log.find(needle);
        size_t end = log.find('\n', at);
        return log.substr(at, end == std::string::npos ? std::string::npos : end - at);
    };
    if (!ok) {
        std::string why = log.empty() ? std::string("OpenMesh could not parse it") : first_line("");
        throw Error(fmt::format("mesh file '{}' could not be read: {}", path, why));
    }
    // ImporterT drops faces with invalid or repeated vertex indices (it duplicates
    // non-manifold ones, which is harmless for us).
    if (log.find("ImporterT:") != std::string::npos)
        throw Error(fmt::format("mesh file '{}': OpenMesh dropped a face ({})", path,
                                first_line("ImporterT:")));

    ImportedMesh out;
    out.vertices.reserve(mesh.n_vertices());
    for (auto vh : mesh.vertices()) {
        const auto& p = mesh.point(vh);
        out.vertices.emplace_back(p[0], p[1], p[2]);
    }
    out.faces.reserve(mesh.n_faces());
    for (auto fh : mesh.faces()) {
        std::vector<int> f;
        for (auto vh : mesh.fv_range(fh)) f.push_back(vh.idx());
        out.faces.push_back(std::move(f));
    }
    if (out.faces.empty()) throw Error(fmt::format("mesh file '{}' has no faces", path));
    if (has_normals) {
        out.normals_left_out = ext == ".obj" ? obj_corner_normal_conflict(path) : "";
        if (out.normals_left_out.empty()) {
            out.normals.reserve(mesh.n_vertices());
            for (auto vh : mesh.vertices()) {
                const auto& n = mesh.normal(vh);
                out.normals.emplace_back(n[0], n[1], n[2]);
            }
        }
    }
    return out;
}

}  // namespace vlf
