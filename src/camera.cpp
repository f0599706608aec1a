#include <nori/camera.h>

namespace nori {

void Camera::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    if (child->getClassType() == EReconstructionFilter) {
        if (m_rfilter)
            throw NoriException("a camera takes only one reconstruction filter");
        m_rfilter = std::static_pointer_cast<ReconstructionFilter>(child);
        return;
    }
    NoriObject::addChild(child, name);
}

void Camera::activate() {
    if (!m_rfilter)
        m_rfilter = std::static_pointer_cast<ReconstructionFilter>(
            NoriObjectFactory::createInstance("gaussian", EReconstructionFilter, PropertyList()));
}

} // namespace nori
