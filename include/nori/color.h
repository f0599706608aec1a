// Linear RGB colours (Rec. 709 primaries) and their conversion to and from sRGB.
#pragma once

#include <nori/common.h>

#include <Eigen/Core>

namespace nori {

/// A linear RGB triple; arithmetic is component-wise (an Eigen array).
struct Color3f : public Eigen::Array3f {
    using Base = Eigen::Array3f;

    Color3f() : Base(Base::Zero()) {}
    /// Grey `value`; implicit, as in Nori 2 (`Color3f c = 0.0f;`, `return 0.0f;`).
    Color3f(float value) : Base(value, value, value) {} // NOLINT(google-explicit-constructor)
    Color3f(float r, float g, float b) : Base(r, g, b) {}
    template <typename Derived> Color3f(const Eigen::ArrayBase<Derived> &p) : Base(p) {}
    template <typename Derived> Color3f &operator=(const Eigen::ArrayBase<Derived> &p) {
        this->Base::operator=(p);
        return *this;
    }

    float &r() { return x(); }
    float r() const { return x(); }
    float &g() { return y(); }
    float g() const { return y(); }
    float &b() { return z(); }
    float b() const { return z(); }

    /// Negative components set to zero.
    Color3f clamp() const { return Color3f(cwiseMax(0.0f)); }
    /// Luminance with the Rec. 709 weights Nori uses.
    float getLuminance() const { return 0.212671f * r() + 0.715160f * g() + 0.072169f * b(); }
    /// True when every component is finite and non-negative.
    bool isValid() const {
        return std::isfinite(r()) && std::isfinite(g()) && std::isfinite(b()) && r() >= 0.0f &&
               g() >= 0.0f && b() >= 0.0f;
    }
    /// "[r, g, b]", for messages.
    std::string toString() const;
    /// sRGB transfer curve (IEC 61966-2-1) applied per component.
    Color3f toSRGB() const;
    /// Inverse of toSRGB.
    Color3f toLinearRGB() const;
};

/// An RGB colour with a weight, as accumulated by an image block: (sum w·c, sum w).
struct Color4f : public Eigen::Array4f {
    using Base = Eigen::Array4f;

    Color4f() : Base(Base::Zero()) {}
    Color4f(const Color3f &c, float w) : Base(c.r() * w, c.g() * w, c.b() * w, w) {}
    /// A colour of weight 1 (Nori 2).
    Color4f(const Color3f &c) : Base(c.r(), c.g(), c.b(), 1.0f) {} // NOLINT: implicit as in Nori 2
    Color4f(float r, float g, float b, float w) : Base(r, g, b, w) {}
    template <typename Derived> Color4f(const Eigen::ArrayBase<Derived> &p) : Base(p) {}
    template <typename Derived> Color4f &operator=(const Eigen::ArrayBase<Derived> &p) {
        this->Base::operator=(p);
        return *this;
    }

    /// Divides by the accumulated weight; a pixel that received no weight is black.
    Color3f divideByFilterWeight() const {
        if (w() == 0.0f)
            return Color3f(0.0f);
        return Color3f(x() / w(), y() / w(), z() / w());
    }
    /// "[r, g, b, w]", for messages.
    std::string toString() const;
};

} // namespace nori
