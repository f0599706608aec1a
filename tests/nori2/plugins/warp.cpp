/*
    This file is part of Nori, a simple educational ray tracer (course assignment 2)

    The functions below replace the renderer's own versions of the same warps.
*/

#include <nori/warp.h>
#include <nori/vector.h>
#include <nori/frame.h>

NORI_NAMESPACE_BEGIN

/* Shirley and Chiu's concentric map, instead of the polar map r = sqrt(u) */
Point2f Warp::squareToUniformDisk(const Point2f &sample) {
    float a = 2 * sample.x() - 1, b = 2 * sample.y() - 1;
    if (a == 0 && b == 0)
        return Point2f(0.0f, 0.0f);
    float r, phi;
    if (a * a > b * b) {
        r = a;
        phi = (M_PI / 4) * (b / a);
    } else {
        r = b;
        phi = (M_PI / 2) - (M_PI / 4) * (a / b);
    }
    return Point2f(r * std::cos(phi), r * std::sin(phi));
}

float Warp::squareToUniformDiskPdf(const Point2f &p) {
    return p.squaredNorm() <= 1 ? INV_PI : 0.0f;
}

/* Uniform sphere by inversion of z = 1 - 2u */
Vector3f Warp::squareToUniformSphere(const Point2f &sample) {
    float z = 1 - 2 * sample.x();
    float r = std::sqrt(std::max(0.0f, 1 - z * z));
    float phi = 2 * M_PI * sample.y();
    return Vector3f(r * std::cos(phi), r * std::sin(phi), z);
}

float Warp::squareToUniformSpherePdf(const Vector3f &v) {
    return std::abs(v.squaredNorm() - 1) < 1e-3f ? INV_FOURPI : 0.0f;
}

NORI_NAMESPACE_END
