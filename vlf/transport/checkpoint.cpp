// checkpoint.cpp — writing, checking and restoring the checkpoints of checkpoint.hpp.
#include "vlf/transport/checkpoint.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "vlf/core/checksum.hpp"
#include "vlf/core/error.hpp"
#include "vlf/core/files.hpp"
#include "vlf/transport/state_io.hpp"
#include "vlf/transport/transport.hpp"

namespace vlf {

namespace fs = std::filesystem;

namespace {

// fsync of a file or a directory: what rename's atomicity needs to survive a power cut
// as well as a kill.
void sync_path(const std::string& path, bool directory) {
    const int fd = ::open(path.c_str(), directory ? O_RDONLY | O_DIRECTORY : O_RDONLY);
    if (fd < 0) throw Error(fmt::format("{}: cannot open to sync: {}", path, std::strerror(errno)));
    const int rc = ::fsync(fd);
    const int err = errno;
    ::close(fd);
    if (rc != 0) throw Error(fmt::format("{}: fsync failed: {}", path, std::strerror(err)));
}

std::string state_name(int cycle) {
    return fmt::format("state-{:04d}.bin", cycle);
}

template <class T>
void hash_value(Sha256& h, const T& v) {
    h.update(&v, sizeof(T));
}
void hash_vec3(Sha256& h, const Vec3& v) {
    hash_value(h, v.x);
    hash_value(h, v.y);
    hash_value(h, v.z);
}

bool little_endian() {
    const uint16_t one = 1;
    uint8_t first = 0;
    std::memcpy(&first, &one, 1);
    return first == 1;
}

}  // namespace

std::string scene_fingerprint(const Scene& scene) {
    Sha256 h;
    hash_value(h, scene.faces.size());
    for (const Face& f : scene.faces) {
        hash_value(h, f.material);
        hash_value(h, f.chart);
        hash_value(h, f.twin);
        hash_value(h, f.inner);
        hash_value(h, f.vertices.size());
        for (const Vec3& v : f.vertices) hash_vec3(h, v);
        for (const Vec3& v : f.vertex_normals) hash_vec3(h, v);
    }
    hash_value(h, scene.charts.size());
    for (const Chart& c : scene.charts) {
        hash_value(h, c.material);
        hash_vec3(h, c.texels.origin);
        hash_vec3(h, c.texels.axis_u);
        hash_vec3(h, c.texels.axis_v);
        hash_value(h, c.texels.size);
        hash_value(h, c.texels.width);
        hash_value(h, c.texels.height);
        h.update(c.texel_area.data(), c.texel_area.size() * sizeof(double));
        for (const Rgb& a : c.texel_albedo) hash_vec3(h, a);
        h.update(c.texel_open.data(), c.texel_open.size() * sizeof(double));
    }
    hash_value(h, scene.materials.size());
    for (const Material& m : scene.materials) {
        hash_vec3(h, m.diffuse);
        hash_vec3(h, m.specular);
        hash_vec3(h, m.emission);
        hash_value(h, m.transmission);
        hash_value(h, m.dielectric);
        hash_value(h, m.ior);
        hash_vec3(h, m.absorption);
    }
    hash_value(h, scene.lights.size());
    for (const Light& l : scene.lights) {
        hash_value(h, int(l.type));
        hash_vec3(h, l.position);
        hash_vec3(h, l.direction);
        hash_vec3(h, l.intensity);
        hash_value(h, l.cos_inner);
        hash_value(h, l.cos_outer);
        hash_vec3(h, l.irradiance);
        hash_value(h, l.angular_diameter_deg);
    }
    hash_vec3(h, scene.normalisation.center);
    hash_value(h, scene.normalisation.scale);
    hash_value(h, scene.seal_gap);
    return h.hex_digest();
}

nlohmann::json bake_parameters(const PropagateParams& params) {
    nlohmann::json j = to_json(params);
    j.erase("threads");
    j.erase("cache_budget_mib");
    // The final gather follows the last cycle: a checkpoint holds none of it.
    j.erase("gather");
    j.erase("gather_below");
    return j;
}

void write_checkpoint(const std::string& dir, const Scene& scene, const Transport& transport) {
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
        throw Error(fmt::format("{}: cannot create the checkpoint directory", dir));
    const int cycle = transport.cycles_done();
    const std::string name = state_name(cycle);
    const std::string path = (fs::path(dir) / name).string();
    const std::string partial = path + ".partial";
    std::string digest;
    uint64_t bytes = 0;
    {
        StateWriter out(partial);
        transport.save_state(out);
        out.close();
        digest = out.hex_digest();
        bytes = out.size();
    }
    sync_path(partial, false);
    fs::rename(partial, path, ec);
    if (ec) throw Error(fmt::format("{}: cannot rename into place: {}", path, ec.message()));

    const nlohmann::json params = bake_parameters(transport.params());
    const nlohmann::json manifest = {
        {"format", kCheckpointFormat},
        {"version", kCheckpointVersion},
        {"cycle", cycle},
        {"little_endian", little_endian()},
        {"scene_source", scene.source},
        {"scene_sha256", scene_fingerprint(scene)},
        {"parameters", params},
        {"parameters_sha256", sha256_hex(params.dump())},
        {"state", {{"file", name}, {"bytes", bytes}, {"sha256", digest}}}};
    const std::string mpath = (fs::path(dir) / "manifest.json").string();
    write_atomically(mpath, [&](const std::string& p) {
        write_text(p, manifest.dump(2) + "\n");
        sync_path(p, false);
    });
    sync_path(dir, true);
    // The manifest now names this cycle's state: older ones are no longer needed.
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
        const std::string f = entry.path().filename().string();
        if (f.rfind("state-", 0) == 0 && f != name) fs::remove(entry.path(), ec);
    }
}

CheckpointInfo check_checkpoint(const std::string& dir, const Scene& scene,
                                const PropagateParams& params) {
    auto fail = [&](const std::string& what) -> void {
        throw Error(fmt::format("{}: {}", dir, what));
    };
    if (!fs::is_directory(dir)) fail("no such checkpoint directory");
    const std::string mpath = (fs::path(dir) / "manifest.json").string();
    std::ifstream in(mpath);
    if (!in) fail("manifest.json is missing (not a checkpoint, or no cycle completed yet)");
    std::stringstream text;
    text << in.rdbuf();
    nlohmann::json m;
    try {
        m = nlohmann::json::parse(text.str());
    } catch (const std::exception&) {
        fail("manifest.json is not valid JSON");
    }
    try {
        if (m.at("format") != kCheckpointFormat) fail("manifest.json: not a VLF checkpoint");
        if (m.at("version") != kCheckpointVersion)
            fail(fmt::format("manifest.json: checkpoint version {}, this build reads {}",
                             m.at("version").dump(), kCheckpointVersion));
        if (m.at("little_endian").get<bool>() != little_endian())
            fail("manifest.json: written on a machine of the other byte order");
        if (m.at("scene_sha256") != scene_fingerprint(scene))
            fail(fmt::format("checkpoint is of another scene ({}), or the scene changed since",
                             m.at("scene_source").get<std::string>()));
        const nlohmann::json want = bake_parameters(params);
        const nlohmann::json& have = m.at("parameters");
        for (const auto& [key, value] : want.items())
            if (!have.contains(key) || have.at(key) != value)
                fail(fmt::format("checkpoint was made with {} = {}, this run has {}", key,
                                 have.contains(key) ? have.at(key).dump() : "(none)",
                                 value.dump()));
        if (m.at("parameters_sha256") != sha256_hex(have.dump()) || have != want)
            fail("manifest.json: parameters do not match their checksum");
        CheckpointInfo info;
        info.dir = dir;
        info.cycle = m.at("cycle").get<int>();
        if (info.cycle < 1 || info.cycle > params.cycles)
            fail(fmt::format("manifest.json: cycle {} is out of range 1..{}", info.cycle,
                             params.cycles));
        const nlohmann::json& st = m.at("state");
        const std::string file = st.at("file").get<std::string>();
        if (file != state_name(info.cycle)) fail("manifest.json: state file name does not match");
        info.state_file = (fs::path(dir) / file).string();
        if (!fs::is_regular_file(info.state_file)) fail(file + " is missing");
        uint64_t bytes = 0;
        const std::string digest = sha256_file(info.state_file, bytes);
        if (bytes != st.at("bytes").get<uint64_t>())
            fail(fmt::format("{} has {} bytes, the manifest says {} (truncated?)", file, bytes,
                             st.at("bytes").get<uint64_t>()));
        if (digest != st.at("sha256").get<std::string>())
            fail(fmt::format("{}: checksum mismatch (corrupted)", file));
        return info;
    } catch (const nlohmann::json::exception& e) {
        fail(fmt::format("manifest.json: {}", e.what()));
    }
    return {};
}

void restore_checkpoint(const CheckpointInfo& info, Transport& transport) {
    VLF_CHECK(transport.cycles_done() == 0);
    StateReader in(info.state_file);
    transport.load_state(in);
    if (transport.cycles_done() != info.cycle)
        throw Error(fmt::format("{}: the state holds {} cycles, the manifest says {}", info.dir,
                                transport.cycles_done(), info.cycle));
}

}  // namespace vlf
