/*
 * bumpmap — bump mapping by any float texture, as Mitsuba's `bumpmap` BSDF wraps another
 * (Mitsuba 0.6 documentation, "bumpmap"; Blinn 1978): the texture is a height field
 * along the normal, and the shading normal follows its slopes (shading.h). Attached to a
 * shape, it gives the shape that bump map (as its `bump` parameter would) and the nested
 * BSDF; the shape keeps its uvScale.
 *
 * Parameters:
 *   height  float/texture  (required)  the height field (a texture child without a
 *                                      name also serves, as Mitsuba writes it)
 *   scale   float          1           the heights are multiplied by this
 *
 * Children: one nested <bsdf>, the surface.
 *
 *   <mesh type="rectangle">
 *       <bsdf type="bumpmap">
 *           <texture type="checkerboard" name="height"><float name="scale" value="8"/>
 *               <color name="color0" value="0"/><color name="color1" value="0.01"/></texture>
 *           <bsdf type="roughconductor"/>
 *       </bsdf>
 *   </mesh>
 */
#include <nori/bsdf.h>
#include <nori/proplist.h>
#include <nori/shading.h>
#include <nori/shape.h>

namespace nori {
namespace {

class BumpMap : public BSDF {
public:
    explicit BumpMap(const PropertyList &props) {
        if (props.holdsObject("height")) {
            m_heights = std::dynamic_pointer_cast<const Texture>(props.getObject("height"));
            if (!m_heights)
                throw NoriException("bumpmap: 'height' must be a texture");
        } else if (props.has("height")) {
            m_heights = m_textures.scalar(props, "height", 0.0f);
        }
        m_scale = props.getFloat("scale", 1.0f);
    }

    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override {
        if (child->getClassType() == ETexture) {
            if (m_heights)
                throw NoriException("bumpmap: takes one height texture, got a second");
            m_heights = std::static_pointer_cast<const Texture>(child);
            return;
        }
        if (child->getClassType() != EBSDF)
            return BSDF::addChild(child, name);
        if (m_nested)
            throw NoriException("bumpmap: takes one nested BSDF, got a second");
        m_nested = std::static_pointer_cast<BSDF>(child);
    }

    void activate() override {
        if (!m_heights)
            throw NoriException("bumpmap: needs a height texture ('height' or a <texture> child)");
        if (!m_nested)
            throw NoriException("bumpmap: needs a nested <bsdf>, the surface");
    }

    /// On a shape: the shape's bump map is the height field, its BSDF the nested one.
    bool attachTo(NoriObject &parent, const std::string &name) override {
        auto *shape = dynamic_cast<Shape *>(&parent);
        if (!shape)
            return BSDF::attachTo(parent, name);
        activate();
        shape->setSurfaceShading(
            SurfaceShading::withBumpMap(shape->getSurfaceShading(), m_heights, m_scale));
        return m_nested->attachTo(parent, name);
    }

    // Elsewhere (a test of the BSDF alone), the flat surface.
    Color3f sample(BSDFQueryRecord &bRec, const Point2f &sample) const override {
        return m_nested->sample(bRec, sample);
    }
    Color3f eval(const BSDFQueryRecord &bRec) const override { return m_nested->eval(bRec); }
    float pdf(const BSDFQueryRecord &bRec) const override { return m_nested->pdf(bRec); }
    bool isDiffuse() const override { return m_nested->isDiffuse(); }
    Color3f albedo(const BSDFQueryRecord &bRec) const override { return m_nested->albedo(bRec); }
    int discreteLobes(const BSDFQueryRecord &bRec, DiscreteLobe *lobes) const override {
        return m_nested->discreteLobes(bRec, lobes);
    }

    std::string toString() const override {
        return fmt::format("BumpMap[height={}, scale={}, {}]",
                           m_heights ? m_heights->toString() : "", m_scale,
                           m_nested ? m_nested->toString() : "");
    }

private:
    std::shared_ptr<const Texture> m_heights;
    float m_scale;
    std::shared_ptr<BSDF> m_nested;
};

NORI_REGISTER_CLASS(BumpMap, "bumpmap");

} // namespace
} // namespace nori
