#include "testing/halfvectorroutine.h"

#include <nori/common.h>

#include <cmath>

namespace nori {

namespace {

/// The map's radial part: u = F(s) for s = tan²θh, and its derivative.
struct RadialMap {
    double alpha2, share;

    double cdf(double s) const { return share * s / (s + alpha2) + (1.0 - share) * s / (s + 1.0); }
    double derivative(double s) const {
        return share * alpha2 / ((s + alpha2) * (s + alpha2)) +
               (1.0 - share) / ((s + 1.0) * (s + 1.0));
    }
    /// s with F(s) = u, for u in [0, 1): the root of
    /// (u − 1)s² + (u(1 + α²) − w − (1 − w)α²)s + uα² = 0
    /// (F(s) = u times (s + α²)(s + 1)) that is not negative.
    double inverse(double u) const {
        const double a = u - 1.0, b = u * (1.0 + alpha2) - share - (1.0 - share) * alpha2,
                     c = u * alpha2;
        const double root = std::sqrt(std::max(0.0, b * b - 4.0 * a * c));
        // The two roots q/a and c/q, without cancellation (Numerical Recipes §5.6).
        const double q = -0.5 * (b + std::copysign(root, b));
        const double first = q / a, second = q != 0.0 ? c / q : 0.0;
        return std::max({first, second, 0.0});
    }
};

} // namespace

SamplingRoutine halfVectorRoutine(const SamplingRoutine &reflection, const Vector3f &wi,
                                  double alpha, double sharpShare) {
    if (!(alpha > 0.0) || !(sharpShare > 0.0) || !(sharpShare < 1.0) || !(wi.z() > 0.0f))
        throw NoriException("halfVectorRoutine: needs alpha > 0, a share in (0, 1) and wi "
                            "above the surface");
    const RadialMap map{alpha * alpha, sharpShare};
    const Eigen::Vector3d in = wi.cast<double>().normalized();
    SamplingRoutine routine;
    routine.domain = SampleDomain::UnitSquare;
    routine.sample = [reflection, map, in](const Point2f &sample, Vector3f &point) {
        Vector3f wo;
        if (!reflection.sample(sample, wo))
            return false;
        const Eigen::Vector3d out = wo.cast<double>().normalized(), sum = in + out;
        if (!(out.z() > 0.0) || !(sum.z() > 0.0)) {
            point = Vector3f(-1.0f, -1.0f, 0.0f); // below the surface: outside the domain
            return true;
        }
        const Eigen::Vector3d h = sum.normalized();
        const double s = (h.x() * h.x() + h.y() * h.y()) / (h.z() * h.z());
        double phi = std::atan2(h.y(), h.x()) / (2.0 * kPiDouble);
        if (phi < 0.0)
            phi += 1.0;
        point = Vector3f(static_cast<float>(map.cdf(s)), static_cast<float>(phi), 0.0f);
        return true;
    };
    routine.pdf = [reflection, map, in](const Vector3f &point) {
        const double u = point.x(), v = point.y();
        if (!(u >= 0.0) || !(u < 1.0) || !(v >= 0.0) || !(v <= 1.0))
            return 0.0;
        const double s = map.inverse(u), cosTheta = 1.0 / std::sqrt(1.0 + s),
                     sinTheta = std::sqrt(s) * cosTheta, phi = 2.0 * kPiDouble * v;
        const Eigen::Vector3d h(sinTheta * std::cos(phi), sinTheta * std::sin(phi), cosTheta);
        const double cosine = in.dot(h);
        const Eigen::Vector3d out = 2.0 * cosine * h - in;
        if (!(cosine > 0.0) || !(out.z() > 0.0))
            return 0.0;
        const double halfVectorDensity =
            map.derivative(s) / (kPiDouble * cosTheta * cosTheta * cosTheta);
        return reflection.pdf(out.cast<float>()) * 4.0 * cosine / halfVectorDensity;
    };
    return routine;
}

} // namespace nori
