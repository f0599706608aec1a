// Warps from the unit square to other domains, each with its density (PBR 4th ed. §A.5,
// Nori's warp.h). Densities are with respect to area for planar warps and solid angle
// for directions; a point outside the warp's domain has density 0.
#pragma once

#include <nori/vector.h>

#include <array>

namespace nori {

class Sampler;

/// Every function is defined weak (src/math/warp.cpp): a course's own warp.cpp, dropped
/// into plugins/, replaces the ones it defines, in every program and plugin, as in Nori 2's
/// warp assignment; `warptest` then tests the course's versions.
class Warp {
public:
    /// The unit vector with cos θ = cosTheta and azimuth φ about +z.
    static Vector3f sphericalDirection(float cosTheta, float phi);

    /// Identity on [0,1)²; density 1.
    static Point2f squareToUniformSquare(const Point2f &sample);
    static float squareToUniformSquarePdf(const Point2f &p);

    /// Separable tent on [-1,1]²: density (1 − |x|)(1 − |y|).
    static Point2f squareToTent(const Point2f &sample);
    static float squareToTentPdf(const Point2f &p);

    /// Uniform on the unit disk by the polar map r = √u, φ = 2πv; density 1/π.
    static Point2f squareToUniformDisk(const Point2f &sample);
    static float squareToUniformDiskPdf(const Point2f &p);

    /// Shirley–Chiu concentric map onto the unit disk (equal area); density 1/π.
    static Point2f squareToUniformDiskConcentric(const Point2f &sample);
    static float squareToUniformDiskConcentricPdf(const Point2f &p);

    /// The bilinear density on [0,1]² through the corner weights w = (w(0,0), w(1,0),
    /// w(0,1), w(1,1)), not negative: 4·bilerp(w, p)/Σw (PBR 4th ed. §A.5.2), drawn by the
    /// marginal in y and then the conditional in x, each linear and inverted in closed
    /// form. Uniform when every weight is 0.
    static Point2f squareToBilinear(const Point2f &sample, const std::array<float, 4> &w);
    static float squareToBilinearPdf(const Point2f &p, const std::array<float, 4> &w);

    /// Uniform in the triangle (0,0), (1,0), (0,1), as barycentrics (PBR 4th ed. §A.5.5);
    /// density 2.
    static Point2f squareToUniformTriangle(const Point2f &sample);
    static float squareToUniformTrianglePdf(const Point2f &p);
    /// Nori 2's first warp: a uniform direction on the hemisphere about northPole, drawn by
    /// rejection from the sampler.
    static Vector3f sampleUniformHemisphere(Sampler *sampler, const Normal3f &northPole);
    /// Uniform on the unit sphere: z = 1 − 2u (Archimedes); density 1/4π.
    static Vector3f squareToUniformSphere(const Point2f &sample);
    static float squareToUniformSpherePdf(const Vector3f &v);

    /// Uniform on the unit sphere by Clarberg's equal-area octahedral map (Clarberg 2008,
    /// "Fast Equal-Area Mapping of the (Hemi)Sphere using SIMD"; PBR 4th ed. §3.8.3): the
    /// square's inner diamond covers z ≥ 0, its corners z < 0. pbrt-v4's square
    /// environment maps are images of it. Density 1/4π.
    static Vector3f squareToEqualAreaSphere(const Point2f &sample);
    static float squareToEqualAreaSpherePdf(const Vector3f &v);
    /// The inverse: the point of [0, 1]² that squareToEqualAreaSphere sends to v (unit).
    static Point2f equalAreaSphereToSquare(const Vector3f &v);

    /// Uniform on the hemisphere z ≥ 0; density 1/2π.
    static Vector3f squareToUniformHemisphere(const Point2f &sample);
    static float squareToUniformHemispherePdf(const Vector3f &v);

    /// Cosine-weighted hemisphere about +z via Malley's method; density cos θ/π.
    static Vector3f squareToCosineHemisphere(const Point2f &sample);
    static float squareToCosineHemispherePdf(const Vector3f &v);

    /// A cosine-power lobe about +z, density (n + 1)/(2π) cos^n θ on the hemisphere: the
    /// glossy lobe of the modified Phong model (Lafortune and Willems 1994, §4).
    static Vector3f squareToCosinePowerHemisphere(const Point2f &sample, float exponent);
    static float squareToCosinePowerHemispherePdf(const Vector3f &v, float exponent);

    /// Uniform on the spherical cap cos θ ≥ cosThetaMax about +z; density
    /// 1/(2π(1 − cosThetaMax)).
    static Vector3f squareToUniformSphereCap(const Point2f &sample, float cosThetaMax);
    static float squareToUniformSphereCapPdf(const Vector3f &v, float cosThetaMax);

    /// Beckmann microfacet normals, density D(m) cos θm with
    /// D = exp(−tan²θ/α²)/(π α² cos⁴θ) (Walter et al. 2007, eq. 25, 28).
    static Vector3f squareToBeckmann(const Point2f &sample, float alpha);
    static float squareToBeckmannPdf(const Vector3f &m, float alpha);

    /// GGX (Trowbridge–Reitz) microfacet normals, density D(m) cos θm with
    /// D = α²/(π cos⁴θ (α² + tan²θ)²) (Walter et al. 2007, eq. 33, 35).
    static Vector3f squareToGGX(const Point2f &sample, float alpha);
    static float squareToGGXPdf(const Vector3f &m, float alpha);

    /// GTR1, Burley's clearcoat lobe: D = (α² − 1)/(π ln(α²) (1 + (α² − 1) cos²θ)), density
    /// D cos θ (Burley 2012, "Physically-Based Shading at Disney", appendix B.2).
    static Vector3f squareToGTR1(const Point2f &sample, float alpha);
    static float squareToGTR1Pdf(const Vector3f &m, float alpha);

    /// Henyey–Greenstein directions about +z, density
    /// (1 − g²)/(4π (1 + g² − 2g cos θ)^{3/2}) (PBR 4th ed. §11.3.1).
    static Vector3f squareToHenyeyGreenstein(const Point2f &sample, float g);
    static float squareToHenyeyGreensteinPdf(const Vector3f &v, float g);
};

} // namespace nori
