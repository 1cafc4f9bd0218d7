#include "vlf/transport/ledger.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace vlf {

NumericalLoss& NumericalLoss::operator+=(const NumericalLoss& o) {
    sealed += o.sealed;
    empty_footprint += o.empty_footprint;
    grazing_mirror += o.grazing_mirror;
    subpixel_mirror += o.subpixel_mirror;
    rounding += o.rounding;
    cut_beam += o.cut_beam;
    return *this;
}

NumericalLoss NumericalLoss::operator*(double s) const {
    return {sealed * s,          empty_footprint * s, grazing_mirror * s,
            subpixel_mirror * s, rounding * s,        cut_beam * s};
}

double LedgerEntry::relative_error() const {
    double worst = 0.0;
    for (int c = 0; c < 3; ++c) {
        if (emitted[c] <= 0.0) continue;
        const double r = emitted[c] - absorbed[c] - absorbed_back[c] - lost.total()[c] -
                         escaped[c] - unshot[c] - deferred[c];
        worst = std::max(worst, std::abs(r) / emitted[c]);
    }
    return worst;
}

nlohmann::json to_json(const LedgerEntry& e) {
    auto v = [](const Rgb& c) { return nlohmann::json{c.x, c.y, c.z}; };
    const nlohmann::json lost = {{"total", v(e.lost.total())},
                                 {"sealed", v(e.lost.sealed)},
                                 {"empty_footprint", v(e.lost.empty_footprint)},
                                 {"grazing_mirror", v(e.lost.grazing_mirror)},
                                 {"subpixel_mirror", v(e.lost.subpixel_mirror)},
                                 {"rounding", v(e.lost.rounding)},
                                 {"cut_beam", v(e.lost.cut_beam)}};
    return {{"cycle", e.cycle},
            {"emitted", v(e.emitted)},
            {"absorbed", v(e.absorbed)},
            {"absorbed_back_sides", v(e.absorbed_back)},
            {"lost", lost},
            {"escaped", v(e.escaped)},
            {"unshot", v(e.unshot)},
            {"deferred", v(e.deferred)},
            {"relative_error", e.relative_error()}};
}

std::string format_ledger(const LedgerEntry& e) {
    auto lum = [](const Rgb& c) { return (c.x + c.y + c.z) / 3.0; };
    const double em = std::max(lum(e.emitted), 1e-300);
    return fmt::format(
        "cycle {:3d}  emitted {:.6g}  absorbed {:5.1f}% (back sides {:.2f}%)  lost {:.1e}%  "
        "escaped {:5.1f}%  unshot {:5.1f}%  deferred {:5.1f}%  balance error {:.1e}",
        e.cycle, lum(e.emitted), 100 * lum(e.absorbed + e.absorbed_back) / em,
        100 * lum(e.absorbed_back) / em, 100 * lum(e.lost.total()) / em, 100 * lum(e.escaped) / em,
        100 * lum(e.unshot) / em, 100 * lum(e.deferred) / em, e.relative_error());
}

}  // namespace vlf
