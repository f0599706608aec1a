/*
 * mask — makes a surface partly absent by an opacity (Mitsuba 0.6 documentation, "mask"):
 * where the opacity is 0 there is no surface, where it is 1 the nested BSDF, in between
 * the surface is there at that fraction of its points (shape.h, surfacePresent). Light,
 * camera and shadow rays pass through the holes, so a cut-out leaf casts a cut-out
 * shadow. It is the same as the shape's own `alpha` parameter: attached to a shape, it
 * gives the shape its alpha mask and the nested BSDF.
 *
 * Parameters:
 *   opacity  float/texture  0.5  the fraction of the surface that is there, in [0, 1]
 *
 * Children: one nested <bsdf>, the surface where it is there.
 *
 *   <mesh type="rectangle">
 *       <bsdf type="mask">
 *           <texture type="checkerboard" name="opacity"><color name="color0" value="0"/>
 *               <color name="color1" value="1"/></texture>
 *           <bsdf type="diffuse"/>
 *       </bsdf>
 *   </mesh>
 */
#include <nori/bsdf.h>
#include <nori/shading.h>
#include <nori/shape.h>

namespace nori {
namespace {

class Mask : public BSDF {
public:
    explicit Mask(const PropertyList &props) {
        m_opacity = m_textures.scalar(props, "opacity", 0.5f, 0.0f, 1.0f);
    }

    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override {
        if (child->getClassType() != EBSDF)
            return BSDF::addChild(child, name);
        if (m_nested)
            throw NoriException("mask: takes one nested BSDF, got a second");
        m_nested = std::static_pointer_cast<BSDF>(child);
    }

    void activate() override {
        if (!m_nested)
            m_nested = createDefault<BSDF>("diffuse"); // Mitsuba's default
    }

    /// On a shape: its alpha mask is the opacity, its BSDF the nested one.
    bool attachTo(NoriObject &parent, const std::string &name) override {
        auto *shape = dynamic_cast<Shape *>(&parent);
        if (!shape)
            return BSDF::attachTo(parent, name);
        if (!m_nested)
            activate();
        shape->setOpacity(std::make_shared<AlphaMask>(m_opacity, *shape));
        return m_nested->attachTo(parent, name);
    }

    // Elsewhere (a test of the BSDF alone), the surface where it is there.
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
        return fmt::format("Mask[opacity={}, {}]", m_opacity->toString(),
                           m_nested ? m_nested->toString() : "");
    }

private:
    std::shared_ptr<const Texture> m_opacity;
    std::shared_ptr<BSDF> m_nested;
};

NORI_REGISTER_CLASS(Mask, "mask");

} // namespace
} // namespace nori
