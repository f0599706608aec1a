#include <nori/emitter.h>
#include <nori/frame.h>
#include <nori/proplist.h>
#include <nori/shape.h>
#include <nori/warp.h>

namespace nori {

bool Emitter::attachTo(NoriObject &parent, const std::string &name) {
    (void)name;
    auto *shape = dynamic_cast<Shape *>(&parent);
    if (!shape)
        return false;
    shape->setEmitter(std::static_pointer_cast<Emitter>(shared_from_this()));
    m_shape = shape;
    return true;
}

void SceneBoundingSphere::set(const BoundingBox3f &bounds) {
    if (!bounds.isValid())
        return;
    center = bounds.getCenter();
    radius = std::max(0.5f * (bounds.max - bounds.min).norm(), 1e-3f);
}

void SceneBoundingSphere::placeBeyond(EmitterQueryRecord &lRec) const {
    // From any point, leaving the sphere takes at most the distance to its centre plus
    // its diameter.
    const float distance = (lRec.ref - center).norm() + 2.0f * radius;
    lRec.p = lRec.ref + distance * lRec.wi;
    lRec.n = Normal3f(-lRec.wi);
    lRec.setShadowRay(distance);
}

float SceneBoundingSphere::photonRayFrom(const Vector3f &toLight, const Point2f &sample,
                                         EmissionSample &emission) const {
    const Frame frame(toLight);
    const Point2f disk = radius * Warp::squareToUniformDiskConcentric(sample);
    emission.p = center + radius * toLight + disk.x() * frame.s + disk.y() * frame.t;
    emission.ray = Ray3f(emission.p, -toLight, 0.0f, kInfinity);
    emission.density.position = 1.0f / diskArea();
    return diskArea();
}

Color3f Emitter::sampleEmission(EmissionSample &, const Point2f &, const Point2f &) const {
    throw NoriException("{} cannot emit photons (its plugin does not override "
                        "Emitter::sampleEmission), so the photon mappers, the light tracer "
                        "and bdpt cannot use it",
                        toString());
}

EmissionDensity Emitter::emissionDensity(const Point3f &, const Normal3f &,
                                         const Vector3f &) const {
    throw NoriException("{} cannot give the density of its photons (its plugin does not "
                        "override Emitter::emissionDensity), so bdpt cannot use it",
                        toString());
}

Color3f Emitter::samplePhoton(Ray3f &ray, const Point2f &positionSample,
                              const Point2f &directionSample) const {
    EmissionSample emission;
    Color3f weight = sampleEmission(emission, positionSample, directionSample);
    ray = emission.ray;
    return weight;
}

EmissionDensity Emitter::densityAtInfinity(const SceneBoundingSphere &sphere,
                                           const Vector3f &direction) const {
    EmitterQueryRecord lRec;
    lRec.wi = -direction;
    return {1.0f / sphere.diskArea(), pdf(lRec)};
}

float Emitter::aimAtPoint(EmitterQueryRecord &lRec, const Point3f &position) {
    lRec.p = position;
    const Vector3f toLight = position - lRec.ref;
    const float distanceSquared = toLight.squaredNorm();
    if (distanceSquared == 0.0f)
        return 0.0f;
    const float distance = std::sqrt(distanceSquared);
    lRec.wi = toLight / distance;
    lRec.n = Normal3f(-lRec.wi);
    lRec.pdf = 1.0f; // a delta distribution: the weight is the incident radiance's integral
    lRec.setShadowRay(distance);
    return distanceSquared;
}

Color3f Emitter::readIntensity(const PropertyList &props, const std::string &plugin,
                               float solidAngle) {
    const bool hasPower = props.has("power"), hasIntensity = props.has("intensity");
    if (hasPower == hasIntensity)
        throw NoriException("{}: give exactly one of 'power' and 'intensity'", plugin);
    Color3f intensity =
        hasPower ? Color3f(props.getColor("power") / solidAngle) : props.getColor("intensity");
    if ((intensity < 0.0f).any() || !intensity.allFinite())
        throw NoriException("{}: power and intensity must be finite and not negative", plugin);
    return intensity;
}

} // namespace nori
