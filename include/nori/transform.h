// Homogeneous transforms. Points use the full matrix, vectors the linear part,
// normals the inverse transpose (pbrt-v4 §3.10.4), so normals stay perpendicular.
#pragma once

#include <nori/ray.h>

namespace nori {

class Transform {
public:
    Transform()
        : m_transform(Eigen::Matrix4f::Identity()), m_inverse(Eigen::Matrix4f::Identity()) {}
    /// Throws NoriException when the matrix is singular.
    explicit Transform(const Eigen::Matrix4f &matrix);
    Transform(const Eigen::Matrix4f &matrix, const Eigen::Matrix4f &inverse)
        : m_transform(matrix), m_inverse(inverse) {}

    static Transform translate(const Vector3f &offset);
    static Transform scale(const Vector3f &factors);
    /// Rotation by angleDegrees about axis (right-handed, as in Nori and Mitsuba).
    static Transform rotate(const Vector3f &axis, float angleDegrees);
    /// Camera-to-world matrix placing the origin at `origin` looking at `target`;
    /// the camera looks along +z with +y up (Nori's convention).
    static Transform lookAt(const Point3f &origin, const Point3f &target, const Vector3f &up);

    const Eigen::Matrix4f &getMatrix() const { return m_transform; }
    const Eigen::Matrix4f &getInverseMatrix() const { return m_inverse; }
    Transform inverse() const { return Transform(m_inverse, m_transform); }

    /// Composition: (a * b) applies b first, then a.
    Transform operator*(const Transform &other) const {
        return Transform(m_transform * other.m_transform, other.m_inverse * m_inverse);
    }

    Vector3f operator*(const Vector3f &v) const {
        return Vector3f(m_transform.topLeftCorner<3, 3>() * v);
    }
    Normal3f operator*(const Normal3f &n) const {
        return Normal3f(m_inverse.topLeftCorner<3, 3>().transpose() * n);
    }
    Point3f operator*(const Point3f &p) const {
        Eigen::Vector4f result = m_transform * Eigen::Vector4f(p.x(), p.y(), p.z(), 1.0f);
        return Point3f(result.head<3>() / result.w());
    }
    Ray3f operator*(const Ray3f &ray) const {
        return Ray3f(operator*(ray.o), operator*(ray.d), ray.mint, ray.maxt);
    }

    std::string toString() const;

private:
    Eigen::Matrix4f m_transform;
    Eigen::Matrix4f m_inverse;
};

} // namespace nori
