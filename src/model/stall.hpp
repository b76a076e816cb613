// How much of the drive the random forces can hold back (docs/model.md §8).
#pragma once

#include "slidespec/parameters.hpp"

namespace slidespec {

/// The largest total random force the touching contacts can hold against the drive [N]:
/// each contact's force is uniform over a width alpha f_kin about its mean, so half of
/// that, summed. A constant force can stall the block where this reaches F_drive - F_kin.
double stall_resistance(const Parameters& p);

}  // namespace slidespec
