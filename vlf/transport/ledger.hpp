// ledger.hpp — the energy ledger (DESIGN §5): per channel, in double precision, after
// every cycle: emitted = absorbed + absorbed_back + lost + escaped + unshot + deferred.
// Power in watts in the
// scene's own units (radiance x user area x sr).
#pragma once

#include <nlohmann/json.hpp>
#include <vector>

#include "vlf/core/math.hpp"

namespace vlf {

// Power that left the transport through the discretisation rather than through a
// material or out of the scene: light sent to the wrong place shows up here instead of
// hiding in "absorbed" (docs/propagation.md §6).
struct NumericalLoss {
    Rgb sealed{0.0};           // light sent into a ray shut by a back face in contact
                               // (exchange.hpp kSealed; only mirrors' light can be)
    Rgb empty_footprint{0.0};  // a beam with no area on the face its centre hit
    Rgb grazing_mirror{0.0};   // reflected light with no PSF direction able to carry it
    Rgb subpixel_mirror{0.0};  // a mirror's unshot light with no ray on the finer exchange
                               // grid (super-sampling) to leave by
    Rgb rounding{0.0};         // reflected power that single-precision radiance maps
                               // did not keep (deposited minus stored; either sign)
    Rgb cut_beam{0.0};         // a light's beam reflected from beyond its mirror's rim (a beam
                               // across the rim, finer than an edge is resolved; light_beams.hpp);
                               // a beam's or a lamp caustic ray's branch split by glass below
                               // 10^-3 of its power; light handed to the lamp caustics' shot in
                               // a channel its rays did not find (lamp_caustics.hpp)
    Rgb total() const {
        return sealed + empty_footprint + grazing_mirror + subpixel_mirror + rounding + cut_beam;
    }
    NumericalLoss& operator+=(const NumericalLoss& o);
    NumericalLoss operator*(double s) const;
};

struct LedgerEntry {
    int cycle = 0;
    Rgb emitted{0.0};   // loaded by emitters so far
    Rgb absorbed{0.0};  // by materials: (1 - rho_d - rho_s) of what surfaces receive
    // by the black back sides of one-sided faces: light whose next surface along its ray
    // shows its back at a distance (open geometry; the path tracer absorbs there too). 0 in
    // a closed, watertight scene without interpenetration.
    Rgb absorbed_back{0.0};
    NumericalLoss lost;  // by the discretisation, by cause
    Rgb escaped{0.0};    // left the scene (open scenes)
    Rgb unshot{0.0};     // in current texture maps and unshot radiance maps, to be shot
    Rgb deferred{0.0};   // held back by deferred surfaces (VLF §4.5)
    // |emitted - absorbed - absorbed_back - lost - escaped - unshot - deferred| / emitted,
    // worst channel.
    double relative_error() const;
};

nlohmann::json to_json(const LedgerEntry& e);
std::string format_ledger(const LedgerEntry& e);

}  // namespace vlf
