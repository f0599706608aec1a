#include <nori/emitter.h>
#include <nori/proplist.h>

namespace nori {

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
    lRec.shadowRay = Ray3f(lRec.ref, lRec.wi, 0.0f, distance);
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
    lRec.shadowRay = Ray3f(lRec.ref, lRec.wi, 0.0f, distance * (1.0f - kShadowEpsilon));
    return distanceSquared;
}

Color3f Emitter::readIntensity(const PropertyList &props, const std::string &plugin,
                               float solidAngle) {
    const bool hasPower = props.has("power"), hasIntensity = props.has("intensity");
    if (hasPower == hasIntensity)
        throw NoriException("{}: give exactly one of 'power' and 'intensity'", plugin);
    const Color3f intensity =
        hasPower ? Color3f(props.getColor("power") / solidAngle) : props.getColor("intensity");
    if ((intensity < 0.0f).any() || !intensity.allFinite())
        throw NoriException("{}: power and intensity must be finite and not negative", plugin);
    return intensity;
}

} // namespace nori
