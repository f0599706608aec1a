// Hashing integers into well-mixed bits: how samplers make a pixel's sample stream a
// pure function of (seed, pixel, sample index, dimension) without storing any state.
#pragma once

#include <cstdint>

namespace nori {

/// A 64-bit finaliser with full avalanche (Stafford's "Mix13" variant of MurmurHash3's
/// fmix64, the one SplitMix64 uses).
constexpr uint64_t mixBits(uint64_t value) {
    value = (value ^ (value >> 30)) * 0xbf58476d1ce4e5b9ULL;
    value = (value ^ (value >> 27)) * 0x94d049bb133111ebULL;
    return value ^ (value >> 31);
}

/// Hashes several integers into one 64-bit value (each folded in after mixing the last).
template <typename... Values> constexpr uint64_t hashValues(Values... values) {
    uint64_t hash = 0x9e3779b97f4a7c15ULL; // 2^64 / golden ratio: any odd start will do
    ((hash = mixBits(hash ^ static_cast<uint64_t>(values))), ...);
    return hash;
}

} // namespace nori
