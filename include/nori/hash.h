// Hashing integers into well-mixed bits: how samplers make a pixel's sample stream a
// pure function of (seed, pixel, sample index, dimension) without storing any state.
#pragma once

#include <cstdint>
#include <cstring>
#include <string_view>

namespace nori {

/// A 64-bit finaliser with full avalanche (Stafford's "Mix13" variant of MurmurHash3's
/// fmix64, the one SplitMix64 uses).
constexpr uint64_t mixBits(uint64_t value) {
    value = (value ^ (value >> 30)) * 0xbf58476d1ce4e5b9ULL;
    value = (value ^ (value >> 27)) * 0x94d049bb133111ebULL;
    return value ^ (value >> 31);
}

/// Folds more integers into a hash: hashMore(hashValues(a, b), c) == hashValues(a, b, c),
/// so a prefix used by many hashes (a pixel's, for all its dimensions) is hashed once.
template <typename... Values> constexpr uint64_t hashMore(uint64_t hash, Values... values) {
    ((hash = mixBits(hash ^ static_cast<uint64_t>(values))), ...);
    return hash;
}

/// Hashes several integers into one 64-bit value (each folded in after mixing the last).
template <typename... Values> constexpr uint64_t hashValues(Values... values) {
    // The start, 2^64 / golden ratio: any odd constant will do.
    return hashMore(0x9e3779b97f4a7c15ULL, values...);
}

/// Hashes floats by their bit patterns (so that +0 and −0 differ, as the points they are
/// coordinates of may).
template <typename... Floats> uint64_t hashFloats(Floats... values) {
    auto bitsOf = [](float value) {
        uint32_t bits;
        std::memcpy(&bits, &value, sizeof(bits));
        return bits;
    };
    return hashValues(bitsOf(values)...);
}

/// The top 24 bits of a hash as a float uniform in [0, 1).
constexpr float hashToUnitFloat(uint64_t hash) {
    return static_cast<float>(hash >> 40) * 0x1p-24f;
}

/// A 64-bit digest of a byte string, 8 bytes at a time through mixBits (with the length
/// folded in, so a trailing zero byte changes it). Not cryptographic: it tells files apart
/// (a render split over machines checks they read the same scene), it does not resist
/// an adversary.
inline uint64_t hashBytes(std::string_view bytes) {
    uint64_t hash = hashValues(bytes.size());
    size_t offset = 0;
    for (; offset + 8 <= bytes.size(); offset += 8) {
        uint64_t word;
        std::memcpy(&word, bytes.data() + offset, 8);
        hash = mixBits(hash ^ word);
    }
    uint64_t tail = 0;
    if (offset < bytes.size()) // (memcpy from an empty view's nullptr is undefined)
        std::memcpy(&tail, bytes.data() + offset, bytes.size() - offset);
    return mixBits(hash ^ tail);
}

} // namespace nori
