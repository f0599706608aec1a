/*
 * miplevel — a debugging view of texture filtering: at the first hit, the MIP level
 * that the surface's first MIP-mapped texture (of its BSDF) uses there, from the ray
 * differentials: 0 is the full-resolution image. Shown as a colour ramp (blue 0, cyan
 * 1, green 2, yellow 3, red 4, magenta 5 and more, blended between integer levels), or
 * as the level itself with `raw`; black where the ray escapes or the surface has no
 * MIP-mapped texture.
 *
 * Parameters:
 *   raw  boolean  false  output the level as a grey value instead of the ramp
 *
 *   <integrator type="miplevel"/>
 */
#include <nori/bsdf.h>
#include <nori/integrator.h>
#include <nori/scene.h>

#include <array>

namespace nori {
namespace {

class MipLevelIntegrator : public Integrator {
public:
    explicit MipLevelIntegrator(const PropertyList &props) {
        m_raw = props.getBoolean("raw", false);
    }

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        (void)sampler;
        Intersection its;
        if (!scene->rayIntersect(ray, its))
            return Color3f(0.0f);
        const TextureQuery query(its);
        for (const auto &texture : its.shape->getBSDF()->textures().all()) {
            const float level = texture->mipLevel(query);
            if (level >= 0.0f)
                return m_raw ? Color3f(level) : ramp(level);
        }
        return Color3f(0.0f);
    }

    std::string toString() const override {
        return fmt::format("MipLevelIntegrator[raw={}]", m_raw);
    }

private:
    static Color3f ramp(float level) {
        static const std::array<Color3f, 6> kColors = {
            Color3f(0.0f, 0.0f, 1.0f), Color3f(0.0f, 1.0f, 1.0f), Color3f(0.0f, 1.0f, 0.0f),
            Color3f(1.0f, 1.0f, 0.0f), Color3f(1.0f, 0.0f, 0.0f), Color3f(1.0f, 0.0f, 1.0f)};
        const float clamped = std::min(level, static_cast<float>(kColors.size() - 1));
        const int lower = static_cast<int>(clamped);
        const int upper = std::min(lower + 1, static_cast<int>(kColors.size() - 1));
        const float blend = clamped - lower;
        return (1.0f - blend) * kColors[lower] + blend * kColors[upper];
    }

    bool m_raw;
};

NORI_REGISTER_CLASS(MipLevelIntegrator, "miplevel");

} // namespace
} // namespace nori
