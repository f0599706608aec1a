#include <nori/camera.h>
#include <nori/mesh.h>
#include <nori/scene.h>
#include <nori/shading.h>

#include <tbb/enumerable_thread_specific.h>

#include <chrono>

namespace nori {

/// Rays traced per thread. Every ray counts, so the lookup must be cheap: a native
/// thread-local key per counter (pthread_getspecific), not the default's hash table of
/// thread ids, which cost 1.4 % of a Cornell box render's cycles. A scene holds one of the
/// process's keys (1024 on Linux) while it lives.
struct Scene::RayCounter {
    tbb::enumerable_thread_specific<uint64_t, tbb::cache_aligned_allocator<uint64_t>,
                                    tbb::ets_key_per_instance>
        perThread{0};
};

Scene::Scene(const PropertyList &props) : m_rayCounter(std::make_unique<RayCounter>()) {
    const std::string lightSampler = props.getString("lightSampler", "bvh");
    if (lightSampler != "bvh" && lightSampler != "power")
        throw NoriException("scene: 'lightSampler' is \"{}\"; it must be \"bvh\" (by "
                            "importance at the point) or \"power\"",
                            lightSampler);
    m_lightsByPower = lightSampler == "power";
}

Scene::~Scene() = default;

Color3f Scene::sampleCameraRay(Ray3f &ray, const Point2f &samplePosition,
                               const Point2f &apertureSample) const {
    return m_needsRayDifferentials
               ? m_camera->sampleRayDifferential(ray, samplePosition, apertureSample)
               : m_camera->sampleRay(ray, samplePosition, apertureSample);
}

bool Scene::rayIntersect(const Ray3f &ray, Intersection &its) const {
    ++m_rayCounter->perThread.local();
    if (!m_contents.accel().rayIntersect(ray, its, false))
        return false;
    completeHit(ray, its);
    return true;
}

bool Scene::rayIntersect(const Ray3f &ray) const {
    ++m_rayCounter->perThread.local();
    Intersection its;
    return m_contents.accel().rayIntersect(ray, its, true);
}

uint64_t Scene::rayCount() const {
    return m_rayCounter->perThread.combine(std::plus<uint64_t>());
}

std::string Scene::statisticsSummary() const {
    size_t triangles = 0;
    for (const auto &shape : getShapes())
        if (dynamic_cast<const Mesh *>(shape.get()))
            triangles += shape->getPrimitiveCount();
    const Accel &accel = m_contents.accel();
    const std::string instances = accel.instanceCount() == 0
                                      ? ""
                                      : fmt::format(" and {} instances ({} levels)",
                                                    accel.instanceCount(), accel.instanceDepth());
    return fmt::format("{} shapes ({} triangles), {} emitters; BVH of {} primitives{} built in {}",
                       getShapes().size(), triangles, m_emitters.size(),
                       accel.statistics().primitives, instances,
                       m_buildSeconds < 1.0 ? fmt::format("{:.0f} ms", m_buildSeconds * 1e3)
                                            : fmt::format("{:.2f} s", m_buildSeconds));
}

void Scene::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    switch (child->getClassType()) {
    case EMesh:
        m_contents.add(child);
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
    m_defaultSampler = !m_sampler;
    if (m_defaultSampler) // Nori 2's default is independent (docs/user-guide.md)
        m_sampler = createDefault<Sampler>("sobol");
    m_needsRayDifferentials = false;
    m_contents.visitShapes([this](const Shape &shape) {
        m_needsRayDifferentials = m_needsRayDifferentials || usesFootprint(shape);
    });
    m_meshes.clear();
    for (const auto &shape : getShapes()) {
        if (shape->getEmitterPtr())
            m_emitters.push_back(shape->getEmitterPtr());
        if (auto *mesh = dynamic_cast<Mesh *>(shape.get()))
            m_meshes.push_back(mesh);
    }
    const auto start = std::chrono::steady_clock::now();
    m_contents.build();
    m_buildSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    m_infiniteEmitters.clear();
    for (const auto &emitter : m_emitters) {
        emitter->setSceneBounds(getBoundingBox());
        if (emitter->isInfinite())
            m_infiniteEmitters.push_back(emitter.get());
    }
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
    if (!m_lightsByPower)
        m_lightTree.build(m_emitters);
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

const Emitter *Scene::sampleEmitter(const Point3f &p, const Normal3f &n, float &u,
                                    float &pmf) const {
    // A scene without lights (a pbrt-v4 file may have none) has no tree to walk.
    if (m_lightsByPower || m_emitters.empty())
        return sampleEmitter(u, pmf);
    return m_lightTree.sample(p, n, u, pmf);
}

float Scene::emitterPmf(const Point3f &p, const Normal3f &n, const Emitter *emitter) const {
    return m_lightsByPower ? emitterPmf(emitter) : m_lightTree.pmf(p, n, emitter);
}

std::string Scene::toString() const {
    std::string shapes;
    for (const auto &shape : getShapes())
        shapes += "    " + shape->toString() + "\n";
    return fmt::format("Scene[\n  integrator = {},\n  camera = {},\n  sampler = {},\n"
                       "  shapes = {{\n{}  }}\n]",
                       m_integrator->toString(), m_camera->toString(), m_sampler->toString(),
                       shapes);
}

NORI_REGISTER_CLASS(Scene, "scene");

} // namespace nori
