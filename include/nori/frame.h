// An orthonormal frame (s, t, n); the local shading frame has the normal along +z.
#pragma once

#include <nori/vector.h>

namespace nori {

struct Frame {
    Vector3f s, t;
    Normal3f n;

    Frame() = default;
    Frame(const Vector3f &s, const Vector3f &t, const Normal3f &n) : s(s), t(t), n(n) {}
    /// A frame around a unit normal; the tangents are an arbitrary orthonormal pair.
    /// A frame around a unit normal (implicit, as in Nori 2).
    Frame(const Vector3f &normal) : n(normal) { coordinateSystem(normal, s, t); } // NOLINT

    Vector3f toLocal(const Vector3f &v) const { return Vector3f(v.dot(s), v.dot(t), v.dot(n)); }
    Vector3f toWorld(const Vector3f &v) const { return s * v.x() + t * v.y() + n * v.z(); }

    // Spherical-coordinate helpers for a direction v given in this local frame.
    static float cosTheta(const Vector3f &v) { return v.z(); }
    static float sinTheta2(const Vector3f &v) { return std::max(0.0f, 1.0f - v.z() * v.z()); }
    static float sinTheta(const Vector3f &v) { return std::sqrt(sinTheta2(v)); }
    static float tanTheta(const Vector3f &v) { return sinTheta(v) / v.z(); }
    static float sinPhi(const Vector3f &v) {
        float st = sinTheta(v);
        return st == 0.0f ? 0.0f : std::clamp(v.y() / st, -1.0f, 1.0f);
    }
    static float cosPhi(const Vector3f &v) {
        float st = sinTheta(v);
        return st == 0.0f ? 1.0f : std::clamp(v.x() / st, -1.0f, 1.0f);
    }
    static float sinPhi2(const Vector3f &v) { return sinPhi(v) * sinPhi(v); }
    static float cosPhi2(const Vector3f &v) { return cosPhi(v) * cosPhi(v); }

    bool operator==(const Frame &frame) const {
        return frame.s == s && frame.t == t && frame.n == n;
    }
    bool operator!=(const Frame &frame) const { return !operator==(frame); }
    std::string toString() const {
        return fmt::format("Frame[s={}, t={}, n={}]", s.toString(), t.toString(), n.toString());
    }
};

} // namespace nori
