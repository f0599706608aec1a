#include <nori/warp.h>

namespace nori {

float Warp::squareToUniformSquarePdf(const Point2f &p) {
    return (p.array() >= 0.0f).all() && (p.array() <= 1.0f).all() ? 1.0f : 0.0f;
}

Point2f Warp::squareToUniformDiskConcentric(const Point2f &sample) {
    // Shirley & Chiu 1997: map concentric squares to concentric circles.
    Point2f offset(2.0f * sample.x() - 1.0f, 2.0f * sample.y() - 1.0f);
    if (offset.x() == 0.0f && offset.y() == 0.0f)
        return Point2f(0.0f, 0.0f);
    float r, theta;
    if (std::abs(offset.x()) > std::abs(offset.y())) {
        r = offset.x();
        theta = (kPi / 4.0f) * (offset.y() / offset.x());
    } else {
        r = offset.y();
        theta = (kPi / 2.0f) - (kPi / 4.0f) * (offset.x() / offset.y());
    }
    return Point2f(r * std::cos(theta), r * std::sin(theta));
}

float Warp::squareToUniformDiskConcentricPdf(const Point2f &p) {
    return p.squaredNorm() <= 1.0f ? kInvPi : 0.0f;
}

Vector3f Warp::squareToCosineHemisphere(const Point2f &sample) {
    // Malley: a uniform point on the disk lifted to the hemisphere is cosine distributed.
    Point2f d = squareToUniformDiskConcentric(sample);
    float z = safeSqrt(1.0f - d.squaredNorm());
    return Vector3f(d.x(), d.y(), z);
}

float Warp::squareToCosineHemispherePdf(const Vector3f &v) {
    return v.z() > 0.0f ? v.z() * kInvPi : 0.0f;
}

} // namespace nori
