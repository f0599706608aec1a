// Textures: colours and scalars that vary over a surface, looked up at a point with the
// footprint of a pixel there (uv derivatives from ray differentials), so that image
// textures can filter instead of aliasing (pbrt-v3 §10.1, §10.4).
#pragma once
#include <nori/color.h>
#include <nori/object.h>
#include <nori/vector.h>

#include <cmath>
#include <memory>
#include <vector>

namespace nori {

class PropertyList;
struct Intersection;

/// Where a texture is looked up: the surface point and its screen-space footprint.
struct TextureQuery {
    Point2f uv = Point2f(0.0f, 0.0f);      ///< surface parameterisation
    Point3f p = Point3f(0.0f, 0.0f, 0.0f); ///< world-space position (for 3D textures)
    /// uv derivatives per pixel step in x and y; all zero means "a point", which image
    /// textures answer from the finest level.
    float dudx = 0.0f, dudy = 0.0f, dvdx = 0.0f, dvdy = 0.0f;

    TextureQuery() = default;
    explicit TextureQuery(const Point2f &uv) : uv(uv) {}
    /// The point and footprint of a ray hit.
    explicit TextureQuery(const Intersection &its);
};

class Texture : public NoriObject {
public:
    static constexpr EClassType kClassType = ETexture;

    /// The colour at q, filtered over q's footprint.
    virtual Color3f eval(const TextureQuery &q) const = 0;
    /// The value used where a scalar is expected (roughness, bump height): the luminance,
    /// which is the value itself for grey textures.
    virtual float evalFloat(const TextureQuery &q) const { return eval(q).getLuminance(); }
    /// The mean over the unit uv square (an area light's power, a BSDF's mean albedo).
    virtual Color3f average() const = 0;
    /// The MIP level a lookup at q uses (0 = full resolution), or −1 for textures
    /// without levels; for the miplevel integrator.
    virtual float mipLevel(const TextureQuery &q) const {
        (void)q;
        return -1.0f;
    }
    /// Whether a lookup depends on the query's footprint (filtered textures): when no
    /// texture of a scene does, rays skip their differentials.
    virtual bool usesFootprint() const { return false; }
    /// Whether the texture is the same everywhere (a constant).
    virtual bool isConstant() const { return false; }
    /// The same texture reading 8-bit files as linear data rather than sRGB, for slots
    /// that hold data (normal, bump and roughness maps); nullptr when that is this one.
    virtual std::shared_ptr<const Texture> linearVariant() const { return nullptr; }

    EClassType getClassType() const override { return kClassType; }
};

/// How plugins read a parameter that may be textured: a <texture name="..."> child, or a
/// plain <color>/<float> of that name (wrapped in a `constant` texture), or the default.
/// Every BSDF and emitter reads its colour and float parameters through one of these,
/// which also keeps the list of its textures (for tools such as the miplevel
/// integrator).
class TextureParameters {
public:
    std::shared_ptr<const Texture> color(const PropertyList &props, const std::string &name,
                                         const Color3f &defaultValue);
    /// A required colour parameter (an area light's radiance).
    std::shared_ptr<const Texture> color(const PropertyList &props, const std::string &name);
    /// A scalar parameter; with `minimum`/`maximum`, a constant outside [minimum, maximum]
    /// is an error naming the parameter (textures are checked where they are decoded).
    std::shared_ptr<const Texture> scalar(const PropertyList &props, const std::string &name,
                                          float defaultValue, float minimum = -kInfinity,
                                          float maximum = kInfinity);
    /// A constant the plugin computed itself (e.g. from a named material).
    std::shared_ptr<const Texture> constant(const Color3f &value);
    /// The textures (constants included) in the order they were read.
    const std::vector<std::shared_ptr<const Texture>> &all() const { return m_textures; }

private:
    std::shared_ptr<const Texture> remember(std::shared_ptr<const Texture> texture);
    std::vector<std::shared_ptr<const Texture>> m_textures;
};

/// The pattern of the course's checkerboards (checkerboard_color, checkerboard_float):
/// with i = ⌊u/scale.x − delta.x⌋ and j = ⌊v/scale.y − delta.y⌋, the cell is "even" (value1)
/// when i + j is even.
struct CourseCheckerboard {
    Point2f delta;
    Vector2f scale;
    /// Reads `delta` (default 0, 0) and `scale` (default 1, 1; finite, non-zero).
    CourseCheckerboard(const PropertyList &props, const std::string &plugin);
    bool even(const Point2f &uv) const {
        const double i = std::floor(double(uv.x()) / scale.x() - delta.x());
        const double j = std::floor(double(uv.y()) / scale.y() - delta.y());
        return std::fmod(std::abs(i + j), 2.0) == 0.0; // (NaN: odd)
    }
};

/// A constant texture holding `value` (created through the factory, as `constant`).
std::shared_ptr<const Texture> makeConstantTexture(const Color3f &value);

} // namespace nori
