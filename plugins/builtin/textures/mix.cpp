/*
 * mix — a blend of two textures by a third, (1 − amount)·tex1 + amount·tex2 (pbrt-v4's
 * `mix` texture, PBR 4th ed. §10.3.2): moss over stone by a mask, rust by a noise.
 *
 * Parameters:
 *   tex1    color/texture  0    where amount is 0
 *   tex2    color/texture  1    where amount is 1
 *   amount  float/texture  0.5  the blend (its luminance, for a colour texture)
 *
 *   <bsdf type="diffuse">
 *       <texture type="mix" name="albedo">
 *           <color name="tex1" value="0.8, 0.2, 0.1"/> <color name="tex2" value="0.1, 0.3, 0.8"/>
 *           <texture type="checkerboard" name="amount"><color name="color0" value="0"/>
 *               <color name="color1" value="1"/></texture>
 *       </texture>
 *   </bsdf>
 */
#include <nori/proplist.h>
#include <nori/texture.h>

namespace nori {
namespace {

class MixTexture : public Texture {
public:
    explicit MixTexture(const PropertyList &props) {
        m_first = m_parameters.color(props, "tex1", Color3f(0.0f));
        m_second = m_parameters.color(props, "tex2", Color3f(1.0f));
        m_amount = m_parameters.scalar(props, "amount", 0.5f);
    }

    Color3f eval(const TextureQuery &q) const override {
        const float amount = m_amount->evalFloat(q);
        // pbrt-v4 skips a texture whose weight is exactly zero.
        const Color3f first = amount != 1.0f ? m_first->eval(q) : Color3f(0.0f);
        const Color3f second = amount != 0.0f ? m_second->eval(q) : Color3f(0.0f);
        return (1.0f - amount) * first + amount * second;
    }
    float evalFloat(const TextureQuery &q) const override {
        const float amount = m_amount->evalFloat(q);
        const float first = amount != 1.0f ? m_first->evalFloat(q) : 0.0f;
        const float second = amount != 0.0f ? m_second->evalFloat(q) : 0.0f;
        return (1.0f - amount) * first + amount * second;
    }
    /// Exact when the amount is constant; otherwise a blend by its mean (which only
    /// steers light selection and sampling weights).
    Color3f average() const override {
        const float amount = m_amount->average().getLuminance();
        return (1.0f - amount) * m_first->average() + amount * m_second->average();
    }
    bool usesFootprint() const override {
        return m_first->usesFootprint() || m_second->usesFootprint() || m_amount->usesFootprint();
    }
    bool isConstant() const override {
        return m_first->isConstant() && m_second->isConstant() && m_amount->isConstant();
    }

    std::string toString() const override {
        return fmt::format("MixTexture[tex1={}, tex2={}, amount={}]", m_first->toString(),
                           m_second->toString(), m_amount->toString());
    }

private:
    TextureParameters m_parameters;
    std::shared_ptr<const Texture> m_first, m_second, m_amount;
};

NORI_REGISTER_CLASS(MixTexture, "mix");

} // namespace
} // namespace nori
