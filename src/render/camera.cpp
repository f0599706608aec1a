#include <nori/camera.h>
#include <nori/spectrum.h>

namespace nori {

void Camera::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    if (child->getClassType() == EReconstructionFilter)
        setUniqueChild(m_rfilter, child, "a camera");
    else if (child->getClassType() == EMedium)
        setUniqueChild(m_medium, child, "a camera");
    else
        NoriObject::addChild(child, name);
}

void Camera::readFilm(const PropertyList &props) {
    m_fullSize = Vector2i(props.getInteger("width", 1280), props.getInteger("height", 720));
    m_cropOffset = Vector2i(props.getInteger("cropOffsetX", 0), props.getInteger("cropOffsetY", 0));
    m_outputSize = Vector2i(props.getInteger("cropWidth", m_fullSize.x() - m_cropOffset.x()),
                            props.getInteger("cropHeight", m_fullSize.y() - m_cropOffset.y()));
    if ((m_cropOffset.array() < 0).any() || (m_outputSize.array() < 1).any() ||
        ((m_cropOffset + m_outputSize).array() > m_fullSize.array()).any())
        throw NoriException("the crop of {} x {} pixels at ({}, {}) does not lie in the image "
                            "of {} x {} pixels",
                            m_outputSize.x(), m_outputSize.y(), m_cropOffset.x(), m_cropOffset.y(),
                            m_fullSize.x(), m_fullSize.y());
    m_sampleBorder = props.getBoolean("sampleBorder", false);
    const float temperature = props.getFloat("whiteBalance", 0.0f);
    if (temperature != 0.0f)
        m_whiteBalance = whiteBalanceMatrix(temperature);
}

bool Camera::outputPosition(const Point2f &fraction, Point2f &samplePosition) const {
    if (!(fraction.x() >= 0.0f && fraction.x() < 1.0f && fraction.y() >= 0.0f &&
          fraction.y() < 1.0f))
        return false;
    samplePosition =
        Point2f(fraction.cwiseProduct(m_fullSize.cast<float>()) - m_cropOffset.cast<float>());
    // A fraction just below 1 may round up to the edge.
    return samplePosition.x() >= 0.0f && samplePosition.y() >= 0.0f &&
           samplePosition.x() < static_cast<float>(m_outputSize.x()) &&
           samplePosition.y() < static_cast<float>(m_outputSize.y());
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
    Color3f weight = sampleRay(ray, samplePosition, apertureSample);
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
