#include <nori/instance.h>
#include <nori/proplist.h>

namespace nori {

namespace {

/// A shape seen with another BSDF: the geometry, uvs and maps are the parent's; hits on
/// a tmesh copy with its own BSDF report this view, so integrators read that BSDF.
class ShapeWithBSDF : public Shape {
public:
    ShapeWithBSDF(const Shape &parent, std::shared_ptr<BSDF> bsdf) : m_parent(parent) {
        m_shading = parent.getSurfaceShadingPtr();
        m_bsdf = std::move(bsdf);
        m_bbox = parent.getBoundingBox();
    }
    uint32_t getPrimitiveCount() const override { return m_parent.getPrimitiveCount(); }
    BoundingBox3f getPrimitiveBoundingBox(uint32_t index) const override {
        return m_parent.getPrimitiveBoundingBox(index);
    }
    Point3f getPrimitiveCentroid(uint32_t index) const override {
        return m_parent.getPrimitiveCentroid(index);
    }
    bool rayIntersect(uint32_t index, const Ray3f &ray, float &t,
                      Point2f &hitCoords) const override {
        return m_parent.rayIntersect(index, ray, t, hitCoords);
    }
    void setHitInformation(uint32_t index, const Ray3f &ray, const Point2f &hitCoords,
                           Intersection &its) const override {
        m_parent.setHitInformation(index, ray, hitCoords, its);
        its.shape = its.mesh = this;
    }
    float getArea() const override { return m_parent.getArea(); }
    ShapeSample sampleSurface(const Point2f &sample) const override {
        return m_parent.sampleSurface(sample);
    }
    std::string toString() const override {
        return fmt::format("ShapeWithBSDF[{}, with a tmesh copy's own bsdf]", m_parent.toString());
    }

private:
    const Shape &m_parent;
};

} // namespace

Instance::Instance(const PropertyList &props)
    : m_toWorld(AffineMap::of(props.getTransform("toWorld", {}).getMatrix())) {}

void Instance::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    (void)name;
    auto group = std::dynamic_pointer_cast<ShapeGroup>(child);
    if (!group)
        throw NoriException("an instance places a <mesh type=\"shapegroup\"> (through <ref>), "
                            "not a <{} type=\"{}\">",
                            classTypeName(child->getClassType()), child->pluginName());
    if (m_group)
        throw NoriException("an instance places one shape group, not several");
    m_group = std::move(group);
}

void Instance::activate() {
    if (!m_group)
        throw NoriException("an instance needs a <ref id=\"...\"/> to the shape group it places");
}

std::string Instance::toString() const {
    Eigen::Matrix4f matrix = Eigen::Matrix4f::Identity();
    matrix.topRows<3>() = m_toWorld.matrix();
    return fmt::format("Instance[toWorld = {}]", Transform(matrix).toString());
}

TMesh::TMesh(const PropertyList &props) : m_toWorld(props.getTransform("toWorld", {})) {
    AffineMap::of(m_toWorld.getMatrix());
}

void TMesh::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    if (child->getClassType() != EBSDF || !child->attachTo(*this, name))
        NoriObject::addChild(child, name);
}

void TMesh::setBSDF(std::shared_ptr<BSDF> bsdf) {
    if (m_bsdf)
        throw NoriException("a tmesh takes only one bsdf");
    m_bsdf = std::move(bsdf);
}

std::string TMesh::toString() const {
    return fmt::format("TMesh[toWorld = {}]", m_toWorld.toString());
}

TMeshSet::TMeshSet(const Shape &parent) : m_parent(parent) {}

void TMeshSet::add(const TMesh &tmesh) {
    m_copies.emplace_back(tmesh.bsdf(), tmesh.toWorld());
}

void TMeshSet::build() {
    m_accel.addShape(&m_parent);
    m_accel.build();
    m_targets.push_back(
        std::make_unique<Accel::InstanceTarget>(Accel::InstanceTarget{&m_accel, nullptr}));
    // One view (and target) per distinct BSDF other than the parent's.
    for (const auto &[bsdf, toWorld] : m_copies) {
        if (!bsdf || bsdf.get() == m_parent.getBSDF() || m_targetOfBSDF.count(bsdf.get()))
            continue;
        m_views.push_back(std::make_shared<ShapeWithBSDF>(m_parent, bsdf));
        m_targets.push_back(std::make_unique<Accel::InstanceTarget>(
            Accel::InstanceTarget{&m_accel, m_views.back().get()}));
        m_targetOfBSDF.emplace(bsdf.get(), m_targets.back().get());
    }
}

void TMeshSet::placeInto(Accel &accel) {
    for (const auto &[bsdf, toWorld] : m_copies) {
        auto view = bsdf ? m_targetOfBSDF.find(bsdf.get()) : m_targetOfBSDF.end();
        accel.addInstance(view != m_targetOfBSDF.end() ? view->second : m_targets.front().get(),
                          AffineMap::of(toWorld.getMatrix()));
    }
    decltype(m_copies)().swap(m_copies); // frees it (`= {}` would keep the capacity)
}

void ShapeCollection::keepAlive(const std::shared_ptr<const void> &object) {
    if (m_placedSet.insert(object.get()).second)
        m_placed.push_back(object);
}

void ShapeCollection::add(const std::shared_ptr<NoriObject> &child) {
    if (auto instance = std::dynamic_pointer_cast<Instance>(child)) {
        m_accel.addInstance(instance->group()->target(), instance->toWorld());
        if (m_placedSet.count(instance->group().get()) == 0)
            m_placedGroups.push_back(instance->group().get());
        keepAlive(instance->group());
    } else if (std::dynamic_pointer_cast<ShapeGroup>(child)) {
        // A declaration: its instances place it.
    } else if (auto compound = std::dynamic_pointer_cast<CompoundShape>(child)) {
        for (const auto &part : compound->parts())
            add(part);
    } else if (std::dynamic_pointer_cast<TMesh>(child)) {
        throw NoriException("a <mesh type=\"tmesh\"> must be nested inside the mesh whose "
                            "geometry it copies");
    } else {
        auto shape = std::static_pointer_cast<Shape>(child);
        m_shapes.push_back(shape);
        if (shape->tmeshes()) {
            shape->tmeshes()->placeInto(m_accel);
            keepAlive(shape->tmeshes());
        }
    }
}

void ShapeCollection::visitShapes(const std::function<void(const Shape &)> &visit) const {
    for (const auto &shape : m_shapes) {
        visit(*shape);
        if (shape->tmeshes())
            for (const auto &view : shape->tmeshes()->views())
                visit(*view);
    }
    for (const ShapeGroup *group : m_placedGroups)
        group->contents().visitShapes(visit);
}

void ShapeCollection::build() {
    for (const auto &shape : m_shapes)
        if (shape->isVisible())
            m_accel.addShape(shape.get());
    m_accel.build();
}

ShapeGroup::ShapeGroup(const PropertyList &props) : m_target{&m_contents.accel(), nullptr} {
    (void)props;
}

void ShapeGroup::addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) {
    if (child->getClassType() != EMesh) {
        NoriObject::addChild(child, name);
        return;
    }
    if (auto compound = std::dynamic_pointer_cast<CompoundShape>(child)) {
        for (const auto &part : compound->parts())
            addChild(part, name);
        return;
    }
    if (const auto *shape = dynamic_cast<const Shape *>(child.get()); shape && shape->getEmitter())
        throw NoriException("a shape group cannot hold an area light (instanced geometry does "
                            "not emit): put the emitting mesh in the scene itself");
    if (const auto *shape = dynamic_cast<const Shape *>(child.get());
        shape && shape->hasMediumInterface())
        throw NoriException("a shape group cannot hold a medium boundary: put the shape with the "
                            "medium in the scene itself");
    m_contents.add(child);
    if (dynamic_cast<const Shape *>(child.get()))
        ++m_shapeCount;
    else if (dynamic_cast<const Instance *>(child.get()))
        ++m_instanceCount;
}

void ShapeGroup::activate() {
    if (m_shapeCount == 0 && m_instanceCount == 0)
        throw NoriException("a shape group needs at least one shape or instance");
    m_contents.build();
}

std::string ShapeGroup::toString() const {
    return fmt::format("ShapeGroup[{} shapes, {} instances]", m_shapeCount, m_instanceCount);
}

} // namespace nori
