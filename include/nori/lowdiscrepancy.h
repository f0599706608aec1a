// Low-discrepancy sequences: deterministic points that cover [0, 1)^n more evenly than
// random ones (PBR 4th ed. §8.6).
#pragma once

#include <cstdint>

namespace nori {

/// The radical inverse of `index` in a prime `base`: its digits mirrored about the radix
/// point (van der Corput; PBR 4th ed. §8.6.1). Bases 2, 3, 5, ... make the Halton points.
double radicalInverse(int base, uint64_t index);

} // namespace nori
