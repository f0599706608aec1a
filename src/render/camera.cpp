#include <nori/camera.h>

namespace nori {

void Camera::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    if (child->getClassType() == EReconstructionFilter)
        setUniqueChild(m_rfilter, child, "a camera");
    else if (child->getClassType() == EMedium)
        setUniqueChild(m_medium, child, "a camera");
    else
        NoriObject::addChild(child, name);
}

Camera::Convention Camera::readConvention(const PropertyList &props) {
    const std::string name = props.getString("convention", "epfl");
    if (name == "epfl")
        return Convention::EPFL;
    if (name == "eth")
        return Convention::ETH;
    throw NoriException("'convention' must be \"epfl\" (image x mirrored, Nori 2's default) "
                        "or \"eth\" (not mirrored), got '{}'",
                        name);
}

void Camera::activate() {
    const int width = m_outputSize.x(), height = m_outputSize.y();
    if (width < 1 || height < 1 || width > kMaxImageSide || height > kMaxImageSide ||
        int64_t(width) * height > kMaxImagePixels)
        throw NoriException("an image of width {} and height {} is not possible: each must lie in "
                            "[1, {}] and width x height must be at most {} pixels",
                            width, height, kMaxImageSide, kMaxImagePixels);
    if (!m_rfilter)
        m_rfilter = createDefault<ReconstructionFilter>("gaussian");
}

Color3f Camera::sampleRayDifferential(Ray3f &ray, const Point2f &samplePosition,
                                      const Point2f &apertureSample) const {
    const Color3f weight = sampleRay(ray, samplePosition, apertureSample);
    Ray3f rx, ry;
    if ((weight == 0.0f).all() ||
        (sampleRay(rx, samplePosition + Point2f(1.0f, 0.0f), apertureSample) == 0.0f).all() ||
        (sampleRay(ry, samplePosition + Point2f(0.0f, 1.0f), apertureSample) == 0.0f).all())
        return weight; // no neighbour ray (e.g. outside a lens's exit pupil): no footprint
    ray.hasDifferentials = true;
    ray.rxOrigin = rx.o;
    ray.rxDirection = rx.d;
    ray.ryOrigin = ry.o;
    ray.ryDirection = ry.d;
    return weight;
}

} // namespace nori
