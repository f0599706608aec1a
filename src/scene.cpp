#include <nori/scene.h>

namespace nori {

Scene::Scene(const PropertyList &props) {
    (void)props;
}

void Scene::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    switch (child->getClassType()) {
    case EMesh:
        m_shapes.push_back(std::static_pointer_cast<Shape>(child));
        break;
    case EIntegrator:
        if (m_integrator)
            throw NoriException("a scene takes only one integrator");
        m_integrator = std::static_pointer_cast<Integrator>(child);
        break;
    case ECamera:
        if (m_camera)
            throw NoriException("a scene takes only one camera");
        m_camera = std::static_pointer_cast<Camera>(child);
        break;
    case ESampler:
        if (m_sampler)
            throw NoriException("a scene takes only one sampler");
        m_sampler = std::static_pointer_cast<Sampler>(child);
        break;
    default:
        NoriObject::addChild(child, name);
    }
}

void Scene::activate() {
    if (!m_integrator)
        throw NoriException("the scene has no integrator");
    if (!m_camera)
        throw NoriException("the scene has no camera");
    if (!m_sampler)
        m_sampler = std::static_pointer_cast<Sampler>(
            NoriObjectFactory::createInstance("independent", ESampler, PropertyList()));
    for (const auto &shape : m_shapes)
        m_accel.addShape(shape.get());
    m_accel.build();
}

std::string Scene::toString() const {
    std::string shapes;
    for (const auto &shape : m_shapes)
        shapes += "    " + shape->toString() + "\n";
    return fmt::format("Scene[\n  integrator = {},\n  camera = {},\n  sampler = {},\n"
                       "  shapes = {{\n{}  }}\n]",
                       m_integrator->toString(), m_camera->toString(), m_sampler->toString(),
                       shapes);
}

NORI_REGISTER_CLASS(Scene, "scene");

} // namespace nori
