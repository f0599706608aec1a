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
#include <nori/nestedbsdf.h>
#include <nori/proplist.h>
#include <nori/shading.h>
#include <nori/shape.h>

namespace nori {
namespace {

class BumpMap : public SurfaceWrapperBSDF {
public:
    explicit BumpMap(const PropertyList &props) : SurfaceWrapperBSDF("bumpmap") {
        if (props.holdsObject("height")) {
            m_heights = std::dynamic_pointer_cast<const Texture>(props.getObject("height"));
            if (!m_heights)
                throw NoriException("bumpmap: 'height' must be a texture");
        } else if (props.has("height")) {
            m_heights = m_textures.scalar(props, "height", 0.0f);
        }
        m_scale = props.getFloat("scale", 1.0f);
    }

    /// Takes the height field as a texture child without a name too (Mitsuba's way).
    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override {
        if (child->getClassType() != ETexture)
            return SurfaceWrapperBSDF::addChild(child, name);
        if (m_heights)
            throw NoriException("bumpmap: takes one height texture, got a second");
        m_heights = std::static_pointer_cast<const Texture>(child);
    }

    void activate() override {
        if (!m_heights)
            throw NoriException("bumpmap: needs a height texture ('height' or a <texture> child)");
        SurfaceWrapperBSDF::activate();
    }

    std::string toString() const override {
        return fmt::format("BumpMap[height={}, scale={}, {}]",
                           m_heights ? m_heights->toString() : "", m_scale, nestedToString());
    }

private:
    /// The shape's bump map is the height field (its uvScale stays).
    void decorate(Shape &shape) override {
        shape.setSurfaceShading(
            SurfaceShading::withBumpMap(shape.getSurfaceShading(), m_heights, m_scale));
    }

    std::shared_ptr<const Texture> m_heights;
    float m_scale;
};

NORI_REGISTER_CLASS(BumpMap, "bumpmap");

} // namespace
} // namespace nori
