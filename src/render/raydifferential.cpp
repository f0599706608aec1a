#include <nori/bsdf.h>
#include <nori/raydifferential.h>
#include <nori/shape.h>

#include <algorithm>

namespace nori {

namespace {

/// Derivatives larger than this are treated as garbage (a ray grazing the tangent plane).
constexpr float kMaxDerivative = 1e8f;

float sane(float value) {
    return std::isfinite(value) ? std::clamp(value, -kMaxDerivative, kMaxDerivative) : 0.0f;
}

void clearFootprint(Intersection &its) {
    its.dpdx = its.dpdy = Vector3f::Zero();
    its.dudx = its.dudy = its.dvdx = its.dvdy = 0.0f;
}

} // namespace

void computeDifferentials(Intersection &its, const Ray3f &ray) {
    if (!ray.hasDifferentials) {
        clearFootprint(its);
        return;
    }
    // Where the offset rays meet the tangent plane n·(x − p) = 0 (pbrt-v3 §10.1.1).
    const Vector3f &n = its.geoFrame.n;
    const float tx = n.dot(its.p - ray.rxOrigin) / n.dot(ray.rxDirection);
    const float ty = n.dot(its.p - ray.ryOrigin) / n.dot(ray.ryDirection);
    if (!std::isfinite(tx) || !std::isfinite(ty)) {
        clearFootprint(its);
        return;
    }
    its.dpdx = ray.rxOrigin + tx * ray.rxDirection - its.p;
    its.dpdy = ray.ryOrigin + ty * ray.ryDirection - its.p;
    // Least squares: [dpdu dpdv] (du, dv)ᵀ = dp, via the normal equations (pbrt-v4 §10.1.1).
    const float ata00 = its.dpdu.dot(its.dpdu), ata01 = its.dpdu.dot(its.dpdv),
                ata11 = its.dpdv.dot(its.dpdv);
    const float invDet = 1.0f / (ata00 * ata11 - ata01 * ata01);
    const float atb0x = its.dpdu.dot(its.dpdx), atb1x = its.dpdv.dot(its.dpdx);
    const float atb0y = its.dpdu.dot(its.dpdy), atb1y = its.dpdv.dot(its.dpdy);
    its.dudx = sane((ata11 * atb0x - ata01 * atb1x) * invDet);
    its.dvdx = sane((ata00 * atb1x - ata01 * atb0x) * invDet);
    its.dudy = sane((ata11 * atb0y - ata01 * atb1y) * invDet);
    its.dvdy = sane((ata00 * atb1y - ata01 * atb0y) * invDet);
}

Ray3f spawnScatteredRay(const Intersection &its, const Ray3f &ray, const BSDFQueryRecord &bRec) {
    const Vector3f direction = its.toWorld(bRec.wo);
    Ray3f next = its.spawnRay(direction);
    if (!ray.hasDifferentials)
        return next;
    next.hasDifferentials = true;
    next.rxOrigin = its.p + its.dpdx;
    next.ryOrigin = its.p + its.dpdy;

    if (bRec.measure != EDiscrete) {
        // A ray cone: the incoming angular spread plus kNonSpecularSpread, around the new
        // direction, along two axes perpendicular to it.
        const float spread =
            std::max((ray.rxDirection - ray.d).norm(), (ray.ryDirection - ray.d).norm()) +
            kNonSpecularSpread;
        const Frame frame(direction);
        next.rxDirection = direction + spread * frame.s;
        next.ryDirection = direction + spread * frame.t;
        return next;
    }

    // Specular: differentiate the reflected or refracted direction (Igehy 1999, §4;
    // pbrt-v3 §10.1.3). ω points back along the incoming ray, n is the shading normal.
    const Vector3f omega = -ray.d;
    Vector3f n = its.shFrame.n;
    Vector3f dndx = its.dndu * its.dudx + its.dndv * its.dvdx;
    Vector3f dndy = its.dndu * its.dudy + its.dndv * its.dvdy;
    const Vector3f domegadx = -ray.rxDirection - omega, domegady = -ray.ryDirection - omega;
    const bool reflection = Frame::cosTheta(bRec.wi) * Frame::cosTheta(bRec.wo) > 0.0f;
    if (reflection) {
        // r = −ω + 2(ω·n)n, so dr = −dω + 2[(ω·n) dn + d(ω·n) n].
        const float dDNdx = domegadx.dot(n) + omega.dot(dndx);
        const float dDNdy = domegady.dot(n) + omega.dot(dndy);
        const float cosine = omega.dot(n);
        next.rxDirection = direction - domegadx + 2.0f * (cosine * dndx + dDNdx * n);
        next.ryDirection = direction - domegady + 2.0f * (cosine * dndy + dDNdy * n);
        return next;
    }
    // t = −ω/η + μ n with μ = cos θi/η − cos θt, n on ω's side and η = η_t/η_i (bRec.eta):
    // dt = −dω/η + dμ n + μ dn, dμ = (1/η − cos θi/(η² cos θt)) d(ω·n).
    if (omega.dot(n) < 0.0f) {
        n = -n;
        dndx = -dndx;
        dndy = -dndy;
    }
    const float eta = bRec.eta, cosI = omega.dot(n), cosT = std::abs(direction.dot(n));
    const float mu = cosI / eta - cosT;
    const float dmuScale = cosT > 0.0f ? 1.0f / eta - cosI / (eta * eta * cosT) : 0.0f;
    const float dDNdx = domegadx.dot(n) + omega.dot(dndx);
    const float dDNdy = domegady.dot(n) + omega.dot(dndy);
    next.rxDirection = direction - domegadx / eta + (dmuScale * dDNdx) * n + mu * dndx;
    next.ryDirection = direction - domegady / eta + (dmuScale * dDNdy) * n + mu * dndy;
    return next;
}

} // namespace nori
