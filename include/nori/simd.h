// The few SIMD operations the BVH's box test and the triangle packets' test use, on four
// float lanes (SSE, every x86-64) or eight (AVX, when the build targets it), with the same
// names for both widths so that one template serves each.
#pragma once

#include <immintrin.h>

namespace nori {

template <int Lanes> struct SimdFloats;

template <> struct SimdFloats<4> {
    using Type = __m128;
    static constexpr int kLanes = 4;
    static Type broadcast(float value) { return _mm_set1_ps(value); }
    static Type zero() { return _mm_setzero_ps(); }
    static Type load(const float *p) { return _mm_load_ps(p); }
    static void store(float *p, Type a) { _mm_store_ps(p, a); }
    static Type add(Type a, Type b) { return _mm_add_ps(a, b); }
    static Type sub(Type a, Type b) { return _mm_sub_ps(a, b); }
    static Type mul(Type a, Type b) { return _mm_mul_ps(a, b); }
    static Type div(Type a, Type b) { return _mm_div_ps(a, b); }
    /// For a NaN, max and min return their second operand.
    static Type max(Type a, Type b) { return _mm_max_ps(a, b); }
    static Type min(Type a, Type b) { return _mm_min_ps(a, b); }
    static Type bitAnd(Type a, Type b) { return _mm_and_ps(a, b); }
    static Type bitOr(Type a, Type b) { return _mm_or_ps(a, b); }
    static Type bitXor(Type a, Type b) { return _mm_xor_ps(a, b); }
    /// ~a & b.
    static Type andNot(Type a, Type b) { return _mm_andnot_ps(a, b); }
    // Comparisons give all-ones lanes where true; ordered (false for a NaN) but for
    // notEqual, which a NaN satisfies.
    static Type less(Type a, Type b) { return _mm_cmplt_ps(a, b); }
    static Type lessEqualMask(Type a, Type b) { return _mm_cmple_ps(a, b); }
    static Type greater(Type a, Type b) { return _mm_cmpgt_ps(a, b); }
    static Type greaterEqual(Type a, Type b) { return _mm_cmpge_ps(a, b); }
    static Type equal(Type a, Type b) { return _mm_cmpeq_ps(a, b); }
    static Type notEqual(Type a, Type b) { return _mm_cmpneq_ps(a, b); }
    /// Bit i: lane i's sign bit (set in a true comparison's lane).
    static int bits(Type a) { return _mm_movemask_ps(a); }
    /// Bit i set: a[i] <= b[i] (false for a NaN).
    static int lessEqual(Type a, Type b) { return bits(lessEqualMask(a, b)); }
};

#ifdef __AVX__
template <> struct SimdFloats<8> {
    using Type = __m256;
    static constexpr int kLanes = 8;
    static Type broadcast(float value) { return _mm256_set1_ps(value); }
    static Type zero() { return _mm256_setzero_ps(); }
    static Type load(const float *p) { return _mm256_load_ps(p); }
    /// Lanes 0–3 from `low`, 4–7 from `high` (two 16-byte aligned arrays).
    static Type loadHalves(const float *low, const float *high) {
        return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(low)), _mm_load_ps(high), 1);
    }
    static void store(float *p, Type a) { _mm256_store_ps(p, a); }
    static Type add(Type a, Type b) { return _mm256_add_ps(a, b); }
    static Type sub(Type a, Type b) { return _mm256_sub_ps(a, b); }
    static Type mul(Type a, Type b) { return _mm256_mul_ps(a, b); }
    static Type div(Type a, Type b) { return _mm256_div_ps(a, b); }
    static Type max(Type a, Type b) { return _mm256_max_ps(a, b); }
    static Type min(Type a, Type b) { return _mm256_min_ps(a, b); }
    static Type bitAnd(Type a, Type b) { return _mm256_and_ps(a, b); }
    static Type bitOr(Type a, Type b) { return _mm256_or_ps(a, b); }
    static Type bitXor(Type a, Type b) { return _mm256_xor_ps(a, b); }
    static Type andNot(Type a, Type b) { return _mm256_andnot_ps(a, b); }
    static Type less(Type a, Type b) { return _mm256_cmp_ps(a, b, _CMP_LT_OQ); }
    static Type lessEqualMask(Type a, Type b) { return _mm256_cmp_ps(a, b, _CMP_LE_OQ); }
    static Type greater(Type a, Type b) { return _mm256_cmp_ps(a, b, _CMP_GT_OQ); }
    static Type greaterEqual(Type a, Type b) { return _mm256_cmp_ps(a, b, _CMP_GE_OQ); }
    static Type equal(Type a, Type b) { return _mm256_cmp_ps(a, b, _CMP_EQ_OQ); }
    static Type notEqual(Type a, Type b) { return _mm256_cmp_ps(a, b, _CMP_NEQ_UQ); }
    static int bits(Type a) { return _mm256_movemask_ps(a); }
    static int lessEqual(Type a, Type b) { return bits(lessEqualMask(a, b)); }
};
#endif

} // namespace nori
