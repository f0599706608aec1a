#include <nori/camera.h>

namespace nori {

void Camera::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    if (child->getClassType() == EReconstructionFilter)
        setUniqueChild(m_rfilter, child, "a camera");
    else
        NoriObject::addChild(child, name);
}

void Camera::activate() {
    if (!m_rfilter)
        m_rfilter = createDefault<ReconstructionFilter>("gaussian");
}

} // namespace nori
