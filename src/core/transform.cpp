#include <nori/rayerror.h>
#include <nori/transform.h>

#include <Eigen/LU>
#include <Eigen/QR>
#include <sstream>

namespace nori {

Transform::Transform(const Eigen::Matrix4f &matrix) : m_transform(matrix) {
    Eigen::FullPivLU<Eigen::Matrix4f> lu(matrix);
    if (!lu.isInvertible()) {
        std::ostringstream out;
        out << matrix.format(Eigen::IOFormat(4, 0, ", ", "; ", "", "", "[", "]"));
        throw NoriException("transform matrix {} is singular", out.str());
    }
    m_inverse = lu.inverse();
}

Transform Transform::translate(const Vector3f &offset) {
    Eigen::Matrix4f matrix = Eigen::Matrix4f::Identity();
    matrix.topRightCorner<3, 1>() = offset;
    Eigen::Matrix4f inverse = Eigen::Matrix4f::Identity();
    inverse.topRightCorner<3, 1>() = -offset;
    return Transform(matrix, inverse);
}

Transform Transform::scale(const Vector3f &factors) {
    if ((factors.array() == 0.0f).any())
        throw NoriException("scale ({}, {}, {}) has a zero factor", factors.x(), factors.y(),
                            factors.z());
    Eigen::Matrix4f matrix = Eigen::Matrix4f::Identity();
    matrix.diagonal().head<3>() = factors;
    Eigen::Matrix4f inverse = Eigen::Matrix4f::Identity();
    inverse.diagonal().head<3>() = factors.cwiseInverse();
    return Transform(matrix, inverse);
}

Transform Transform::rotate(const Vector3f &axis, float angleDegrees) {
    if (axis.norm() == 0.0f)
        throw NoriException("rotation axis is the zero vector");
    Eigen::Matrix4f matrix = Eigen::Matrix4f::Identity();
    matrix.topLeftCorner<3, 3>() =
        Eigen::AngleAxisf(degToRad(angleDegrees), axis.normalized()).toRotationMatrix();
    // A rotation's inverse is its transpose.
    return Transform(matrix, matrix.transpose());
}

namespace {

/// Below this length of up × dir (both unit vectors, so it is sin of their angle) the
/// camera's left axis is rounding noise.
constexpr float kMinLeftLength = 1e-6f;

Vector3f viewDirection(const Point3f &origin, const Point3f &target) {
    const Vector3f dir = target - origin;
    if (dir.norm() == 0.0f)
        throw NoriException("lookat: origin and target are the same point");
    return dir.normalized();
}

} // namespace

bool Transform::isUpParallelToView(const Point3f &origin, const Point3f &target,
                                   const Vector3f &up) {
    return up.normalized().cross(viewDirection(origin, target)).norm() < kMinLeftLength;
}

Transform Transform::collapsedLookAt(const Point3f &origin, const Point3f &target) {
    Eigen::Matrix4f matrix = Eigen::Matrix4f::Zero();
    matrix.col(2).head<3>() = viewDirection(origin, target);
    matrix.col(3).head<3>() = origin;
    matrix(3, 3) = 1.0f;
    const Eigen::Matrix4f inverse = matrix.completeOrthogonalDecomposition().pseudoInverse();
    return Transform(matrix, inverse);
}

Transform Transform::lookAt(const Point3f &origin, const Point3f &target, const Vector3f &up) {
    const Vector3f dir = viewDirection(origin, target);
    Vector3f left = up.normalized().cross(dir);
    if (left.norm() < kMinLeftLength)
        throw NoriException("lookat: 'up' is zero or parallel to the viewing direction");
    left.normalize();
    Vector3f newUp = dir.cross(left);

    Eigen::Matrix4f matrix = Eigen::Matrix4f::Identity();
    matrix.col(0).head<3>() = left;
    matrix.col(1).head<3>() = newUp;
    matrix.col(2).head<3>() = dir;
    matrix.col(3).head<3>() = origin;
    return Transform(matrix);
}

std::string Transform::toString() const {
    std::ostringstream out;
    out << m_transform.format(Eigen::IOFormat(4, 0, ", ", ";\n", "", "", "[", "]"));
    return out.str();
}

AffineMap AffineMap::of(const Eigen::Matrix4f &matrix) {
    if (matrix.row(3) != Eigen::RowVector4f(0.0f, 0.0f, 0.0f, 1.0f))
        throw NoriException("the transform must be affine (last row 0 0 0 1), not projective");
    return AffineMap(matrix.topRows<3>());
}

AffineMap AffineMap::inverse() const {
    Eigen::Matrix4d full = Eigen::Matrix4d::Identity();
    full.topRows<3>() = m_matrix.cast<double>();
    return AffineMap(full.inverse().topRows<3>().cast<float>());
}

AffineMap AffineMap::operator*(const AffineMap &other) const {
    Matrix result;
    result.leftCols<3>() = m_matrix.leftCols<3>() * other.m_matrix.leftCols<3>();
    result.col(3) = m_matrix.leftCols<3>() * other.m_matrix.col(3) + m_matrix.col(3);
    return AffineMap(result);
}

Vector3f AffineMap::roundingError(const Point3f &p) const {
    return gammaBound(3) *
           Vector3f(m_matrix.leftCols<3>().cwiseAbs() * p.cwiseAbs() + m_matrix.col(3).cwiseAbs());
}

Vector3f AffineMap::propagatedError(const Point3f &p, const Vector3f &pError) const {
    return (1.0f + gammaBound(3)) * Vector3f(m_matrix.leftCols<3>().cwiseAbs() * pError) +
           roundingError(p);
}

} // namespace nori
