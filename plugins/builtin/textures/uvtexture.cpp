/*
 * uvtexture — ETH's 2024 texture-coordinate test pattern: the colour (r, g, 0.5) with
 * r = |fmod(u, 1)|·(1 − 0.2 sin(Cu) sin(Cv)) and g = |fmod(v, 1)|·(1 − 0.2 cos(Cu) sin(Cv)),
 * C = 16π: a red ramp along u, a green one along v, and a faint 8 × 8 ripple, so that
 * a wrong uv parameterisation (swapped, flipped, or not wrapping) shows at a glance.
 *
 * No parameters.
 *
 *   <bsdf type="diffuse">
 *       <texture type="uvtexture" name="albedo"/>
 *   </bsdf>
 */
#include <nori/proplist.h>
#include <nori/texture.h>

namespace nori {
namespace {

class UVTexture : public Texture {
public:
    explicit UVTexture(const PropertyList &props) { (void)props; }

    Color3f eval(const TextureQuery &q) const override {
        constexpr float kFrequency = 16.0f * kPi;
        const float u = q.uv.x(), v = q.uv.y();
        const float ripple = std::sin(kFrequency * v);
        const float r =
            std::abs(std::fmod(u, 1.0f)) * (1.0f - 0.2f * std::sin(kFrequency * u) * ripple);
        const float g =
            std::abs(std::fmod(v, 1.0f)) * (1.0f - 0.2f * std::cos(kFrequency * u) * ripple);
        return Color3f(r, g, 0.5f);
    }

    // Over the unit square the ripple averages out (sin(Cv) has 8 whole periods), leaving
    // the mean of the ramps, 1/2.
    Color3f average() const override { return Color3f(0.5f); }

    std::string toString() const override { return "UVTexture[]"; }
};

NORI_REGISTER_CLASS(UVTexture, "uvtexture");

} // namespace
} // namespace nori
