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
    case EEmitter: {
        auto emitter = std::static_pointer_cast<Emitter>(child);
        if (emitter->requiresShape())
            throw NoriException("{} must be nested in the <mesh> it lights from",
                                emitter->toString());
        m_emitters.push_back(emitter);
        break;
    }
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
    for (const auto &shape : m_shapes) {
        m_accel.addShape(shape.get());
        if (shape->getEmitterPtr())
            m_emitters.push_back(shape->getEmitterPtr());
    }
    m_accel.build();

    // Lights are chosen in proportion to their power; if all are dark, uniformly.
    m_emitterPdf.clear();
    float totalPower = 0.0f;
    for (const auto &emitter : m_emitters)
        totalPower += std::max(0.0f, emitter->getPower().getLuminance());
    for (size_t i = 0; i < m_emitters.size(); ++i) {
        const float power = std::max(0.0f, m_emitters[i]->getPower().getLuminance());
        m_emitterPdf.append(totalPower > 0.0f ? power : 1.0f);
        m_emitterIndex[m_emitters[i].get()] = i;
    }
    if (!m_emitters.empty())
        m_emitterPdf.normalize();
}

const Emitter *Scene::sampleEmitter(float &u, float &pmf) const {
    if (m_emitters.empty()) {
        pmf = 0.0f;
        return nullptr;
    }
    return m_emitters[m_emitterPdf.sampleReuse(u, pmf)].get();
}

float Scene::emitterPmf(const Emitter *emitter) const {
    auto it = m_emitterIndex.find(emitter);
    return it == m_emitterIndex.end() ? 0.0f : m_emitterPdf[it->second];
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
