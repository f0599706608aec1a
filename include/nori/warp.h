// Warps from the unit square to other domains, each with its density.
#pragma once

#include <nori/vector.h>

namespace nori {

class Warp {
public:
    /// Identity warp; density 1 on [0,1)^2.
    static Point2f squareToUniformSquare(const Point2f &sample) { return sample; }
    static float squareToUniformSquarePdf(const Point2f &p);

    /// Shirley–Chiu concentric map of the square onto the unit disk (equal area).
    static Point2f squareToUniformDiskConcentric(const Point2f &sample);
    static float squareToUniformDiskConcentricPdf(const Point2f &p);

    /// Cosine-weighted hemisphere about +z via Malley's method (PBR 4th ed. §A.5.3).
    static Vector3f squareToCosineHemisphere(const Point2f &sample);
    static float squareToCosineHemispherePdf(const Vector3f &v);
};

} // namespace nori
