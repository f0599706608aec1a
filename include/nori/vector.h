// Points, vectors and normals on top of Eigen. They are distinct types because they
// transform differently (see transform.h), but share Eigen's arithmetic.
#pragma once

#include <nori/common.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace nori {

/// "[x, y, z]": the components of a vector, for messages and toString().
template <typename Derived> std::string formatComponents(const Eigen::MatrixBase<Derived> &v) {
    std::string text = "[";
    for (Eigen::Index i = 0; i < v.size(); ++i)
        text += (i ? ", " : "") + fmt::format("{}", v[i]);
    return text + "]";
}

/// A direction or displacement: transforms with the linear part only.
template <typename Scalar, int Dim> struct TVector : public Eigen::Matrix<Scalar, Dim, 1> {
    using Base = Eigen::Matrix<Scalar, Dim, 1>;

    TVector() : Base(Base::Zero()) {}
    /// Every component `value`; implicit, as in Nori 2 (`Vector3f v = 0.0f;`).
    TVector(Scalar value) : Base(Base::Constant(value)) {} // NOLINT(google-explicit-constructor)
    TVector(Scalar x, Scalar y) : Base(x, y) {}
    TVector(Scalar x, Scalar y, Scalar z) : Base(x, y, z) {}
    TVector(Scalar x, Scalar y, Scalar z, Scalar w) : Base(x, y, z, w) {}
    template <typename Derived> TVector(const Eigen::MatrixBase<Derived> &p) : Base(p) {}
    template <typename Derived> TVector &operator=(const Eigen::MatrixBase<Derived> &p) {
        this->Base::operator=(p);
        return *this;
    }
    /// "[x, y, z]", for messages.
    std::string toString() const { return formatComponents(*this); }
};

/// A position: transforms with the full affine (or projective) transform.
template <typename Scalar, int Dim> struct TPoint : public Eigen::Matrix<Scalar, Dim, 1> {
    using Base = Eigen::Matrix<Scalar, Dim, 1>;

    TPoint() : Base(Base::Zero()) {}
    /// Every component `value`; implicit, as in Nori 2 (`Vector3f v = 0.0f;`).
    TPoint(Scalar value) : Base(Base::Constant(value)) {} // NOLINT(google-explicit-constructor)
    TPoint(Scalar x, Scalar y) : Base(x, y) {}
    TPoint(Scalar x, Scalar y, Scalar z) : Base(x, y, z) {}
    TPoint(Scalar x, Scalar y, Scalar z, Scalar w) : Base(x, y, z, w) {}
    template <typename Derived> TPoint(const Eigen::MatrixBase<Derived> &p) : Base(p) {}
    template <typename Derived> TPoint &operator=(const Eigen::MatrixBase<Derived> &p) {
        this->Base::operator=(p);
        return *this;
    }
    /// "[x, y, z]", for messages.
    std::string toString() const { return formatComponents(*this); }
};

/// A surface normal: transforms with the inverse transpose.
struct Normal3f : public Eigen::Matrix<float, 3, 1> {
    using Base = Eigen::Matrix<float, 3, 1>;

    Normal3f() : Base(Base::Zero()) {}
    Normal3f(float value) : Base(Base::Constant(value)) {} // NOLINT(google-explicit-constructor)
    Normal3f(float x, float y, float z) : Base(x, y, z) {}
    template <typename Derived> Normal3f(const Eigen::MatrixBase<Derived> &p) : Base(p) {}
    template <typename Derived> Normal3f &operator=(const Eigen::MatrixBase<Derived> &p) {
        this->Base::operator=(p);
        return *this;
    }
    std::string toString() const { return formatComponents(*this); }
};

using Vector1f = TVector<float, 1>;
using Vector2f = TVector<float, 2>;
using Vector3f = TVector<float, 3>;
using Vector4f = TVector<float, 4>;
using Vector1d = TVector<double, 1>;
using Vector2d = TVector<double, 2>;
using Vector3d = TVector<double, 3>;
using Vector4d = TVector<double, 4>;
using Vector1i = TVector<int, 1>;
using Vector2i = TVector<int, 2>;
using Vector3i = TVector<int, 3>;
using Vector4i = TVector<int, 4>;
using Point1f = TPoint<float, 1>;
using Point2f = TPoint<float, 2>;
using Point3f = TPoint<float, 3>;
using Point4f = TPoint<float, 4>;
using Point1d = TPoint<double, 1>;
using Point2d = TPoint<double, 2>;
using Point3d = TPoint<double, 3>;
using Point4d = TPoint<double, 4>;
using Point1i = TPoint<int, 1>;
using Point2i = TPoint<int, 2>;
using Point3i = TPoint<int, 3>;
using Point4i = TPoint<int, 4>;

/// Builds an orthonormal basis (s, t) around a unit vector n (Duff et al. 2017, JCGT 6(1)).
inline void coordinateSystem(const Vector3f &n, Vector3f &s, Vector3f &t) {
    float sign = std::copysign(1.0f, n.z());
    float a = -1.0f / (sign + n.z());
    float b = n.x() * n.y() * a;
    s = Vector3f(1.0f + sign * n.x() * n.x() * a, sign * b, -sign * n.x());
    t = Vector3f(b, sign + n.y() * n.y() * a, -n.y());
}

} // namespace nori
