#include <nori/color.h>

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

Color3f Color3f::toLinearRGB() const {
    Color3f result;
    for (int i = 0; i < 3; ++i) {
        float value = coeff(i);
        result[i] = value <= 0.04045f ? value * (1.0f / 12.92f)
                                      : std::pow((value + 0.055f) * (1.0f / 1.055f), 2.4f);
    }
    return result;
}

} // namespace nori
