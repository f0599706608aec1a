// Four triangles tested against one ray at once with SSE: the whole watertight test
// (triangle.h; Woop, Benthin and Wald, JCGT 2013) — shear into ray space, edge functions,
// the sign test, the t range, the division and PBR 4th ed.'s t > 0 error bound — computed
// with the same floating-point operations in the same order as the scalar test, lane by
// lane, so a lane's t and barycentrics equal the scalar test's bit for bit. A lane whose
// edge function is zero is left undecided, since the scalar test re-evaluates it in
// double. This needs the compiler to keep each operation as written: the project builds
// with -ffp-contract=off (no fused a·b + c).
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

/// What the packet test finds for its four lanes.
struct PacketHits {
    int hit;       ///< bit i: triangle i is hit within [mint, maxt], at t[i]
    int undecided; ///< bit i: an edge function is zero; the scalar test decides in double
    alignas(16) float t[4], b1[4], b2[4];
};

/// A WatertightRay's permutation and shear, broadcast to four lanes.
struct WatertightRay4 {
    const WatertightRay &ray;
    __m128 ox, oy, oz, sx, sy, sz;

    explicit WatertightRay4(const WatertightRay &r)
        : ray(r), ox(_mm_set1_ps(r.o[r.kx])), oy(_mm_set1_ps(r.o[r.ky])),
          oz(_mm_set1_ps(r.o[r.kz])), sx(_mm_set1_ps(r.sx)), sy(_mm_set1_ps(r.sy)),
          sz(_mm_set1_ps(r.sz)) {}

    /// The watertight test on the packet's four triangles, with the scalar test's
    /// operations in its order, lane by lane: a hit lane's t and barycentrics equal the
    /// scalar test's bit for bit. A lane with a zero edge function is left undecided: the
    /// scalar test re-evaluates it in double.
    PacketHits intersect(const TrianglePacket &packet) const {
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
        const __m128 sAz = _mm_mul_ps(sz, z[0]), sBz = _mm_mul_ps(sz, z[1]),
                     sCz = _mm_mul_ps(sz, z[2]);
        const __m128 tScaled =
            _mm_add_ps(_mm_add_ps(_mm_mul_ps(e0, sAz), _mm_mul_ps(e1, sBz)), _mm_mul_ps(e2, sCz));
        // The range test 0 < t <= maxt before the division, with the sign of det moved onto
        // tScaled (exact): 0 < tScaled·sign(det) <= maxt·|det|.
        const __m128 signBit = _mm_set1_ps(-0.0f);
        const __m128 tSigned = _mm_xor_ps(tScaled, _mm_and_ps(det, signBit));
        const __m128 detAbs = _mm_andnot_ps(signBit, det);
        const __m128 maxt = _mm_set1_ps(ray.maxt);
        __m128 accept = _mm_andnot_ps(_mm_and_ps(anyNegative, anyPositive),
                                      _mm_cmplt_ps(detAbs, _mm_set1_ps(kInfinity))); // finite
        accept = _mm_and_ps(accept, _mm_cmpneq_ps(det, zero));
        accept = _mm_and_ps(accept, _mm_cmpgt_ps(tSigned, zero));
        accept = _mm_and_ps(accept, _mm_cmple_ps(tSigned, _mm_mul_ps(maxt, detAbs)));

        const __m128 invDet = _mm_div_ps(_mm_set1_ps(1.0f), det);
        const __m128 tHit = _mm_mul_ps(tScaled, invDet);
        // The conservative bound on t's error (PBR 4th ed. §6.8.7), as in the scalar test.
        auto absMax = [&](__m128 a, __m128 b, __m128 c) {
            return _mm_max_ps(_mm_max_ps(_mm_andnot_ps(signBit, a), _mm_andnot_ps(signBit, b)),
                              _mm_andnot_ps(signBit, c));
        };
        const __m128 maxZt = absMax(sAz, sBz, sCz);
        const __m128 maxXt = absMax(x[0], x[1], x[2]);
        const __m128 maxYt = absMax(y[0], y[1], y[2]);
        const __m128 deltaZ = _mm_mul_ps(_mm_set1_ps(gammaBound(3)), maxZt);
        const __m128 deltaX = _mm_mul_ps(_mm_set1_ps(gammaBound(5)), _mm_add_ps(maxXt, maxZt));
        const __m128 deltaY = _mm_mul_ps(_mm_set1_ps(gammaBound(5)), _mm_add_ps(maxYt, maxZt));
        const __m128 deltaE = _mm_mul_ps(
            _mm_set1_ps(2.0f),
            _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(_mm_set1_ps(gammaBound(2)), maxXt), maxYt),
                                  _mm_mul_ps(deltaY, maxXt)),
                       _mm_mul_ps(deltaX, maxYt)));
        const __m128 maxE = absMax(e0, e1, e2);
        const __m128 errorSum =
            _mm_add_ps(_mm_add_ps(_mm_mul_ps(_mm_mul_ps(_mm_set1_ps(gammaBound(3)), maxE), maxZt),
                                  _mm_mul_ps(deltaE, maxZt)),
                       _mm_mul_ps(deltaZ, maxE));
        const __m128 deltaT =
            _mm_mul_ps(_mm_mul_ps(_mm_set1_ps(3.0f), errorSum), _mm_andnot_ps(signBit, invDet));
        accept = _mm_and_ps(accept, _mm_cmpgt_ps(tHit, deltaT));
        accept = _mm_and_ps(accept, _mm_cmpge_ps(tHit, _mm_set1_ps(ray.mint)));
        accept = _mm_and_ps(accept, _mm_cmple_ps(tHit, maxt));

        PacketHits hits;
        hits.undecided = _mm_movemask_ps(anyZero);
        hits.hit = _mm_movemask_ps(accept) & ~hits.undecided;
        _mm_store_ps(hits.t, tHit);
        _mm_store_ps(hits.b1, _mm_mul_ps(e1, invDet));
        _mm_store_ps(hits.b2, _mm_mul_ps(e2, invDet));
        return hits;
    }
};

} // namespace nori
