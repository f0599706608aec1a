#include <nori/color.h>

#include <array>

namespace nori {

std::string Color3f::toString() const {
    return fmt::format("[{}, {}, {}]", r(), g(), b());
}

std::string Color4f::toString() const {
    return fmt::format("[{}, {}, {}, {}]", x(), y(), z(), w());
}

Color3f Color3f::toSRGB() const {
    Color3f result;
    for (int i = 0; i < 3; ++i) {
        float value = coeff(i);
        result[i] =
            value <= 0.0031308f ? 12.92f * value : 1.055f * std::pow(value, 1.0f / 2.4f) - 0.055f;
    }
    return result;
}

namespace {

/// The sRGB transfer function's inverse (IEC 61966-2-1).
float srgbToLinear(float value) {
    return value <= 0.04045f ? value * (1.0f / 12.92f)
                             : std::pow((value + 0.055f) * (1.0f / 1.055f), 2.4f);
}

/// srgbToLinear of the values 8-bit images decode to, k/255 as the decoders round it (k ·
/// (1/255) for PNG, k / 255 for JPEG and TGA), looked up: pow was most of the time a
/// large PNG texture took to load (31 % of loading 100 textures of 1024²). The table
/// holds srgbToLinear's own results, so a texture is the same to the bit; any other
/// value (16-bit and float files, colours) is computed.
class EightBitDecoding {
public:
    EightBitDecoding() {
        for (int k = 0; k < 256; ++k) {
            m_product[k] = static_cast<float>(k) * (1.0f / 255.0f);
            m_quotient[k] = static_cast<float>(k) / 255.0f;
            m_linearProduct[k] = srgbToLinear(m_product[k]);
            m_linearQuotient[k] = srgbToLinear(m_quotient[k]);
        }
    }

    float operator()(float value) const {
        const float scaled = value * 255.0f;
        if (!(scaled >= 0.0f && scaled <= 255.0f)) // NaN too
            return srgbToLinear(value);
        // The nearest k (scaled lies in [0, 255], so truncating scaled + 0.5 rounds it); the
        // comparisons below decide whether value is exactly one of the table's.
        const auto k = static_cast<size_t>(scaled + 0.5f); // NOLINT(bugprone-incorrect-roundings)
        if (value == m_product[k])
            return m_linearProduct[k];
        if (value == m_quotient[k])
            return m_linearQuotient[k];
        return srgbToLinear(value);
    }

private:
    std::array<float, 256> m_product, m_quotient, m_linearProduct, m_linearQuotient;
};

} // namespace

Color3f Color3f::toLinearRGB() const {
    static const EightBitDecoding decode;
    return Color3f(decode(r()), decode(g()), decode(b()));
}

} // namespace nori
