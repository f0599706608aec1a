/*
 * scale — a texture multiplied by another, or by a number (pbrt-v4's `scale` texture,
 * PBR 4th ed. §10.3.2): darkening a map, or a map that drives a scalar parameter with
 * the units it needs.
 *
 * Parameters:
 *   tex    color/texture  1  the texture (or colour) to scale
 *   scale  color/texture  1  what it is multiplied by, channel by channel
 *
 *   <bsdf type="diffuse">
 *       <texture type="scale" name="albedo">
 *           <texture type="checkerboard" name="tex"><float name="scale" value="8"/></texture>
 *           <float name="scale" value="0.5"/>
 *       </texture>
 *   </bsdf>
 */
#include <nori/proplist.h>
#include <nori/texture.h>

namespace nori {
namespace {

class ScaleTexture : public Texture {
public:
    explicit ScaleTexture(const PropertyList &props) {
        m_texture = m_parameters.color(props, "tex", Color3f(1.0f));
        m_scale = m_parameters.color(props, "scale", Color3f(1.0f));
    }

    Color3f eval(const TextureQuery &q) const override {
        return m_texture->eval(q) * m_scale->eval(q);
    }
    float evalFloat(const TextureQuery &q) const override {
        return m_texture->evalFloat(q) * m_scale->evalFloat(q);
    }
    /// Exact when either factor is constant; otherwise the product of the means (which
    /// only steers light selection and sampling weights).
    Color3f average() const override { return m_texture->average() * m_scale->average(); }
    float mipLevel(const TextureQuery &q) const override { return m_texture->mipLevel(q); }
    bool usesFootprint() const override {
        return m_texture->usesFootprint() || m_scale->usesFootprint();
    }
    bool isConstant() const override { return m_texture->isConstant() && m_scale->isConstant(); }

    std::string toString() const override {
        return fmt::format("ScaleTexture[tex={}, scale={}]", m_texture->toString(),
                           m_scale->toString());
    }

private:
    TextureParameters m_parameters;
    std::shared_ptr<const Texture> m_texture, m_scale;
};

NORI_REGISTER_CLASS(ScaleTexture, "scale");

} // namespace
} // namespace nori
