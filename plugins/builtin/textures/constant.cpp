/*
 * constant — the same colour everywhere. A plain <color> or <float> given for a
 * textured parameter becomes one of these.
 *
 * Parameters:
 *   value  color  (required)  the colour (a <float> gives a grey)
 *
 *   <bsdf type="diffuse">
 *       <texture type="constant" name="albedo"><color name="value" value="0.3, 0.5,
 * 0.7"/></texture>
 *   </bsdf>
 */
#include <nori/proplist.h>
#include <nori/texture.h>

namespace nori {
namespace {

class ConstantTexture : public Texture {
public:
    explicit ConstantTexture(const PropertyList &props) { m_value = props.getColor("value"); }

    Color3f eval(const TextureQuery &) const override { return m_value; }
    Color3f average() const override { return m_value; }
    bool isConstant() const override { return true; }

    std::string toString() const override {
        return fmt::format("({}, {}, {})", m_value.r(), m_value.g(), m_value.b());
    }

private:
    Color3f m_value;
};

NORI_REGISTER_CLASS(ConstantTexture, "constant");

} // namespace
} // namespace nori
