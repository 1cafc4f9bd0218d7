// bake_test.cpp — the bake bundle (vlf/bake/bake.hpp, DESIGN §6) and its SHA-256
// (vlf/core/checksum.hpp): a propagated scene round-trips through write_bake/read_bake, and every
// damaged bundle is refused with a message naming the bundle and the part.
#include "vlf/bake/bake.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <string>

#include "test_util.hpp"
#include "vlf/bake/geometry_bin.hpp"
#include "vlf/bake/scene_json.hpp"
#include "vlf/core/checksum.hpp"
#include "vlf/core/error.hpp"
#include "vlf/scene/scene_loader.hpp"
#include "vlf/transport/propagation.hpp"
#include "vlf/transport/transport.hpp"

namespace fs = std::filesystem;

namespace vlf {
namespace {

// --- a small propagated scene --------------------------------------------------------------

PropagateParams small_params() {
    PropagateParams p;
    p.field.directions = 33;
    p.field.resolution = 16;
    p.field.tile = 4;
    p.cycles = 2;
    p.threads = 2;
    return p;
}

// Propagated once for the whole suite (the slow part), then baked into memory.
struct Fixture {
    Scene scene;
    PropagateParams params;
    Bake bake;
    Propagation run;
    nlohmann::json report;
    Fixture() {
        // tests/scenes/bake-room.json: a closed room (box seen from inside), a lamp under
        // the ceiling and a tilted mirror facing the room, so specular radiance maps exist.
        scene = load_scene(test::source_path("tests/scenes/bake-room.json"));
        params = small_params();
        run = propagate(scene, params, {});
        report = propagation_report(scene, params, run, 0.0);
        bake = make_bake(scene, params, *run.transport, report);
    }
};

const Fixture& fixture() {
    static const Fixture f;
    return f;
}

// A fresh directory per test under the system temp dir, removed afterwards.
class BakeBundle : public ::testing::Test {
  protected:
    void SetUp() override {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        m_dir = fs::temp_directory_path() /
                (std::string("vlf-bake-") + info->name() + "-" + std::to_string(::getpid()));
        fs::remove_all(m_dir);
        fs::create_directories(m_dir);
        m_bundle = (m_dir / "scene.vlf").string();
    }
    // VLF_KEEP_BAKE_TEST=1 keeps the bundles (to inspect them with exrheader etc.).
    void TearDown() override {
        if (!std::getenv("VLF_KEEP_BAKE_TEST")) fs::remove_all(m_dir);
    }

    // Writes the fixture's bake; returns the bundle path.
    const std::string& written() {
        write_bake(m_bundle, fixture().bake);
        return m_bundle;
    }
    fs::path file(const std::string& name) const { return fs::path(m_bundle) / name; }

    // read_bake must throw an Error whose message contains every needle.
    void expect_refused(const std::vector<std::string>& needles) {
        try {
            read_bake(m_bundle);
            ADD_FAILURE() << "read_bake accepted a damaged bundle";
        } catch (const Error& e) {
            const std::string msg = e.what();
            std::cout << "refused: " << msg << "\n";
            for (const std::string& n : needles)
                EXPECT_NE(msg.find(n), std::string::npos) << "'" << n << "' not in: " << msg;
        } catch (const std::exception& e) {
            ADD_FAILURE() << "not a vlf::Error: " << e.what();
        }
    }

    nlohmann::json read_json(const std::string& name) {
        std::ifstream in(file(name));
        return nlohmann::json::parse(in);
    }
    void write_json(const std::string& name, const nlohmann::json& j) {
        std::ofstream out(file(name), std::ios::trunc);
        out << j.dump(1);
    }
    // Replaces scene.json and gives the manifest its true size and checksum, so only the
    // content checks can refuse it.
    void write_scene_with_checksum(const nlohmann::json& scene) {
        write_json("scene.json", scene);
        nlohmann::json m = read_json("manifest.json");
        uint64_t bytes = 0;
        m["files"]["scene.json"]["sha256"] = sha256_file(file("scene.json").string(), bytes);
        m["files"]["scene.json"]["bytes"] = bytes;
        write_json("manifest.json", m);
    }

    fs::path m_dir;
    std::string m_bundle;
};

void expect_same_vec(const Vec3& a, const Vec3& b) {
    EXPECT_EQ(a.x, b.x);
    EXPECT_EQ(a.y, b.y);
    EXPECT_EQ(a.z, b.z);
}

// A two-sided face and its reverse twin survive the round trip through geometry.bin: the
// walkthrough's ray caster shows, of the two, the side a ray meets, which it can only do
// when it knows they are twins (without them one side of every two-sided face rendered
// black from the bake). A one-way twin is refused.
TEST(BakeGeometry, KeepsTwoSidedTwins) {
    Scene a = load_scene(test::source_path("tests/scenes/contact-room.json"));
    int twins = 0;
    for (const Face& f : a.faces) twins += f.twin >= 0;
    ASSERT_GT(twins, 0);
    const fs::path file = fs::temp_directory_path() / "vlf-bake-twins.bin";
    write_geometry(file.string(), a);
    Scene b = vlf::scene_from_json(scene_to_json(a), "scene.json");
    read_geometry(file.string(), b);
    for (size_t f = 0; f < a.faces.size(); ++f) EXPECT_EQ(b.faces[f].twin, a.faces[f].twin);
    for (Face& f : a.faces)
        if (f.twin >= 0) {
            f.twin = -1;
            break;
        }
    write_geometry(file.string(), a);
    Scene c = vlf::scene_from_json(scene_to_json(a), "scene.json");
    try {
        read_geometry(file.string(), c);
        ADD_FAILURE() << "a one-way twin was accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("does not name it back"), std::string::npos)
            << e.what();
    }
    fs::remove(file);
}

TEST(BakeMake, RaysMatchTheSpecularMaps) {
    const Fixture& fx = fixture();
    const Bake& b = fx.bake;
    ASSERT_GT(fx.scene.specular_face_count(), 0);
    EXPECT_EQ(b.rays.directions, 33);
    EXPECT_EQ(b.rays.resolution, 16);
    EXPECT_EQ(b.rays.tile, 4);
    ASSERT_EQ(b.rays.pixel_offset.size(), size_t(33) * 16 * 16 + 1);
    ASSERT_GT(b.rays.face.size(), 0u);
    // Only specular faces are stored (no --store-all-rays); per pixel ascending face ids.
    bool any_light = false;
    for (size_t p = 0; p + 1 < b.rays.pixel_offset.size(); ++p)
        for (uint64_t k = b.rays.pixel_offset[p]; k < b.rays.pixel_offset[p + 1]; ++k) {
            const Face& f = fx.scene.faces[b.rays.face[k]];
            EXPECT_TRUE(fx.scene.material_of(f).is_specular());
            if (k > b.rays.pixel_offset[p]) {
                EXPECT_LT(b.rays.face[k - 1], b.rays.face[k]);
            }
            any_light = any_light || b.rays.radiance[k].x > 0;
        }
    EXPECT_TRUE(any_light) << "the mirror should carry some light after 2 cycles";
    // Every ray of the mirror's radiance maps appears once: sample count = stored rays.
    Scene scene = fx.scene;
    const Transport t(scene, fx.params);
    EXPECT_EQ(b.rays.face.size(), t.specular_maps().rays());
    // Lightmap radiance is P^T radiance: the lamp is at least its own emission.
    int lamp = -1;
    for (const Face& f : fx.scene.faces)
        if (fx.scene.material_of(f).is_emitter()) lamp = f.id;
    ASSERT_GE(lamp, 0);
    const Face& lf = fx.scene.faces[lamp];
    double best = 0;
    for (size_t t2 = 0; t2 < fx.scene.chart_of(lf).texel_area.size(); ++t2)
        best = std::max(best, b.lightmap_radiance[b.texel_offset[lf.chart] + t2].x);
    EXPECT_GE(best, 10.0 * 0.99);
}

TEST(BakeMake, LookupFindsEverySample) {
    const Bake& b = fixture().bake;
    const int N = b.rays.resolution;
    for (int d = 0; d < b.rays.directions; ++d)
        for (int j = 0; j < N; ++j)
            for (int i = 0; i < N; ++i) {
                const size_t p = (size_t(d) * N + j) * N + i;
                for (uint64_t k = b.rays.pixel_offset[p]; k < b.rays.pixel_offset[p + 1]; ++k) {
                    RgbF out(-1.0f);
                    ASSERT_TRUE(b.rays.lookup(d, i, j, b.rays.face[k], out));
                    EXPECT_EQ(out, b.rays.radiance[k]);
                }
            }
    RgbF out;
    EXPECT_FALSE(b.rays.lookup(0, 0, 0, 100000, out));
    EXPECT_FALSE(b.rays.lookup(-1, 0, 0, 0, out));
    EXPECT_FALSE(b.rays.lookup(0, N, 0, 0, out));
}

TEST_F(BakeBundle, RoundTrip) {
    const Bake& a = fixture().bake;
    write_bake(m_bundle, a);
    EXPECT_FALSE(fs::exists(m_bundle + ".partial"));
    for (const char* f : {"manifest.json", "scene.json", "lightmaps.exr", "lightfield.exr"})
        EXPECT_TRUE(fs::is_regular_file(file(f))) << f;
    const Bake b = read_bake(m_bundle);

    // Scene: exact.
    ASSERT_EQ(b.scene.faces.size(), a.scene.faces.size());
    EXPECT_EQ(scene_to_json(b.scene), scene_to_json(a.scene));
    for (size_t f = 0; f < a.scene.faces.size(); ++f) {
        const Face &fa = a.scene.faces[f], &fb = b.scene.faces[f];
        ASSERT_EQ(fa.vertices.size(), fb.vertices.size());
        for (size_t v = 0; v < fa.vertices.size(); ++v)
            expect_same_vec(fa.vertices[v], fb.vertices[v]);
        expect_same_vec(fa.normal, fb.normal);
        EXPECT_EQ(fa.plane_offset, fb.plane_offset);
        EXPECT_EQ(fa.area, fb.area);
        EXPECT_EQ(fa.chart, fb.chart);
        EXPECT_EQ(fa.inner_edges, fb.inner_edges);
        EXPECT_EQ(fa.material, fb.material);
        EXPECT_EQ(fa.object, fb.object);
        EXPECT_EQ(fa.twin, fb.twin);
    }
    ASSERT_EQ(a.scene.charts.size(), b.scene.charts.size());
    for (size_t c = 0; c < a.scene.charts.size(); ++c) {
        const Chart &ca = a.scene.charts[c], &cb = b.scene.charts[c];
        EXPECT_EQ(ca.faces, cb.faces);
        EXPECT_EQ(ca.material, cb.material);
        EXPECT_EQ(ca.planar, cb.planar);
        EXPECT_EQ(ca.area, cb.area);
        expect_same_vec(ca.normal, cb.normal);
        expect_same_vec(ca.texels.origin, cb.texels.origin);
        expect_same_vec(ca.texels.axis_u, cb.texels.axis_u);
        expect_same_vec(ca.texels.axis_v, cb.texels.axis_v);
        EXPECT_EQ(ca.texels.size, cb.texels.size);
        EXPECT_EQ(ca.texels.width, cb.texels.width);
        EXPECT_EQ(ca.texels.height, cb.texels.height);
        EXPECT_EQ(ca.texel_area, cb.texel_area);
    }
    ASSERT_EQ(b.scene.materials.size(), a.scene.materials.size());
    for (size_t k = 0; k < a.scene.materials.size(); ++k) {
        EXPECT_EQ(b.scene.materials[k].name, a.scene.materials[k].name);
        expect_same_vec(b.scene.materials[k].emission, a.scene.materials[k].emission);
        expect_same_vec(b.scene.materials[k].specular, a.scene.materials[k].specular);
    }
    ASSERT_EQ(b.scene.cameras.size(), 1u);
    expect_same_vec(b.scene.cameras[0].eye, a.scene.cameras[0].eye);
    expect_same_vec(b.scene.normalisation.center, a.scene.normalisation.center);
    EXPECT_EQ(b.scene.normalisation.scale, a.scene.normalisation.scale);
    EXPECT_EQ(b.scene.units, "m");
    EXPECT_EQ(b.scene.texel_size_user, a.scene.texel_size_user);

    // Parameters, manifest, directions.
    EXPECT_EQ(to_json(b.params), to_json(a.params));
    EXPECT_EQ(b.manifest["ledger"], a.manifest["ledger"]);
    EXPECT_FALSE(b.manifest["ledger"].empty());
    EXPECT_EQ(b.manifest["format"], "vlf-bake");
    EXPECT_EQ(b.manifest["version"], kBakeVersion);
    EXPECT_EQ(b.manifest["units"], "m");
    EXPECT_EQ(b.manifest["files"].size(), 6u);
    ASSERT_EQ(b.directions.size(), 33);
    for (int d = 0; d < 33; ++d)
        expect_same_vec(b.directions.direction(d), a.directions.direction(d));

    // Lightmaps: half precision.
    EXPECT_EQ(b.texel_offset, a.texel_offset);
    ASSERT_EQ(b.lightmap_radiance.size(), a.lightmap_radiance.size());
    for (size_t t = 0; t < a.lightmap_radiance.size(); ++t)
        for (int c = 0; c < 3; ++c) {
            const double x = a.lightmap_radiance[t][c], y = b.lightmap_radiance[t][c];
            EXPECT_NEAR(y, x, 1e-3 * std::abs(x) + 1e-6) << "texel " << t << " channel " << c;
        }

    // Rays: identical, every sample.
    EXPECT_EQ(b.rays.directions, a.rays.directions);
    EXPECT_EQ(b.rays.resolution, a.rays.resolution);
    EXPECT_EQ(b.rays.tile, a.rays.tile);
    EXPECT_EQ(b.rays.pixel_offset, a.rays.pixel_offset);
    EXPECT_EQ(b.rays.face, a.rays.face);
    ASSERT_EQ(b.rays.radiance.size(), a.rays.radiance.size());
    for (size_t k = 0; k < a.rays.radiance.size(); ++k)
        ASSERT_EQ(b.rays.radiance[k], a.rays.radiance[k]) << "sample " << k;
}

// propagate writes the light field straight from the radiance maps, one direction at a
// time; the file must be the one the in-memory bake writes, byte for byte.
TEST_F(BakeBundle, StreamedLightFieldIsTheInMemoryOne) {
    const Fixture& fx = fixture();
    write_bake(m_bundle, fx.bake);
    const std::string streamed = (m_dir / "streamed.vlf").string();
    const Bake meta = make_bake(fx.scene, fx.params, *fx.run.transport, fx.report, false);
    EXPECT_TRUE(meta.rays.face.empty());
    write_bake(streamed, meta, ray_source(fx.scene, fx.params, *fx.run.transport));
    auto bytes = [](const fs::path& f) {
        std::ifstream in(f, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    const std::string a = bytes(file("lightfield.exr")),
                      b = bytes(fs::path(streamed) / "lightfield.exr");
    ASSERT_GT(a.size(), 1000u);
    EXPECT_TRUE(a == b) << "sizes " << a.size() << " and " << b.size();
    const Bake back = read_bake(streamed);
    EXPECT_EQ(back.rays.face, fx.bake.rays.face);
    EXPECT_EQ(back.rays.pixel_offset, fx.bake.rays.pixel_offset);
}

TEST_F(BakeBundle, ReplacesAnExistingBundle) {
    written();
    const auto first = fs::last_write_time(file("manifest.json"));
    fs::create_directories(m_bundle + ".partial/junk");  // a stale attempt
    written();
    EXPECT_FALSE(fs::exists(m_bundle + ".partial"));
    EXPECT_GE(fs::last_write_time(file("manifest.json")), first);
    EXPECT_NO_THROW(read_bake(m_bundle));
}

TEST_F(BakeBundle, RefusesToReplaceAnUnrelatedDirectory) {
    fs::create_directories(m_bundle);
    std::ofstream(file("precious.txt")) << "keep me";
    EXPECT_THROW(write_bake(m_bundle, fixture().bake), Error);
    EXPECT_TRUE(fs::exists(file("precious.txt")));
}

TEST_F(BakeBundle, WriteToAnUnwritablePathThrows) {
    // A path below a regular file can never be created (even as root).
    const fs::path blocker = m_dir / "not-a-dir";
    std::ofstream(blocker) << "x";
    const std::string bad = (blocker / "out.vlf").string();
    try {
        write_bake(bad, fixture().bake);
        ADD_FAILURE() << "write_bake succeeded below a regular file";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
}

TEST_F(BakeBundle, MissingLightfield) {
    written();
    fs::remove(file("lightfield.exr"));
    expect_refused({m_bundle, "lightfield.exr", "missing"});
}

TEST_F(BakeBundle, MissingManifest) {
    written();
    fs::remove(file("manifest.json"));
    expect_refused({m_bundle, "manifest.json", "missing"});
}

TEST_F(BakeBundle, MissingBundle) {
    expect_refused({m_bundle});
}

TEST_F(BakeBundle, TruncatedLightfield) {
    written();
    const auto size = fs::file_size(file("lightfield.exr"));
    fs::resize_file(file("lightfield.exr"), size / 2);
    expect_refused({m_bundle, "lightfield.exr", "truncated"});
}

TEST_F(BakeBundle, CorruptedLightmaps) {
    written();
    const auto size = fs::file_size(file("lightmaps.exr"));
    {
        std::fstream io(file("lightmaps.exr"), std::ios::in | std::ios::out | std::ios::binary);
        for (std::streamoff at : {std::streamoff(size / 2), std::streamoff(size - 3)}) {
            io.seekg(at);
            char c = 0;
            io.read(&c, 1);
            c = static_cast<char>(~c);
            io.seekp(at);
            io.write(&c, 1);
        }
    }
    EXPECT_EQ(fs::file_size(file("lightmaps.exr")), size);
    expect_refused({m_bundle, "lightmaps.exr", "checksum"});
}

TEST_F(BakeBundle, OtherFormatVersion) {
    written();
    nlohmann::json m = read_json("manifest.json");
    m["version"] = kBakeVersion + 1;
    write_json("manifest.json", m);
    expect_refused({m_bundle, "manifest.json",
                    fmt::format("format version {} is not supported (this build reads {})",
                                kBakeVersion + 1, kBakeVersion)});
}

TEST_F(BakeBundle, NotAManifest) {
    written();
    std::ofstream(file("manifest.json"), std::ios::trunc) << "{\"format\": \"vlf-bake\", ";
    expect_refused({m_bundle + "/manifest.json: line 1, column 24: malformed JSON: "});
}

TEST_F(BakeBundle, ManifestParametersDisagreeWithTheLightfield) {
    written();
    nlohmann::json m = read_json("manifest.json");
    m["parameters"]["directions"] = 129;  // the file holds 33 parts; checksums still agree
    write_json("manifest.json", m);
    expect_refused({m_bundle, "lightfield.exr", "manifest does not match its files", "33 parts"});
}

TEST_F(BakeBundle, ManifestTileDisagreesWithTheLightfield) {
    written();
    nlohmann::json m = read_json("manifest.json");
    const int tiles = m["parameters"]["tiles_per_side"].get<int>();
    m["parameters"]["tile"] = 8;  // tiles_per_side still says 16 / 4
    write_json("manifest.json", m);
    expect_refused({m_bundle + "/manifest.json: parameters.tiles_per_side: ",
                    fmt::format("must be resolution / tile = {} (got {})", tiles / 2, tiles)});
    m["parameters"]["tiles_per_side"] = tiles / 2;  // consistent, but not the file's tiles
    write_json("manifest.json", m);
    expect_refused({m_bundle, "lightfield.exr: part 0", "manifest does not match its files"});
}

// A defect in the manifest's JSON is one line "<bundle>/manifest.json: <json.path>: ...".
TEST_F(BakeBundle, ManifestWithAWrongType) {
    written();
    nlohmann::json m = read_json("manifest.json");
    m["parameters"]["cycles"] = "four";
    write_json("manifest.json", m);
    expect_refused(
        {m_bundle + "/manifest.json: parameters.cycles: expected an integer, got \"four\""});
    m["parameters"]["cycles"] = 0;
    write_json("manifest.json", m);
    expect_refused({m_bundle + "/manifest.json: parameters: --cycles: 0 is out of range"});
    m["parameters"]["cycles"] = 2;
    m["files"]["scene.json"]["bytes"] = -1;
    write_json("manifest.json", m);
    expect_refused(
        {m_bundle + "/manifest.json: files[\"scene.json\"].bytes: must be >= 0 (got -1)"});
}

TEST_F(BakeBundle, ManifestWithAnUnknownKey) {
    written();
    nlohmann::json m = read_json("manifest.json");
    m["parameters"]["colour"] = 1;
    write_json("manifest.json", m);
    expect_refused({m_bundle + "/manifest.json: parameters.colour: unknown key (expected one of: "
                               "directions, resolution, tile, tiles_per_side, scheme,"});
    m["parameters"].erase("colour");
    m["extra"] = true;
    write_json("manifest.json", m);
    expect_refused({m_bundle + "/manifest.json: extra: unknown key (expected one of: format,"});
    m.erase("extra");
    m["files"]["notes.txt"] = {{"bytes", 0}, {"sha256", ""}};
    write_json("manifest.json", m);
    expect_refused({m_bundle + "/manifest.json: files[\"notes.txt\"]: unknown key"});
    m["files"].erase("notes.txt");
    m["parameters"].erase("seed");
    write_json("manifest.json", m);
    expect_refused({m_bundle + "/manifest.json: parameters: missing required key 'seed'"});
}

TEST_F(BakeBundle, ManifestAtlasDisagreesWithTheScene) {
    written();
    nlohmann::json m = read_json("manifest.json");
    m["lightmaps"][0]["width"] = m["lightmaps"][0]["width"].get<int>() + 1;
    write_json("manifest.json", m);
    expect_refused({m_bundle, "lightmaps.exr", "manifest does not match its files"});
}

TEST_F(BakeBundle, SceneFromAnotherBundle) {
    // A consistent checksum on a scene.json from elsewhere: the transform check catches it.
    written();
    nlohmann::json s = read_json("scene.json");
    s["normalisation"]["scale"] = s["normalisation"]["scale"].get<double>() * 2;
    write_scene_with_checksum(s);
    expect_refused({m_bundle, "scene.json", "manifest does not match its files"});
}

// scene.json with a checksum that agrees: its JSON is checked key by key.
TEST_F(BakeBundle, SceneJsonWithAnUnknownKeyOrWrongType) {
    written();
    const nlohmann::json original = read_json("scene.json");
    auto write_scene = [&](const nlohmann::json& s) { write_scene_with_checksum(s); };
    nlohmann::json s = original;
    s["materials"][2]["colour"] = 1;
    write_scene(s);
    expect_refused({m_bundle + "/scene.json: materials[2].colour: unknown key"});
    s = original;
    s["objects"][1]["face_count"] = "x";
    write_scene(s);
    expect_refused(
        {m_bundle + "/scene.json: objects[1].face_count: expected an integer, got \"x\""});
    s = original;
    s["objects"][1]["first_face"] = 1000000;
    write_scene(s);
    expect_refused({m_bundle + ": scene.json: objects[1]: faces 1000000 to ", "out of range"});
}

// geometry.bin with a checksum that agrees: its size, counts, indices and links are checked.
TEST_F(BakeBundle, GeometryBinDamageIsNamed) {
    written();
    const Scene& scene = fixture().bake.scene;
    const size_t F = scene.faces.size();
    const std::string original = [&] {
        std::ifstream in(file("geometry.bin"), std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    }();
    auto write_geometry_bytes = [&](const std::string& bytes) {
        {
            std::ofstream out(file("geometry.bin"), std::ios::binary | std::ios::trunc);
            out << bytes;
        }
        nlohmann::json m = read_json("manifest.json");
        uint64_t n = 0;
        m["files"]["geometry.bin"]["sha256"] = sha256_file(file("geometry.bin").string(), n);
        m["files"]["geometry.bin"]["bytes"] = n;
        write_json("manifest.json", m);
    };
    auto put_i32 = [](std::string& b, size_t at, int32_t v) { std::memcpy(&b[at], &v, 4); };
    const std::string where = m_bundle + "/geometry.bin: ";
    std::string b = original.substr(0, original.size() - 8);
    write_geometry_bytes(b);
    expect_refused({where, "(truncated)"});
    b = original;
    b[3] = 'X';
    write_geometry_bytes(b);
    expect_refused({where + "not a VLF geometry file (bad magic)"});
    b = original;
    put_i32(b, 40 + 4 * F + 4 * 1, 99);  // face 1's material
    write_geometry_bytes(b);
    expect_refused({where + "face material of 1 is 99 (must be in [0, 2])"});
    b = original;
    put_i32(b, 40 + 12 * F + 4 * 2, int32_t(scene.charts.size()));  // face 2's chart
    write_geometry_bytes(b);
    expect_refused({where + "face chart of 2 is ", "(must be in [0, "});
    b = original;
    ASSERT_NE(scene.faces[0].chart, scene.faces[1].chart);
    put_i32(b, 40 + 12 * F + 4 * 1, scene.faces[0].chart);  // face 1 claims face 0's chart
    write_geometry_bytes(b);
    expect_refused({where, "names chart"});
}

TEST_F(BakeBundle, DamageBehindAForgedChecksumNeverCrashes) {
    // Bytes changed *and* the checksum updated (a buggy writer, not bit rot): reading must
    // throw a vlf::Error naming the part or return a bundle that passed every validation.
    written();
    const fs::path lf = file("lightfield.exr");
    const std::string pristine = [&] {
        std::ifstream in(lf, std::ios::binary);
        return std::string(std::istreambuf_iterator<char>(in), {});
    }();
    const nlohmann::json manifest = read_json("manifest.json");
    int refused = 0;
    for (size_t at = 7; at < pristine.size(); at += pristine.size() / 61 + 1) {
        std::string bytes = pristine;
        bytes[at] = static_cast<char>(bytes[at] ^ 0x5a);
        std::ofstream(lf, std::ios::binary | std::ios::trunc) << bytes;
        nlohmann::json m = manifest;
        m["files"]["lightfield.exr"]["sha256"] = sha256_hex(bytes);
        write_json("manifest.json", m);
        try {
            const Bake b = read_bake(m_bundle);
            EXPECT_EQ(b.rays.pixel_offset.back(), b.rays.face.size());
        } catch (const Error& e) {
            ++refused;
            std::cout << "refused: " << e.what() << "\n";
            EXPECT_NE(std::string(e.what()).find("lightfield.exr"), std::string::npos) << e.what();
        }
    }
    EXPECT_GT(refused, 0);
}

}  // namespace
}  // namespace vlf
