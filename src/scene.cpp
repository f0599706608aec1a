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
        setUniqueChild(m_integrator, child, "a scene");
        break;
    case ECamera:
        setUniqueChild(m_camera, child, "a scene");
        break;
    case ESampler:
        setUniqueChild(m_sampler, child, "a scene");
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
        m_sampler = createDefault<Sampler>("independent");
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
