#include <nori/nestedbsdf.h>
#include <nori/shape.h>

namespace nori {

NestedBSDF::NestedBSDF(std::string plugin, size_t minimum, size_t maximum)
    : m_plugin(std::move(plugin)), m_minimum(minimum), m_maximum(maximum) {}

void NestedBSDF::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    if (child->getClassType() != EBSDF)
        return BSDF::addChild(child, name);
    if (m_nested.size() == m_maximum)
        throw NoriException("{}: takes {} {} nested BSDF{}, got one more", m_plugin,
                            m_minimum == m_maximum ? "exactly" : "at most", m_maximum,
                            m_maximum == 1 ? "" : "s");
    addNested(std::static_pointer_cast<BSDF>(child));
}

void NestedBSDF::activate() {
    if (m_nested.size() < m_minimum)
        throw NoriException("{}: needs {} nested <bsdf>{}, got {}", m_plugin, m_minimum,
                            m_minimum == 1 ? "" : "s", m_nested.size());
}

void NestedBSDF::addNested(std::shared_ptr<BSDF> bsdf) {
    m_nested.push_back(std::move(bsdf));
}

bool NestedBSDF::anyNestedDiffuse() const {
    for (const auto &bsdf : m_nested)
        if (bsdf->isDiffuse())
            return true;
    return false;
}

std::string NestedBSDF::nestedToString() const {
    std::string text;
    for (const auto &bsdf : m_nested)
        text += (text.empty() ? "" : ", ") + bsdf->toString();
    return text;
}

bool SurfaceWrapperBSDF::attachTo(NoriObject &parent, const std::string &name) {
    auto *shape = dynamic_cast<Shape *>(&parent);
    if (!shape)
        return BSDF::attachTo(parent, name);
    activate(); // (idempotent: the parser may have called it already)
    decorate(*shape);
    return nestedPtr(0)->attachTo(parent, name);
}

} // namespace nori
