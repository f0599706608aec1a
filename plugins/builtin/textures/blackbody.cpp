/*
 * blackbody — the colour of a blackbody's light: Planck's law at `temperature`,
 * normalised to 1 at its peak as pbrt-v4's `blackbody` spectra are, turned into linear sRGB
 * as every spectrum is (spectrum.h: integrated against the CIE 1931 matching functions,
 * then to sRGB). A constant texture, for any colour that may be a texture (an area light's
 * or an environment's radiance, say).
 *
 * Parameters:
 *   temperature  float  6500  in kelvin, positive
 *   scale        float  1     multiplies the colour
 *
 *   <mesh type="sphere"><float name="radius" value="0.2"/>
 *       <emitter type="area">
 *           <texture type="blackbody" name="radiance"><float name="temperature" value="3000"/>
 *               <float name="scale" value="40"/></texture>
 *       </emitter>
 *   </mesh>
 */
#include <nori/proplist.h>
#include <nori/spectrum.h>
#include <nori/texture.h>

namespace nori {
namespace {

class Blackbody : public Texture {
public:
    explicit Blackbody(const PropertyList &props) {
        m_temperature = props.getFloat("temperature", 6500.0f);
        m_scale = props.getFloat("scale", 1.0f);
        if (!(m_temperature > 0.0f) || !std::isfinite(m_temperature))
            throw NoriException("blackbody: 'temperature' must be positive, got {}", m_temperature);
        if (!std::isfinite(m_scale))
            throw NoriException("blackbody: 'scale' must be finite");
        const float temperature = m_temperature;
        m_color = m_scale * emissionToRGB([temperature](float lambda) {
                      return normalizedBlackbody(lambda, temperature);
                  });
    }

    Color3f eval(const TextureQuery &) const override { return m_color; }
    Color3f average() const override { return m_color; }
    bool isConstant() const override { return true; }

    std::string toString() const override {
        return fmt::format("Blackbody[temperature={}, scale={}, rgb=({}, {}, {})]", m_temperature,
                           m_scale, m_color.r(), m_color.g(), m_color.b());
    }

private:
    float m_temperature, m_scale;
    Color3f m_color;
};

NORI_REGISTER_CLASS(Blackbody, "blackbody");

} // namespace
} // namespace nori
