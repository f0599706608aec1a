// Triangles tested against one ray four at a time (SSE, one packet) or eight (AVX, two
// packets): the whole watertight test (triangle.h; Woop, Benthin and Wald, JCGT 2013) —
// shear into ray space, edge functions, the sign test, the t range, the division and PBR
// 4th ed.'s t > 0 error bound — computed with the same floating-point operations in the
// same order as the scalar test, lane by lane, so a lane's t and barycentrics equal the
// scalar test's bit for bit. A lane whose edge function is zero, or whose t is positive
// but within its error bound, is left undecided, since the scalar test re-evaluates it in
// double. This needs the compiler to keep each
// operation as written: the project builds with -ffp-contract=off (no fused a·b + c).
#pragma once

#include <nori/simd.h>
#include <nori/triangle.h>

#include <cstddef>
#include <cstdint>
#include <limits>

namespace nori {

/// Four leaf slots on three cache lines: the vertices of their triangles as structures
/// of arrays, v[vertex][axis][lane] (a lane that holds no triangle has NaN coordinates),
/// and every slot's shape and primitive index. The ids share the third line with the
/// last vertex's z, which the test always reads: a closest hit then costs no cache miss
/// beyond its leaf (a separate id array cost incoherent rays a fifth of their speed).
struct alignas(64) TrianglePacket {
    static constexpr int kWidth = 4;
    /// The ids of a slot without a primitive.
    static constexpr uint32_t kNoIndex = 0xFFFFFFFFu;
    float v[3][3][kWidth];
    uint32_t shapeIndex[kWidth];
    uint32_t primIndex[kWidth];
    uint32_t padding[kWidth];

    Point3f vertex(int lane, int index) const {
        return Point3f(v[index][0][lane], v[index][1][lane], v[index][2][lane]);
    }
    void setTriangle(int lane, const Point3f &p0, const Point3f &p1, const Point3f &p2) {
        for (int axis = 0; axis < 3; ++axis) {
            v[0][axis][lane] = p0[axis];
            v[1][axis][lane] = p1[axis];
            v[2][axis][lane] = p2[axis];
        }
    }
    /// Empties the lane: no triangle, no ids.
    void clear(int lane) {
        const float nan = std::numeric_limits<float>::quiet_NaN();
        setTriangle(lane, Point3f::Constant(nan), Point3f::Constant(nan), Point3f::Constant(nan));
        shapeIndex[lane] = primIndex[lane] = padding[lane] = kNoIndex;
    }
    /// Bit i set: lane i holds a triangle.
    int triangleLanes() const {
        const __m128 x = _mm_load_ps(v[0][0]);
        return _mm_movemask_ps(_mm_cmpord_ps(x, x));
    }
};
static_assert(sizeof(TrianglePacket) == 192 && offsetof(TrianglePacket, shapeIndex) / 64 ==
                                                   offsetof(TrianglePacket, v[2][2]) / 64,
              "a packet fills three cache lines, its ids on the line of the last z");

/// What the packet test finds for its Lanes lanes (lane i of the second packet is lane
/// 4 + i).
template <int Lanes> struct PacketHits {
    int hit;       ///< bit i: triangle i is hit within [mint, maxt], at t[i]
    int undecided; ///< bit i: an edge function is zero or t is within its error bound of 0;
                   ///< the scalar test decides in double
    alignas(32) float t[Lanes], b1[Lanes], b2[Lanes];
};

/// A WatertightRay's permutation and shear, broadcast to the lanes of one packet or two.
template <int Lanes> struct WatertightRayPacket {
    using Simd = SimdFloats<Lanes>;
    using Float = typename Simd::Type;

    const WatertightRay &ray;
    Float ox, oy, oz, sx, sy, sz;

    explicit WatertightRayPacket(const WatertightRay &r)
        : ray(r), ox(Simd::broadcast(r.o[r.kx])), oy(Simd::broadcast(r.o[r.ky])),
          oz(Simd::broadcast(r.o[r.kz])), sx(Simd::broadcast(r.sx)), sy(Simd::broadcast(r.sy)),
          sz(Simd::broadcast(r.sz)) {}

    /// The four triangles of one packet (four lanes).
    PacketHits<Lanes> intersect(const TrianglePacket &packet) const {
        static_assert(Lanes == TrianglePacket::kWidth, "one packet fills four lanes");
        return intersectLanes(
            [&](int vertex, int axis) { return Simd::load(packet.v[vertex][axis]); });
    }

#ifdef __AVX__
    /// The eight triangles of two packets (eight lanes): `first`'s in lanes 0–3.
    PacketHits<Lanes> intersect(const TrianglePacket &first, const TrianglePacket &second) const {
        static_assert(Lanes == 2 * TrianglePacket::kWidth, "two packets fill eight lanes");
        return intersectLanes([&](int vertex, int axis) {
            return Simd::loadHalves(first.v[vertex][axis], second.v[vertex][axis]);
        });
    }
#endif

private:
    /// The watertight test, lane by lane, with the scalar test's operations in its
    /// order; `load(vertex, axis)` gives that coordinate of every lane's triangle.
    template <typename Load> PacketHits<Lanes> intersectLanes(Load &&load) const {
        using S = Simd;
        Float x[3], y[3], z[3];
        for (int i = 0; i < 3; ++i) {
            // As in intersectTriangle: a = p0 − o, then ax = a[kx] + sx·a[kz], ...
            z[i] = S::sub(load(i, ray.kz), oz);
            x[i] = S::add(S::sub(load(i, ray.kx), ox), S::mul(sx, z[i]));
            y[i] = S::add(S::sub(load(i, ray.ky), oy), S::mul(sy, z[i]));
        }
        const Float e0 = S::sub(S::mul(x[1], y[2]), S::mul(y[1], x[2]));
        const Float e1 = S::sub(S::mul(x[2], y[0]), S::mul(y[2], x[0]));
        const Float e2 = S::sub(S::mul(x[0], y[1]), S::mul(y[0], x[1]));
        const Float zero = S::zero();
        const Float anyNegative =
            S::bitOr(S::bitOr(S::less(e0, zero), S::less(e1, zero)), S::less(e2, zero));
        const Float anyPositive =
            S::bitOr(S::bitOr(S::greater(e0, zero), S::greater(e1, zero)), S::greater(e2, zero));
        const Float anyZero =
            S::bitOr(S::bitOr(S::equal(e0, zero), S::equal(e1, zero)), S::equal(e2, zero));
        const Float det = S::add(S::add(e0, e1), e2);
        const Float sAz = S::mul(sz, z[0]), sBz = S::mul(sz, z[1]), sCz = S::mul(sz, z[2]);
        const Float tScaled = S::add(S::add(S::mul(e0, sAz), S::mul(e1, sBz)), S::mul(e2, sCz));
        // The range test 0 < t <= maxt before the division, with the sign of det moved onto
        // tScaled (exact): 0 < tScaled·sign(det) <= maxt·|det|.
        const Float signBit = S::broadcast(-0.0f);
        const Float tSigned = S::bitXor(tScaled, S::bitAnd(det, signBit));
        const Float detAbs = S::andNot(signBit, det);
        const Float maxt = S::broadcast(ray.maxt);
        Float accept = S::andNot(S::bitAnd(anyNegative, anyPositive),
                                 S::less(detAbs, S::broadcast(kInfinity))); // finite
        accept = S::bitAnd(accept, S::notEqual(det, zero));
        accept = S::bitAnd(accept, S::greater(tSigned, zero));
        accept = S::bitAnd(accept, S::lessEqualMask(tSigned, S::mul(maxt, detAbs)));

        const Float invDet = S::div(S::broadcast(1.0f), det);
        const Float tHit = S::mul(tScaled, invDet);
        // The conservative bound on t's error (PBR 4th ed. §6.8.7), as in the scalar test.
        auto absMax = [&](Float a, Float b, Float c) {
            return S::max(S::max(S::andNot(signBit, a), S::andNot(signBit, b)),
                          S::andNot(signBit, c));
        };
        const Float maxZt = absMax(sAz, sBz, sCz);
        const Float maxXt = absMax(x[0], x[1], x[2]);
        const Float maxYt = absMax(y[0], y[1], y[2]);
        const Float deltaZ = S::mul(S::broadcast(gammaBound(3)), maxZt);
        const Float deltaX = S::mul(S::broadcast(gammaBound(5)), S::add(maxXt, maxZt));
        const Float deltaY = S::mul(S::broadcast(gammaBound(5)), S::add(maxYt, maxZt));
        const Float deltaE =
            S::mul(S::broadcast(2.0f),
                   S::add(S::add(S::mul(S::mul(S::broadcast(gammaBound(2)), maxXt), maxYt),
                                 S::mul(deltaY, maxXt)),
                          S::mul(deltaX, maxYt)));
        const Float maxE = absMax(e0, e1, e2);
        const Float errorSum = S::add(
            S::add(S::mul(S::mul(S::broadcast(gammaBound(3)), maxE), maxZt), S::mul(deltaE, maxZt)),
            S::mul(deltaZ, maxE));
        const Float deltaT =
            S::mul(S::mul(S::broadcast(3.0f), errorSum), S::andNot(signBit, invDet));
        const Float tooClose = S::bitAnd(accept, S::lessEqualMask(tHit, deltaT));
        accept = S::bitAnd(accept, S::greater(tHit, deltaT));
        accept = S::bitAnd(accept, S::greaterEqual(tHit, S::broadcast(ray.mint)));
        accept = S::bitAnd(accept, S::lessEqualMask(tHit, maxt));

        PacketHits<Lanes> hits;
        hits.undecided = S::bits(S::bitOr(anyZero, tooClose));
        hits.hit = S::bits(accept) & ~hits.undecided;
        S::store(hits.t, tHit);
        S::store(hits.b1, S::mul(e1, invDet));
        S::store(hits.b2, S::mul(e2, invDet));
        return hits;
    }
};

} // namespace nori
