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
#include <nori/nestedbsdf.h>
#include <nori/shading.h>
#include <nori/shape.h>

namespace nori {
namespace {

class Mask : public SurfaceWrapperBSDF {
public:
    explicit Mask(const PropertyList &props) : SurfaceWrapperBSDF("mask") {
        m_opacity = m_textures.scalar(props, "opacity", 0.5f, 0.0f, 1.0f);
    }

    void activate() override {
        if (nestedCount() == 0)
            addNested(createDefault<BSDF>("diffuse")); // Mitsuba's default
    }

    std::string toString() const override {
        return fmt::format("Mask[opacity={}, {}]", m_opacity->toString(), nestedToString());
    }

private:
    /// The shape's alpha mask is the opacity.
    void decorate(Shape &shape) override {
        shape.setOpacity(std::make_shared<AlphaMask>(m_opacity, shape));
    }

    std::shared_ptr<const Texture> m_opacity;
};

NORI_REGISTER_CLASS(Mask, "mask");

} // namespace
} // namespace nori
