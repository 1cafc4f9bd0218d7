// ledger.hpp — the energy ledger (DESIGN §5): per channel, in double precision, after
// every cycle: emitted = absorbed + escaped + unshot + deferred. Power in watts in the
// scene's own units (radiance x user area x sr).
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "vlf/math.hpp"

namespace vlf {

struct LedgerEntry {
    int cycle = 0;
    Rgb emitted{0.0};   // loaded by emitters so far
    Rgb absorbed{0.0};  // by surfaces (1 - rho_d - rho_s), back faces, dropped reflections
    Rgb escaped{0.0};   // left the scene (open scenes)
    Rgb unshot{0.0};    // in current texture maps and unshot radiance maps, to be shot
    Rgb deferred{0.0};  // held back by deferred surfaces (VLF §4.5)
    // |emitted - absorbed - escaped - unshot - deferred| / emitted, worst channel.
    double relative_error() const;
};

nlohmann::json to_json(const LedgerEntry& e);
std::string format_ledger(const LedgerEntry& e);

}  // namespace vlf
