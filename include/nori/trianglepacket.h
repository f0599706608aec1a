// Four triangles tested against one ray at once with SSE: the first half of the
// watertight test (triangle.h; Woop, Benthin and Wald, JCGT 2013) — shear into ray space,
// edge functions, the sign test and the t range — computed with the same floating-point
// operations in the same order as the scalar test, lane by lane. It keeps every
// triangle the scalar test could accept (a lane whose edge function is zero goes on,
// since the scalar test re-decides it in double) and rejects the rest; the few that pass
// are confirmed by the scalar test, which alone sets t and the barycentrics. Hits are
// therefore bit-identical to the scalar test's. This needs the compiler to keep each
// operation as written: the project builds with -ffp-contract=off (no fused a·b + c).
#pragma once

#include <nori/triangle.h>

#include <immintrin.h>

namespace nori {

/// Vertices of four triangles as structures of arrays: v[vertex][axis][lane]. A lane
/// that holds no triangle has NaN coordinates.
struct alignas(16) TrianglePacket {
    static constexpr int kWidth = 4;
    float v[3][3][kWidth];

    Point3f vertex(int lane, int index) const {
        return Point3f(v[index][0][lane], v[index][1][lane], v[index][2][lane]);
    }
    void set(int lane, const Point3f &p0, const Point3f &p1, const Point3f &p2) {
        for (int axis = 0; axis < 3; ++axis) {
            v[0][axis][lane] = p0[axis];
            v[1][axis][lane] = p1[axis];
            v[2][axis][lane] = p2[axis];
        }
    }
    void clear(int lane) {
        const float nan = std::numeric_limits<float>::quiet_NaN();
        set(lane, Point3f::Constant(nan), Point3f::Constant(nan), Point3f::Constant(nan));
    }
    /// Bit i set: lane i holds a triangle.
    int triangleLanes() const {
        const __m128 x = _mm_load_ps(v[0][0]);
        return _mm_movemask_ps(_mm_cmpord_ps(x, x));
    }
};

/// A WatertightRay's permutation and shear, broadcast to four lanes.
struct WatertightRay4 {
    const WatertightRay &ray;
    __m128 ox, oy, oz, sx, sy, sz;

    explicit WatertightRay4(const WatertightRay &r)
        : ray(r), ox(_mm_set1_ps(r.o[r.kx])), oy(_mm_set1_ps(r.o[r.ky])),
          oz(_mm_set1_ps(r.o[r.kz])), sx(_mm_set1_ps(r.sx)), sy(_mm_set1_ps(r.sy)),
          sz(_mm_set1_ps(r.sz)) {}

    /// Bit i set: the scalar test may hit triangle i of the packet with t <= tCull.
    /// Triangles it would reject beyond tCull are culled with a margin of 1e-5 relative
    /// (rounding of t·det, a few ulps), so the scalar test decides ties with tCull.
    int candidates(const TrianglePacket &packet, float tCull) const {
        __m128 x[3], y[3], z[3];
        for (int i = 0; i < 3; ++i) {
            // As in intersectTriangle: a = p0 − o, then ax = a[kx] + sx·a[kz], ...
            z[i] = _mm_sub_ps(_mm_load_ps(packet.v[i][ray.kz]), oz);
            x[i] =
                _mm_add_ps(_mm_sub_ps(_mm_load_ps(packet.v[i][ray.kx]), ox), _mm_mul_ps(sx, z[i]));
            y[i] =
                _mm_add_ps(_mm_sub_ps(_mm_load_ps(packet.v[i][ray.ky]), oy), _mm_mul_ps(sy, z[i]));
        }
        const __m128 e0 = _mm_sub_ps(_mm_mul_ps(x[1], y[2]), _mm_mul_ps(y[1], x[2]));
        const __m128 e1 = _mm_sub_ps(_mm_mul_ps(x[2], y[0]), _mm_mul_ps(y[2], x[0]));
        const __m128 e2 = _mm_sub_ps(_mm_mul_ps(x[0], y[1]), _mm_mul_ps(y[0], x[1]));
        const __m128 zero = _mm_setzero_ps();
        const __m128 anyNegative = _mm_or_ps(
            _mm_or_ps(_mm_cmplt_ps(e0, zero), _mm_cmplt_ps(e1, zero)), _mm_cmplt_ps(e2, zero));
        const __m128 anyPositive = _mm_or_ps(
            _mm_or_ps(_mm_cmpgt_ps(e0, zero), _mm_cmpgt_ps(e1, zero)), _mm_cmpgt_ps(e2, zero));
        const __m128 anyZero = _mm_or_ps(_mm_or_ps(_mm_cmpeq_ps(e0, zero), _mm_cmpeq_ps(e1, zero)),
                                         _mm_cmpeq_ps(e2, zero));
        const __m128 det = _mm_add_ps(_mm_add_ps(e0, e1), e2);
        const __m128 tScaled = _mm_add_ps(
            _mm_add_ps(_mm_mul_ps(e0, _mm_mul_ps(sz, z[0])), _mm_mul_ps(e1, _mm_mul_ps(sz, z[1]))),
            _mm_mul_ps(e2, _mm_mul_ps(sz, z[2])));
        // With the sign of det moved onto tScaled (exact): 0 < t·|det| <= tCull·|det|.
        const __m128 signBit = _mm_set1_ps(-0.0f);
        const __m128 detSign = _mm_and_ps(det, signBit);
        const __m128 tSigned = _mm_xor_ps(tScaled, detSign);
        const __m128 detAbs = _mm_andnot_ps(signBit, det);
        const __m128 bound = _mm_mul_ps(_mm_set1_ps(tCull * (1.0f + 1e-5f)), detAbs);
        // A denormal |det| has no relative precision: such a lane goes on.
        const __m128 tiny = _mm_cmplt_ps(detAbs, _mm_set1_ps(std::numeric_limits<float>::min()));
        const __m128 inRange =
            _mm_and_ps(_mm_cmpgt_ps(tSigned, zero), _mm_or_ps(_mm_cmple_ps(tSigned, bound), tiny));
        const __m128 sameSign = _mm_andnot_ps(_mm_and_ps(anyNegative, anyPositive), inRange);
        return _mm_movemask_ps(_mm_or_ps(_mm_and_ps(sameSign, _mm_cmpneq_ps(det, zero)), anyZero));
    }
};

} // namespace nori
