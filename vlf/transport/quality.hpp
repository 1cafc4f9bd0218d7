// quality.hpp — propagation presets: `propagate --quality draft|preview|final|reference`
// picks the field (l, N, m), the stop rule, the refinements (perturbations, filter,
// super-sampling) and the default texel density together, so a user states the quality
// wanted rather than nine numbers. Options given explicitly on the command line win over
// the preset; a scene file's settings.texel_size wins over the preset's texel density.
//
// Cycles: a preset propagates until the light still to be shot (unshot + deferred) falls
// under a fraction of the emission, `stop_unshot`, with `cycles` as a cap. The remainder
// stays in the ledger as unshot and is not guessed at: it can change any radiance by at
// most stop_unshot / (1 - rho_max) of the emission's share, below each preset's error
// target by a factor of ten or more (docs/quality.md).
#pragma once

#include <string>

#include "vlf/transport/parameters.hpp"

namespace vlf {

enum class Quality { Draft, Preview, Final, Reference };

// Throws ParameterError ("--quality: ...") for an unknown name.
Quality quality_from_string(const std::string& name);
std::string to_string(Quality q);
// The preset's parameters, on top of the defaults.
PropagateParams quality_params(Quality q);

}  // namespace vlf
