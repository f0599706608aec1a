#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/phase.h>
#include <nori/samplingroutines.h>
#include <nori/shape.h>
#include <nori/strutil.h>
#include <nori/warp.h>

namespace nori {

namespace {

SamplingRoutine planar(SampleDomain domain, Point2f (*warp)(const Point2f &),
                       float (*pdf)(const Point2f &)) {
    SamplingRoutine routine;
    routine.domain = domain;
    routine.sample = [warp](const Point2f &u, Vector3f &point) {
        const Point2f p = warp(u);
        point = Vector3f(p.x(), p.y(), 0.0f);
        return true;
    };
    routine.pdf = [pdf](const Vector3f &point) { return pdf(Point2f(point.x(), point.y())); };
    return routine;
}

SamplingRoutine spherical(Vector3f (*warp)(const Point2f &), float (*pdf)(const Vector3f &)) {
    SamplingRoutine routine;
    routine.sample = [warp](const Point2f &u, Vector3f &point) {
        point = warp(u);
        return true;
    };
    routine.pdf = [pdf](const Vector3f &v) { return pdf(v); };
    return routine;
}

SamplingRoutine parametric(Vector3f (*warp)(const Point2f &, float),
                           float (*pdf)(const Vector3f &, float), float parameter) {
    SamplingRoutine routine;
    routine.sample = [warp, parameter](const Point2f &u, Vector3f &point) {
        point = warp(u, parameter);
        return true;
    };
    routine.pdf = [pdf, parameter](const Vector3f &v) { return pdf(v, parameter); };
    return routine;
}

} // namespace

const std::vector<NamedWarp> &namedWarps() {
    static const std::vector<NamedWarp> warps = {
        {"square", "", 0.0f,
         [](float) {
             return planar(SampleDomain::UnitSquare, Warp::squareToUniformSquare,
                           Warp::squareToUniformSquarePdf);
         }},
        {"tent", "", 0.0f,
         [](float) {
             return planar(SampleDomain::CenteredSquare, Warp::squareToTent, Warp::squareToTentPdf);
         }},
        {"triangle", "", 0.0f,
         [](float) {
             return planar(SampleDomain::UnitSquare, Warp::squareToUniformTriangle,
                           Warp::squareToUniformTrianglePdf);
         }},
        {"disk", "", 0.0f,
         [](float) {
             return planar(SampleDomain::CenteredSquare, Warp::squareToUniformDisk,
                           Warp::squareToUniformDiskPdf);
         }},
        {"disk_concentric", "", 0.0f,
         [](float) {
             return planar(SampleDomain::CenteredSquare, Warp::squareToUniformDiskConcentric,
                           Warp::squareToUniformDiskConcentricPdf);
         }},
        {"uniform_sphere", "", 0.0f,
         [](float) {
             return spherical(Warp::squareToUniformSphere, Warp::squareToUniformSpherePdf);
         }},
        {"equal_area_sphere", "", 0.0f,
         [](float) {
             return spherical(Warp::squareToEqualAreaSphere, Warp::squareToEqualAreaSpherePdf);
         }},
        {"uniform_hemisphere", "", 0.0f,
         [](float) {
             return spherical(Warp::squareToUniformHemisphere, Warp::squareToUniformHemispherePdf);
         }},
        {"cosine_hemisphere", "", 0.0f,
         [](float) {
             return spherical(Warp::squareToCosineHemisphere, Warp::squareToCosineHemispherePdf);
         }},
        {"cosine_power", "exponent", 20.0f,
         [](float exponent) {
             return parametric(Warp::squareToCosinePowerHemisphere,
                               Warp::squareToCosinePowerHemispherePdf, exponent);
         }},
        {"sphere_cap", "cosThetaMax", 0.5f,
         [](float cosThetaMax) {
             return parametric(Warp::squareToUniformSphereCap, Warp::squareToUniformSphereCapPdf,
                               cosThetaMax);
         }},
        {"beckmann", "alpha", 0.3f,
         [](float alpha) {
             return parametric(Warp::squareToBeckmann, Warp::squareToBeckmannPdf, alpha);
         }},
        {"ggx", "alpha", 0.3f,
         [](float alpha) { return parametric(Warp::squareToGGX, Warp::squareToGGXPdf, alpha); }},
        {"gtr1", "alpha", 0.3f,
         [](float alpha) { return parametric(Warp::squareToGTR1, Warp::squareToGTR1Pdf, alpha); }},
        {"hg", "g", 0.5f,
         [](float g) {
             return parametric(Warp::squareToHenyeyGreenstein, Warp::squareToHenyeyGreensteinPdf,
                               g);
         }},
    };
    return warps;
}

const NamedWarp &findWarp(const std::string &name) {
    std::vector<std::string> names;
    for (const NamedWarp &warp : namedWarps()) {
        if (warp.name == name)
            return warp;
        names.push_back(warp.name);
    }
    throw NoriException("unknown warp '{}'{} (warps: {})", name, didYouMean(name, names),
                        fmt::join(names, ", "));
}

SamplingRoutine bsdfRoutine(const BSDF &bsdf, const Vector3f &wi, const TextureQuery &where) {
    SamplingRoutine routine;
    routine.sample = [&bsdf, wi, where](const Point2f &u, Vector3f &wo) {
        BSDFQueryRecord bRec(wi);
        static_cast<TextureQuery &>(bRec) = where;
        const Color3f weight = bsdf.sample(bRec, u);
        if ((weight == 0.0f).all() || bRec.measure == EDiscrete)
            return false;
        wo = bRec.wo;
        return true;
    };
    routine.pdf = [&bsdf, wi, where](const Vector3f &wo) {
        BSDFQueryRecord bRec(wi, wo, ESolidAngle);
        static_cast<TextureQuery &>(bRec) = where;
        return bsdf.pdf(bRec);
    };
    return routine;
}

SamplingRoutine phaseRoutine(const PhaseFunction &phase, const Vector3f &wi) {
    SamplingRoutine routine;
    routine.sample = [&phase, wi](const Point2f &u, Vector3f &wo) {
        PhaseFunctionQueryRecord pRec(wi);
        const Color3f weight = phase.sample(pRec, u);
        if ((weight == 0.0f).all() || pRec.measure == EDiscrete)
            return false;
        wo = pRec.wo;
        return true;
    };
    routine.pdf = [&phase, wi](const Vector3f &wo) {
        return phase.pdf(PhaseFunctionQueryRecord(wi, wo, ESolidAngle));
    };
    return routine;
}

Point3f emitterReferencePoint(const Emitter &emitter, const Point2f &u) {
    Point3f center(0.0f);
    float radius = 1.0f;
    if (const Shape *shape = emitter.getShape()) {
        center = shape->getBoundingBox().getCenter();
        radius = std::max(shape->getBoundingBox().getExtents().norm(), 1e-3f);
    }
    return center + radius * Warp::squareToUniformSphere(u);
}

SamplingRoutine emitterRoutine(const Emitter &emitter, const Point3f &ref,
                               const Normal3f &refNormal) {
    // Directions are binned in a frame whose +x points from ref at the light's centre: the
    // light then sits on the histogram's equator, where cells are regular, never at a
    // pole, where they are thin wedges that the quadrature of a disk's edge gets wrong.
    const Shape *shape = emitter.getShape();
    const Vector3f toCenter =
        shape ? Vector3f(shape->getBoundingBox().getCenter() - ref) : Vector3f(0.0f, 0.0f, 0.0f);
    const Vector3f axis =
        toCenter.norm() > 0.0f ? Vector3f(toCenter.normalized()) : Vector3f(1.0f, 0.0f, 0.0f);
    const Frame around(axis); // n = axis; its tangents complete the basis
    const Frame frame(axis, around.s, Normal3f(around.t));
    SamplingRoutine routine;
    routine.sample = [&emitter, ref, refNormal, frame](const Point2f &u, Vector3f &wi) {
        EmitterQueryRecord lRec(ref);
        lRec.refNormal = refNormal;
        if ((emitter.sample(lRec, u) == 0.0f).all())
            return false;
        wi = frame.toLocal(lRec.wi);
        return true;
    };
    routine.pdf = [&emitter, ref, refNormal, frame](const Vector3f &local) -> double {
        const Vector3f wi = frame.toWorld(local);
        EmitterQueryRecord lRec(ref);
        lRec.refNormal = refNormal;
        lRec.wi = wi;
        if (const Shape *shape = emitter.getShape()) {
            // Find where the direction meets the light's shape (closest primitive).
            const Ray3f ray(ref, wi, 0.0f, kInfinity);
            float tBest = kInfinity;
            for (uint32_t i = 0; i < shape->getPrimitiveCount(); ++i) {
                float t;
                Point2f coords;
                if (!shape->rayIntersect(i, ray, t, coords) || t >= tBest)
                    continue;
                tBest = t;
                Intersection its;
                its.t = t;
                shape->setHitInformation(i, ray, coords, its);
                lRec.p = its.p;
                lRec.n = its.geoFrame.n;
                lRec.primitive = i;
            }
            if (tBest == kInfinity)
                return 0.0;
        }
        return emitter.pdf(lRec);
    };
    return routine;
}

} // namespace nori
