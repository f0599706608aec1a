/*
 * spectrum — the colour of a measured or tabulated spectrum: one of pbrt-v4's named
 * spectra (metal-Au-eta, glass-BK7, stdillum-D65, ...), a pbrt-v4 `.spd` file of
 * (wavelength, value) pairs, or pairs written inline; turned into linear sRGB once
 * (spectrum.h): an emission spectrum as light, anything else (a reflectance, a metal's η
 * or k) as seen under D65, where a flat 1 is white. A constant texture.
 *
 * Parameters:
 *   name      string  —            a named spectrum (one of name, filename, values)
 *   filename  string  —            a .spd file, relative to the scene file
 *   values    string  —            "λ:value, λ:value, ..." (nm), as Mitsuba writes them
 *   kind      string  "reflectance"  "reflectance" (also for η and k) or "emission"
 *   scale     float   1            multiplies the colour
 *
 *   <bsdf type="conductor">
 *       <texture type="spectrum" name="eta"><string name="name" value="metal-CuZn-eta"/></texture>
 *       <texture type="spectrum" name="k"><string name="name" value="metal-CuZn-k"/></texture>
 *   </bsdf>
 *
 *   <bsdf type="diffuse">
 *       <texture type="spectrum" name="albedo">
 *           <string name="values" value="400:0.1, 500:0.3, 600:0.8, 700:0.9"/></texture>
 *   </bsdf>
 */
#include <nori/proplist.h>
#include <nori/spectrum.h>
#include <nori/strutil.h>
#include <nori/texture.h>

namespace nori {
namespace {

class SpectrumTexture : public Texture {
public:
    explicit SpectrumTexture(const PropertyList &props) {
        const int sources =
            int(props.has("name")) + int(props.has("filename")) + int(props.has("values"));
        if (sources != 1)
            throw NoriException("spectrum: give exactly one of 'name', 'filename' and 'values'");
        PiecewiseLinearSpectrum spectrum;
        if (props.has("name")) {
            m_source = props.getString("name");
            spectrum = namedSpectrum(m_source);
        } else if (props.has("filename")) {
            m_source = props.getPath("filename");
            spectrum = readSpectrumFile(m_source);
        } else {
            m_source = props.getString("values");
            spectrum = parsePairs(m_source);
        }
        const std::string kind = props.getString("kind", "reflectance");
        if (kind != "reflectance" && kind != "emission")
            throw NoriException("spectrum: unknown kind '{}' (reflectance or emission)", kind);
        m_scale = props.getFloat("scale", 1.0f);
        auto function = [&spectrum](float lambda) { return spectrum(lambda); };
        m_color =
            m_scale * (kind == "emission" ? emissionToRGB(function) : reflectanceToRGB(function));
    }

    Color3f eval(const TextureQuery &) const override { return m_color; }
    Color3f average() const override { return m_color; }
    bool isConstant() const override { return true; }

    std::string toString() const override {
        return fmt::format("Spectrum[{}, scale={}, rgb=({}, {}, {})]", m_source, m_scale,
                           m_color.r(), m_color.g(), m_color.b());
    }

private:
    /// "λ:value" pairs separated by commas or spaces.
    static PiecewiseLinearSpectrum parsePairs(const std::string &text) {
        std::vector<float> lambdas, values;
        for (const std::string &pair : tokenize(text, ", \t\n")) {
            const size_t colon = pair.find(':');
            if (colon == std::string::npos)
                throw NoriException("spectrum: '{}' is not a wavelength:value pair", pair);
            lambdas.push_back(toFloat(pair.substr(0, colon), "wavelength"));
            values.push_back(toFloat(pair.substr(colon + 1), "spectrum value"));
        }
        if (lambdas.empty())
            throw NoriException("spectrum: 'values' holds no wavelength:value pairs");
        return PiecewiseLinearSpectrum(std::move(lambdas), std::move(values));
    }

    std::string m_source;
    float m_scale;
    Color3f m_color;
};

NORI_REGISTER_CLASS(SpectrumTexture, "spectrum");

} // namespace
} // namespace nori
