// Direction-set lookups: nearest() and enclosing() per call, both schemes, against a linear
// nearest-direction scan (DESIGN §4: lookups must be constant time).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "vlf/field/direction_set.hpp"

namespace {

using vlf::DirectionScheme;
using vlf::DirectionSet;
using vlf::Vec3;

// A fixed pool of uniform directions on the sphere (both hemispheres).
const std::vector<Vec3>& queries() {
    static const std::vector<Vec3> q = [] {
        std::mt19937_64 rng(42);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        std::vector<Vec3> out(1 << 14);
        for (Vec3& d : out) {
            const double z = 2.0 * u(rng) - 1.0, phi = 2.0 * vlf::kPi * u(rng);
            const double s = std::sqrt(1.0 - z * z);
            d = Vec3(s * std::cos(phi), s * std::sin(phi), z);
        }
        return out;
    }();
    return q;
}

DirectionScheme scheme_of(int64_t v) {
    return v == 0 ? DirectionScheme::Octahedral : DirectionScheme::EqualArea;
}

void BM_DirectionNearest(benchmark::State& state) {
    const DirectionSet ds(static_cast<int>(state.range(0)), scheme_of(state.range(1)));
    const auto& q = queries();
    size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(ds.nearest(q[i]));
        i = (i + 1) & (q.size() - 1);
    }
    state.SetLabel(vlf::to_string(ds.scheme()));
}

void BM_DirectionEnclosing(benchmark::State& state) {
    const DirectionSet ds(static_cast<int>(state.range(0)), scheme_of(state.range(1)));
    const auto& q = queries();
    size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(ds.enclosing(q[i]));
        i = (i + 1) & (q.size() - 1);
    }
    state.SetLabel(vlf::to_string(ds.scheme()));
}

// The baseline: argmax |dot| over all lines.
void BM_DirectionNearestBruteForce(benchmark::State& state) {
    const DirectionSet ds(static_cast<int>(state.range(0)), scheme_of(state.range(1)));
    const auto& q = queries();
    size_t i = 0;
    for (auto _ : state) {
        int best = -1;
        double best_dot = -1.0;
        for (int k = 0; k < ds.size(); ++k) {
            const double c = std::abs(glm::dot(q[i], ds.direction(k)));
            if (c > best_dot) {
                best_dot = c;
                best = k;
            }
        }
        benchmark::DoNotOptimize(best);
        i = (i + 1) & (q.size() - 1);
    }
    state.SetLabel(vlf::to_string(ds.scheme()));
}

// Construction cost (tables for both lookups included).
void BM_DirectionSetBuild(benchmark::State& state) {
    for (auto _ : state) {
        const DirectionSet ds(static_cast<int>(state.range(0)), scheme_of(state.range(1)));
        benchmark::DoNotOptimize(ds.size());
    }
}

}  // namespace

BENCHMARK(BM_DirectionNearest)->ArgsProduct({{513, 8193}, {0, 1}});
BENCHMARK(BM_DirectionEnclosing)->ArgsProduct({{513, 8193}, {0, 1}});
BENCHMARK(BM_DirectionNearestBruteForce)->ArgsProduct({{513}, {0, 1}});
BENCHMARK(BM_DirectionSetBuild)->ArgsProduct({{513, 8193}, {0, 1}})->Unit(benchmark::kMillisecond);
