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
    /// True when lookAt would throw because `up` is (nearly) parallel to target − origin.
    static bool isUpParallelToView(const Point3f &origin, const Point3f &target,
                                   const Vector3f &up);
    /// What Nori 2's lookat makes of an `up` parallel to the view: its left = up × dir is
    /// zero and Eigen's normalized() leaves a zero vector as it is, so the matrix has
    /// columns (0, 0, dir, origin) and every camera direction d maps to d.z · dir. Course
    /// references were computed with it; the inverse is the pseudo-inverse.
    static Transform collapsedLookAt(const Point3f &origin, const Point3f &target);

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

/// An affine map x ↦ A·x + b kept as its 3×4 matrix [A | b]: 48 bytes, what an instance
/// stores of its placement (a Transform, with its projective row and inverse, is 128).
class AffineMap {
public:
    using Matrix = Eigen::Matrix<float, 3, 4, Eigen::DontAlign>;

    AffineMap() : m_matrix(Matrix::Identity()) {}
    explicit AffineMap(const Matrix &matrix) : m_matrix(matrix) {}
    /// The map of a transform's matrix; throws when its last row is not (0, 0, 0, 1).
    static AffineMap of(const Eigen::Matrix4f &matrix);

    /// The inverse, computed in double precision and rounded once.
    AffineMap inverse() const;
    /// Composition: (a * b) applies b first, then a.
    AffineMap operator*(const AffineMap &other) const;

    Point3f applyToPoint(const Point3f &p) const {
        return Point3f(m_matrix.leftCols<3>() * p + m_matrix.col(3));
    }
    Vector3f applyToVector(const Vector3f &v) const { return Vector3f(m_matrix.leftCols<3>() * v); }
    /// A normal under the inverse of this map: Aᵀ·n (the inverse transpose of A⁻¹), so
    /// a map to local space carries local normals to world ones (pbrt-v4 §3.10.3).
    Vector3f applyTransposeToNormal(const Vector3f &n) const {
        return Vector3f(m_matrix.leftCols<3>().transpose() * n);
    }
    /// Bound on the rounding error of applyToPoint(p) for an exact p (pbrt-v4 §6.8.4:
    /// γ₃·(|A|·|p| + |b|) per component).
    Vector3f roundingError(const Point3f &p) const;
    /// Bound on the error of applyToPoint(p) for p known within ±pError (pbrt-v4 §6.8.4:
    /// (1 + γ₃)·|A|·pError on top of the rounding error).
    Vector3f propagatedError(const Point3f &p, const Vector3f &pError) const;

    const Matrix &matrix() const { return m_matrix; }

private:
    Matrix m_matrix;
};
static_assert(sizeof(AffineMap) == 48, "an affine map is twelve floats");

} // namespace nori
