// Checkpoints (issue 13, checkpoint.hpp): a run stopped after any cycle and resumed from
// its checkpoint ends with the maps, ledger and bake of a run never stopped, bit for bit;
// a checkpoint of another scene or other parameters, or a damaged one, is refused with
// one line naming the directory and the problem; a propagate process killed mid-run
// resumes to the same bake.
#include "vlf/transport/checkpoint.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "test_util.hpp"
#include "vlf/core/error.hpp"
#include "vlf/transport/propagation.hpp"

namespace vlf {
namespace {

namespace fs = std::filesystem;

Scene test_scene(const std::string& name) {
    return load_scene(test::source_path(name));
}

void expect_same_state(const Transport& a, const Transport& b) {
    const TextureMaps &x = a.texture_maps(), &y = b.texture_maps();
    ASSERT_EQ(x.texels(), y.texels());
    for (size_t k = 0; k < x.texels(); ++k) {
        ASSERT_EQ(x.total[k], y.total[k]) << "texel " << k;
        ASSERT_EQ(x.current[k], y.current[k]) << "texel " << k;
    }
    const RadianceMaps &s = a.specular_maps(), &t = b.specular_maps();
    ASSERT_EQ(s.total.size(), t.total.size());
    for (size_t k = 0; k < s.total.size(); ++k) {
        ASSERT_EQ(s.total[k], t.total[k]) << "ray " << k;
        ASSERT_EQ(s.unshot[k], t.unshot[k]) << "ray " << k;
    }
    ASSERT_EQ(a.ledger().size(), b.ledger().size());
    for (size_t c = 0; c < a.ledger().size(); ++c) {
        const LedgerEntry &e = a.ledger()[c], &f = b.ledger()[c];
        EXPECT_EQ(e.absorbed, f.absorbed) << "cycle " << c + 1;
        EXPECT_EQ(e.unshot, f.unshot) << "cycle " << c + 1;
        EXPECT_EQ(e.deferred, f.deferred) << "cycle " << c + 1;
        EXPECT_EQ(e.lost.total(), f.lost.total()) << "cycle " << c + 1;
    }
}

struct Stop {};

// Runs p.cycles cycles with checkpoints in `dir`, stopping (as a kill would) after
// cycle `stop_after`, then resumes from the checkpoint to the end.
Propagation stopped_and_resumed(const Scene& scene, const PropagateParams& p,
                                const std::string& dir, int stop_after) {
    RunOptions first;
    first.checkpoint_dir = dir;
    first.on_cycle = [&](const LedgerEntry& e) {
        if (e.cycle == stop_after) throw Stop{};
    };
    EXPECT_THROW(propagate(scene, p, first), Stop);
    const CheckpointInfo info = check_checkpoint(dir, scene, p);
    EXPECT_EQ(info.cycle, stop_after);
    RunOptions second;
    second.resume = &info;
    second.checkpoint_dir = dir;
    Propagation run = propagate(scene, p, second);
    EXPECT_EQ(run.resumed_after, stop_after);
    return run;
}

// Stops p's run after cycle `stop_after` (checkpoints in dir), resumes it and expects the
// state of the uninterrupted run `straight`.
void expect_resumed_as_straight(const Scene& scene, const PropagateParams& p,
                                const Propagation& straight, const std::string& dir,
                                int stop_after) {
    const Propagation resumed = stopped_and_resumed(scene, p, dir, stop_after);
    expect_same_state(*straight.transport, *resumed.transport);
}

// Deferral, perturbed passes (their normalisers recorded in cycle 1), the filter and
// mirrors (L_U carried between cycles): stopped after cycle 1 and after cycle 2.
TEST(Checkpoint, ResumedRunHasTheMapsOfAnUninterruptedOne) {
    const Scene scene = test_scene("tests/scenes/closed-mirror-room.json");
    PropagateParams p = test::params(33, 32, 8, 3, true);
    p.perturbations = 2;
    p.filter_sigma = 0.7;
    p.perturb_cycles = 2;
    p.resample = true;
    const Propagation straight = propagate(scene, p, {});
    for (int stop : {1, 2}) {
        test::TempDir dir("checkpoint_resume");
        expect_resumed_as_straight(scene, p, straight, dir.path.string(), stop);
        // Only the last cycle's state is kept.
        int states = 0;
        for (const auto& e : fs::directory_iterator(dir.path))
            states += e.path().filename().string().rfind("state-", 0) == 0;
        EXPECT_EQ(states, 1);
    }
}

// Smooth glass (surface_specular.hpp): an uninterrupted run gathers from sources in cycle 1
// and from arrivals through the kept plans after it; a run resumed after cycle 2 makes its
// plans afresh and gathers from sources in cycle 3. The maps must be the same bit for bit:
// both ways are one arithmetic.
TEST(Checkpoint, SmoothGlassGathersFromSourcesAndFromArrivalsAlike) {
    const Scene scene = test_scene("tests/scenes/glass-room.json");
    PropagateParams p = test::params(129, 32, 8, 4, true);
    p.perturbations = 1;
    p.perturb_cycles = 1;
    p.filter_sigma = 0.7;
    const Propagation straight = propagate(scene, p, {});
    test::TempDir dir("checkpoint_glass");
    expect_resumed_as_straight(scene, p, straight, dir.path.string(), 2);
}

// Point and spot lights shoot in cycle 1; their share of P^N is added at
// the end of the cycle. Thread count and cache budget are not part of the key.
TEST(Checkpoint, ResumesAfterTheLightsFirstShot) {
    const Scene scene = test_scene("tests/scenes/lights-open-room.json");
    PropagateParams p = test::params(33, 16, 4, 3, true);
    const Propagation straight = propagate(scene, p, {});
    test::TempDir dir("checkpoint_lights");
    RunOptions first;
    first.checkpoint_dir = dir.path.string();
    first.on_cycle = [&](const LedgerEntry& e) {
        if (e.cycle == 1) throw Stop{};
    };
    EXPECT_THROW(propagate(scene, p, first), Stop);
    PropagateParams q = p;
    q.threads = 1;
    q.cache_budget_mib = 0;
    const CheckpointInfo info = check_checkpoint(dir.path.string(), scene, q);
    RunOptions second;
    second.resume = &info;
    const Propagation resumed = propagate(scene, q, second);
    expect_same_state(*straight.transport, *resumed.transport);
    EXPECT_EQ(straight.transport->light_beams().roots, resumed.transport->light_beams().roots);
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(Checkpoint, RefusesAnotherSceneOtherParametersAndDamage) {
    const Scene scene = test_scene("tests/scenes/closed-mirror-room.json");
    const PropagateParams p = test::params(9, 16, 4, 2, true);
    test::TempDir dir("checkpoint_refuse");
    const std::string d = dir.path.string();
    RunOptions opts;
    opts.checkpoint_dir = d;
    propagate(scene, p, opts);
    EXPECT_EQ(check_checkpoint(d, scene, p).cycle, 2);

    PropagateParams other = p;
    other.field.directions = 33;
    std::string e = error_of([&] { check_checkpoint(d, scene, other); });
    EXPECT_NE(e.find(d), std::string::npos) << e;
    EXPECT_NE(e.find("directions = 9, this run has 33"), std::string::npos) << e;
    other = p;
    other.filter_sigma = 0.5;
    e = error_of([&] { check_checkpoint(d, scene, other); });
    EXPECT_NE(e.find("filter_sigma"), std::string::npos) << e;

    const Scene another = test_scene("tests/scenes/mirror-room.json");
    e = error_of([&] { check_checkpoint(d, another, p); });
    EXPECT_NE(e.find("another scene"), std::string::npos) << e;

    e = error_of([&] { check_checkpoint(d + "/nowhere", scene, p); });
    EXPECT_NE(e.find("no such checkpoint directory"), std::string::npos) << e;

    // One flipped byte in the state file; then the file cut short.
    const fs::path state = dir.path / "state-0002.bin";
    ASSERT_TRUE(fs::exists(state));
    {
        std::fstream f(state, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(100);
        f.put('\x5a');
    }
    e = error_of([&] { check_checkpoint(d, scene, p); });
    EXPECT_NE(e.find("checksum mismatch"), std::string::npos) << e;
    fs::resize_file(state, fs::file_size(state) / 2);
    e = error_of([&] { check_checkpoint(d, scene, p); });
    EXPECT_NE(e.find("truncated"), std::string::npos) << e;
    // No line breaks: the executables print it as one line.
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;

    test::TempDir empty("checkpoint_empty");
    e = error_of([&] { check_checkpoint(empty.path.string(), scene, p); });
    EXPECT_NE(e.find("manifest.json is missing"), std::string::npos) << e;
}

// --- the executable, killed mid-run -------------------------------------------------------

const char* propagate_exe() {
    const char* exe = std::getenv("VLF_PROPAGATE");
    return exe != nullptr ? exe : VLF_BINARY_DIR "/propagate/propagate";
}

int run_exe(const std::vector<std::string>& args) {
    std::string cmd = propagate_exe();
    for (const std::string& a : args) cmd += " '" + a + "'";
    cmd += " > /dev/null 2>&1";
    const int rc = std::system(cmd.c_str());
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

int checkpoint_cycle(const fs::path& dir) {
    std::ifstream in(dir / "manifest.json");
    if (!in) return 0;
    try {
        return nlohmann::json::parse(in).at("cycle").get<int>();
    } catch (const std::exception&) {
        return 0;
    }
}

// The bake's parts that depend on the propagation, by their checksums in the manifest
// (the manifest itself also holds timings, which differ).
nlohmann::json bake_files(const fs::path& bake) {
    std::ifstream in(bake / "manifest.json");
    nlohmann::json files = nlohmann::json::parse(in).at("files");
    return files;
}

TEST(CheckpointCli, KilledPropagateResumesToTheSameBake) {
    test::TempDir dir("checkpoint_kill");
    const std::string scene = test::source_path("tests/scenes/closed-mirror-room.json");
    const std::vector<std::string> common = {
        scene, "-l", "129", "-N", "32", "-m", "8", "-c", "5", "--perturbations", "1", "-q"};
    auto with = [&](std::vector<std::string> extra) {
        std::vector<std::string> a = common;
        a.insert(a.end(), extra.begin(), extra.end());
        return a;
    };
    const fs::path straight = dir.path / "straight.vlf", resumed = dir.path / "resumed.vlf";
    const fs::path ckpt = dir.path / "ckpt";
    ASSERT_EQ(run_exe(with({"-o", straight.string()})), 0);

    // Start it, wait for the first checkpoint, kill it without warning.
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        std::vector<std::string> a = with({"-o", resumed.string(), "--checkpoint", ckpt.string()});
        std::vector<char*> argv;
        argv.push_back(const_cast<char*>(propagate_exe()));
        for (std::string& s : a) argv.push_back(s.data());
        argv.push_back(nullptr);
        const int devnull = ::open("/dev/null", O_WRONLY);
        ::dup2(devnull, 1);
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (checkpoint_cycle(ckpt) < 1 && std::chrono::steady_clock::now() < deadline)
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << "propagate finished before it could be killed";
    const int at = checkpoint_cycle(ckpt);
    ASSERT_GE(at, 1);
    ASSERT_LT(at, 5);
    EXPECT_FALSE(fs::exists(resumed)) << "a killed run left a bake";

    // A mismatched resume is refused before any work: exit 2, one line.
    std::vector<std::string> other = with({"-o", resumed.string(), "--resume", ckpt.string()});
    other[2] = "33";  // -l
    EXPECT_EQ(run_exe(other), 2);
    ASSERT_EQ(run_exe(with({"-o", resumed.string(), "--resume", ckpt.string(), "--checkpoint",
                            ckpt.string()})),
              0);
    EXPECT_EQ(checkpoint_cycle(ckpt), 5);
    const nlohmann::json a = bake_files(straight), b = bake_files(resumed);
    EXPECT_EQ(a, b);
    EXPECT_FALSE(a.empty());
}

}  // namespace
}  // namespace vlf
