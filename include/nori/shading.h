// Shading at a hit: what a surface adds to the geometry a ray found before any BSDF is
// evaluated there. A shape's `uvScale` rescales its texture coordinates; a `normal` map
// (tangent space, decoded as 2c − 1) or a `bump` map (a height, scaled by `bumpScale`)
// bends its shading normal; and the pixel footprint at the hit comes from the ray's
// differentials, so that textures can filter (raydifferential.h).
#pragma once

#include <nori/shape.h>

#include <memory>

namespace nori {

class PropertyList;
class Texture;

/// A shape's uv scale and normal or bump map.
class SurfaceShading {
public:
    /// Reads `uvScale` (a float or 2D vector), `normal` or `bump` (textures, not both) and
    /// `bumpScale`; nullptr when every one has its default.
    static std::shared_ptr<const SurfaceShading> read(const PropertyList &props);
    /// `base` (which may be nullptr: defaults) with `heights` as its bump map, scaled by
    /// `scale`: what Mitsuba's `bumpmap` BSDF gives the shape it is on. Throws when `base`
    /// already has a normal or bump map.
    static std::shared_ptr<const SurfaceShading>
    withBumpMap(const SurfaceShading *base, std::shared_ptr<const Texture> heights, float scale);

    /// uv as textures see them (scaled by uvScale).
    Point2f textureUV(const Point2f &uv) const { return uv.cwiseProduct(m_uvScale); }
    /// Applies uvScale to the hit's uv and its derivatives (before the footprint is made).
    void scaleUV(Intersection &its) const;
    /// Perturbs the shading frame by the normal or bump map, if any.
    void perturbNormal(const Ray3f &ray, Intersection &its) const;
    /// Whether a lookup of the maps depends on the pixel footprint.
    bool usesFootprint() const;

private:
    Vector2f m_uvScale = Vector2f(1.0f, 1.0f);
    std::shared_ptr<const Texture> m_normalMap, m_bumpMap;
    float m_bumpScale = 1.0f;
};

/// An alpha mask: the opacity of a surface from a float texture (a shape's `alpha`,
/// pbrt-v4's `alpha`, Mitsuba's `mask` BSDF), looked up at the texture uv the shape's
/// uvScale gives.
class AlphaMask : public SurfaceOpacity {
public:
    /// `shape` is the shape it will be attached to (for its uvScale).
    AlphaMask(std::shared_ptr<const Texture> opacity, const Shape &shape);
    float opacityAtHit(const Point2f &shapeUV, const Point3f &p) const override;
    float opacityAt(const Point2f &textureUV, const Point3f &p) const override;

private:
    std::shared_ptr<const Texture> m_opacity;
    const Shape &m_shape;
};

/// Reads the parameters every shape plugin shares, `visible`, `alpha` (a float or float
/// texture: the opacity, 1 everywhere by default) and those of SurfaceShading::read, into
/// `shape`. Shape plugins call it from their constructor.
void readSurfaceParameters(Shape &shape, const PropertyList &props);

/// What the scene does to every hit after the shape's setHitInformation: applies the
/// uv scale, computes the pixel footprint from the ray's differentials, then perturbs
/// the shading frame by the normal or bump map.
void completeHit(const Ray3f &ray, Intersection &its);

/// uv as textures see them at a point of `shape` that did not come from a ray hit (a
/// sampled point of an area light).
Point2f textureUV(const Shape &shape, const Point2f &uv);

/// Whether a texture on the shape (its maps, its BSDF's or its light's) is filtered over
/// the pixel footprint, so rays hitting it need differentials.
bool usesFootprint(const Shape &shape);

} // namespace nori
