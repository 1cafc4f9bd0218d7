// transport_state.cpp — the transport's state between two cycles, out to a checkpoint's
// state file and back (transport.hpp save_state/load_state, checkpoint.hpp). The sections
// are written and read in one order; every length is checked against this run's maps.
#include "vlf/transport/state_io.hpp"
#include "vlf/transport/transport_internal.hpp"

namespace vlf {

namespace {

// A pass's per-direction chart lists, flattened: counts, then charts and cosines.
void save_charts(StateWriter& out, const std::vector<std::vector<ChartCosine>>& charts) {
    std::vector<uint32_t> count, chart;
    std::vector<double> cosine;
    for (const auto& list : charts) {
        count.push_back(uint32_t(list.size()));
        for (const ChartCosine& cc : list) {
            chart.push_back(cc.chart);
            cosine.push_back(cc.cosine);
        }
    }
    out.array("pass.count", count);
    out.array("pass.chart", chart);
    out.array("pass.cosine", cosine);
}

void load_charts(StateReader& in, std::vector<std::vector<ChartCosine>>& charts, int64_t dirs,
                 size_t chart_count) {
    std::vector<uint32_t> count, chart;
    std::vector<double> cosine;
    in.array("pass.count", count);
    if (!count.empty() && int64_t(count.size()) != dirs)
        throw Error("checkpoint: section 'pass.count' does not match the directions");
    in.array("pass.chart", chart);
    in.array("pass.cosine", cosine, int64_t(chart.size()));
    charts.assign(count.size(), {});
    size_t k = 0;
    for (size_t d = 0; d < count.size(); ++d)
        for (uint32_t i = 0; i < count[d]; ++i, ++k) {
            if (k >= chart.size() || chart[k] >= chart_count)
                throw Error("checkpoint: section 'pass.chart' is inconsistent");
            charts[d].push_back({chart[k], cosine[k]});
        }
    if (k != chart.size()) throw Error("checkpoint: section 'pass.chart' is inconsistent");
}

}  // namespace

void Transport::save_state(StateWriter& out) const {
    // The maps of every direction: with several ranks, rank 0 after gather_radiance_maps.
    for (const RadianceMaps* maps : {&m_spec, &m_other})
        if (maps->first != 0 || maps->last != m_dirs.size())
            throw Error("checkpoint: the radiance maps are not held whole (gather them first)");
    out.array("tex.current", m_tex.current);
    out.array("tex.next", m_tex.next);
    out.array("tex.total", m_tex.total);
    out.array("spec.unshot", m_spec.unshot);
    out.array("spec.unshot_nx", m_spec.unshot_next);
    out.array("spec.total", m_spec.total);
    out.array("other.total", m_other.total);
    out.array("deferred", m_deferred);
    out.array("light_next", m_light_next);
    out.value("light_stats", m_light_stats);
    out.value("caustic_stats", m_caustic_stats);
    out.array("ledger", m_ledger);
    out.value("running", m_running);
    const uint64_t passes = m_passes.size();
    out.value("passes", passes);
    for (const Pass& p : m_passes) {
        const uint8_t known = p.norms_known ? 1 : 0;
        out.value("pass.known", known);
        out.array("pass.send_norm", p.send_norm);
        save_charts(out, p.charts);
    }
}

void Transport::load_state(StateReader& in) {
    const auto n = [](const auto& v) { return int64_t(v.size()); };
    in.array("tex.current", m_tex.current, n(m_tex.current));
    in.array("tex.next", m_tex.next, n(m_tex.next));
    in.array("tex.total", m_tex.total, n(m_tex.total));
    // The file holds every direction's rays; this rank reads its own (RadianceMaps::first,
    // last), so the state resumes on any number of ranks.
    const auto part = [&](const char* tag, std::vector<RgbF>& v, const RadianceMaps& maps) {
        in.array_part(tag, v, maps.rays(), maps.base);
    };
    part("spec.unshot", m_spec.unshot, m_spec);
    part("spec.unshot_nx", m_spec.unshot_next, m_spec);
    part("spec.total", m_spec.total, m_spec);
    part("other.total", m_other.total, m_other);
    in.array("deferred", m_deferred, n(m_deferred));
    in.array("light_next", m_light_next);
    if (!m_light_next.empty() && m_light_next.size() != m_tex.texels())
        throw Error("checkpoint: section 'light_next' does not match the texture maps");
    in.value("light_stats", m_light_stats);
    in.value("caustic_stats", m_caustic_stats);
    in.array("ledger", m_ledger);
    in.value("running", m_running);
    uint64_t passes = 0;
    in.value("passes", passes);
    if (passes != m_passes.size())
        throw Error("checkpoint: the number of passes does not match the parameters");
    for (Pass& p : m_passes) {
        uint8_t known = 0;
        in.value("pass.known", known);
        p.norms_known = known != 0;
        in.array("pass.send_norm", p.send_norm, n(p.send_norm));
        load_charts(in, p.charts, m_dirs.size(), m_scene.charts.size());
    }
    in.finish();
    // Perturbed geometry is released after the last cycle that perturbs; none is cached
    // here yet, so there is nothing to release (the cache fills as cycles run).
}

}  // namespace vlf
