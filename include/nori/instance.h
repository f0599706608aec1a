// Instancing: the objects that place geometry rather than being a surface, and the
// collection of shapes and placements that a scene and a shape group both hold.
//   <mesh type="shapegroup" id="g">  shapes placed only through instances of it
//   <mesh type="instance">           a <ref id="g"/> and a toWorld
//   <mesh type="tmesh">              nested in a mesh (course style): a copy of that
//                                    mesh placed by its own toWorld, with its own BSDF
// Every placement is a 56-byte record in an Accel's instance BVH; the geometry it places
// has one bottom-level BVH, shared by all its placements (see accel.h).
#pragma once

#include <nori/accel.h>

#include <functional>
#include <unordered_map>
#include <unordered_set>

namespace nori {

class ShapeGroup;

/// A <mesh> that stands for several shapes, each with its own BSDF and maybe an area
/// light (a glTF file's primitives and materials): the scene or shape group that takes it
/// adds each of its parts in its place.
class CompoundShape : public NoriObject {
public:
    static constexpr EClassType kClassType = EMesh;
    /// The parts, made and activated by the compound's activate().
    virtual const std::vector<std::shared_ptr<Shape>> &parts() const = 0;
    EClassType getClassType() const override { return kClassType; }
};

/// <mesh type="instance">: a shape group placed by `toWorld`.
class Instance : public NoriObject {
public:
    static constexpr EClassType kClassType = EMesh;

    explicit Instance(const PropertyList &props);
    /// Takes the shape group (through a <ref>); anything else is an error.
    using NoriObject::addChild;
    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override;
    void activate() override;
    const std::shared_ptr<ShapeGroup> &group() const { return m_group; }
    const AffineMap &toWorld() const { return m_toWorld; }
    std::string toString() const override;
    EClassType getClassType() const override { return kClassType; }

private:
    // Every instance of a scene exists at once while the scene is read (its children are
    // made before it): an affine map (48 B) rather than a Transform (two 4×4 matrices, 64-byte
    // aligned with AVX-512) keeps each at 176 bytes instead of 320.
    AffineMap m_toWorld;
    std::shared_ptr<ShapeGroup> m_group;
};

/// <mesh type="tmesh">: a copy of the mesh it is nested in, placed by `toWorld` (applied
/// after the parent's own toWorld), with its own BSDF or else the parent's.
class TMesh : public NoriObject {
public:
    static constexpr EClassType kClassType = EMesh;

    explicit TMesh(const PropertyList &props);
    /// Takes one <bsdf> (which attaches itself through setBSDF).
    using NoriObject::addChild;
    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override;
    const Transform &toWorld() const { return m_toWorld; }
    const std::shared_ptr<BSDF> &bsdf() const { return m_bsdf; }
    void setBSDF(std::shared_ptr<BSDF> bsdf);
    std::string toString() const override;
    EClassType getClassType() const override { return kClassType; }

private:
    Transform m_toWorld;
    std::shared_ptr<BSDF> m_bsdf;
};

/// The tmesh copies of one shape: an Accel over the shape alone, shared by every copy,
/// and for each BSDF other than the shape's a view of the shape that reports it.
class TMeshSet {
public:
    explicit TMeshSet(const Shape &parent);
    /// Records a copy; its BSDF (if any) must be activated.
    void add(const TMesh &tmesh);
    /// Builds the shared Accel once every copy is recorded.
    void build();
    /// Places every copy into `accel`, then forgets the placements: the records in
    /// `accel` are the only per-copy memory left.
    void placeInto(Accel &accel);
    /// The views of the shape with another BSDF, one per distinct BSDF of the copies.
    const std::vector<std::shared_ptr<Shape>> &views() const { return m_views; }

private:
    const Shape &m_parent;
    Accel m_accel;
    std::vector<std::unique_ptr<Accel::InstanceTarget>> m_targets; ///< front(): the parent's BSDF
    std::vector<std::shared_ptr<Shape>> m_views;                   ///< one per other BSDF
    /// The target of each view's BSDF.
    std::unordered_map<const BSDF *, const Accel::InstanceTarget *> m_targetOfBSDF;
    /// (own BSDF or nullptr, toWorld) per copy, until placeInto().
    std::vector<std::pair<std::shared_ptr<BSDF>, Transform>> m_copies;
};

/// The shapes and placements a scene or a shape group holds, and the Accel over them.
class ShapeCollection {
public:
    /// Takes a <mesh> child: a shape (rendered unless `visible` is false, with its tmesh
    /// copies), a compound shape (each of its parts), an instance (kept only as a record
    /// in the Accel), or a shape group (a declaration, used through <ref>: ignored here).
    /// A tmesh outside a mesh is an error.
    void add(const std::shared_ptr<NoriObject> &child);
    /// Builds the Accel over the visible shapes and every placement.
    void build();

    const Accel &accel() const { return m_accel; }
    /// Every shape added, including invisible templates.
    const std::vector<std::shared_ptr<Shape>> &shapes() const { return m_shapes; }
    /// Calls `visit` on every shape it renders, here or through a placement (the shapes
    /// of placed groups, the views of tmesh copies), and on invisible templates.
    void visitShapes(const std::function<void(const Shape &)> &visit) const;

private:
    /// Keeps what a placement refers to alive, once per object.
    void keepAlive(const std::shared_ptr<const void> &object);

    std::vector<std::shared_ptr<Shape>> m_shapes;
    std::vector<std::shared_ptr<const void>> m_placed;
    std::unordered_set<const void *> m_placedSet;
    std::vector<const ShapeGroup *> m_placedGroups; ///< each once
    Accel m_accel;
};

/// <mesh type="shapegroup">: shapes and instances that render only where instances of
/// the group place them.
class ShapeGroup : public NoriObject {
public:
    static constexpr EClassType kClassType = EMesh;

    explicit ShapeGroup(const PropertyList &props);
    /// Takes shapes, instances and nested group declarations; refuses area lights.
    using NoriObject::addChild;
    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override;
    /// Builds the group's Accel; an empty group is an error.
    void activate() override;
    const Accel::InstanceTarget *target() const { return &m_target; }
    const ShapeCollection &contents() const { return m_contents; }
    std::string toString() const override;
    EClassType getClassType() const override { return kClassType; }

private:
    ShapeCollection m_contents;
    Accel::InstanceTarget m_target;
    size_t m_shapeCount = 0, m_instanceCount = 0;
};

} // namespace nori
