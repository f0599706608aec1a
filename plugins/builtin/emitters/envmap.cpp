/*
 * envmap — an environment map: radiance arriving from infinitely far away, read from a
 * latitude-longitude image (EXR or HDR; 8-bit images are sRGB-decoded). Mitsuba 3's
 * convention: a texel's u = φ/2π and v = θ/π map to the direction
 * (sin φ sin θ, cos θ, −cos φ sin θ) of the emitter's frame, +y is up and v = 0 is the
 * top row. Directions are importance-sampled from the piecewise-constant density
 * luminance × sin θ over texels (PBR 4th ed. §12.5.2), whose solid-angle density is
 * p(u, v)/(2π² sin θ). With mapping "equalarea" the image is instead a square in
 * Clarberg's equal-area octahedral map (pbrt-v4's environment maps; warp.h): u along the
 * frame's +x, v (down the rows) along +y, +z up; every texel then covers the same solid
 * angle 4π/(W·H), so the density is luminance alone and p(u, v)/4π per solid angle.
 * The radiance of a direction is its texel's (so that it matches
 * that density exactly), except for camera rays and specular chains, which see a
 * trilinear MIP lookup over their ray differentials. Rays that leave the scene see it;
 * its power is that through the disk of the scene's bounding sphere.
 *
 * Parameters:
 *   filename  string     (required)   the lat-long image, relative to the scene file
 *   scale, strength  float  1         multiplies the radiance (strength: the name
 *                                     Blender and several course scenes use)
 *   toWorld   transform  identity     orientation of the map (rotations)
 *   mapping   string     "latlong"    "latlong" or "equalarea" (a square image)
 *   sampling  string     "luminance"  "luminance" (importance sampling, above) or
 *                                     "uniform" (directions uniform over the sphere:
 *                                     only for comparisons, it is much noisier)
 *
 *   <emitter type="envmap">
 *       <string name="filename" value="scenes/textured/textures/sky.exr"/>
 *   </emitter>
 *
 *   <emitter type="envmap">
 *       <string name="filename" value="tests/data/envmaps/equalarea.pfm"/>
 *       <string name="mapping" value="equalarea"/>
 *   </emitter>
 *
 *   <emitter type="environment">
 *       <string name="filename" value="scenes/textured/textures/sky.exr"/>
 *       <float name="strength" value="2"/>
 *   </emitter>
 *
 * Also registered as: environment.
 */
#include <nori/bbox.h>
#include <nori/dpdf.h>
#include <nori/emitter.h>
#include <nori/loadahead.h>
#include <nori/proplist.h>
#include <nori/texturecache.h>
#include <nori/transform.h>
#include <nori/warp.h>

namespace nori {
namespace {

class EnvironmentMap : public Emitter {
public:
    explicit EnvironmentMap(const PropertyList &props) {
        m_filename = props.getPath("filename");
        m_scale = props.getFloat(props.spelling("scale", {"strength"}), 1.0f);
        if (!(m_scale >= 0.0f) || !std::isfinite(m_scale))
            throw NoriException("envmap: 'scale' must be finite and not negative, got {}", m_scale);
        m_toWorld = props.getTransform("toWorld", Transform());
        m_toLocal = m_toWorld.inverse();
        const std::string sampling = props.getString("sampling", "luminance");
        if (sampling != "luminance" && sampling != "uniform")
            throw NoriException("envmap: unknown sampling '{}' (use luminance or uniform)",
                                sampling);
        m_uniform = sampling == "uniform";
        const std::string mapping = props.getString("mapping", "latlong");
        if (mapping != "latlong" && mapping != "equalarea")
            throw NoriException("envmap: unknown mapping '{}' (use latlong or equalarea)", mapping);
        m_equalArea = mapping == "equalarea";
        m_mipmap = loadTextureImage(m_filename, ColorSpace::Auto);
        if (m_equalArea && m_mipmap->level(0).width() != m_mipmap->level(0).height())
            throw NoriException("envmap: an equal-area map is square, but '{}' is {}x{}",
                                m_filename, m_mipmap->level(0).width(),
                                m_mipmap->level(0).height());
        buildDistribution();
    }

    bool isInfinite() const override { return true; }

    void setSceneBounds(const BoundingBox3f &bounds) override { m_scene.set(bounds); }

    Color3f sample(EmitterQueryRecord &lRec, const Point2f &sample) const override {
        lRec.dwdx = lRec.dwdy = Vector3f::Zero();
        if (m_uniform) {
            lRec.wi = Warp::squareToUniformSphere(sample);
            lRec.pdf = Warp::squareToUniformSpherePdf(lRec.wi);
            m_scene.placeBeyond(lRec);
            return eval(lRec) / lRec.pdf;
        }
        float uvPdf;
        Vector2i texel;
        Point2f uv = m_distribution.sampleContinuous(sample, uvPdf, texel);
        if (uvPdf <= 0.0f)
            return Color3f(0.0f);
        // The direction must read back as the texel it was drawn in: eval() and pdf() find
        // a direction's texel from it, and one that rounds into a neighbour would be
        // weighted by the neighbour's radiance over this texel's density (a sun texel's
        // edge samples lost its light; a sky texel's beside the sun were fireflies). A
        // sample whose round trip lands next door moves toward the texel's centre, by a
        // distance that doubles from a millionth of the texel; the density moves by as
        // much, far below any estimate's noise.
        const Bitmap &image = m_mipmap->level(0);
        const Point2f centre((texel.x() + 0.5f) / float(image.width()),
                             (texel.y() + 0.5f) / float(image.height()));
        float sinTheta = 0.0f;
        for (float pull = 1e-6f;; pull *= 2.0f) {
            Vector3f local;
            if (m_equalArea) {
                local = Warp::squareToEqualAreaSphere(uv);
                sinTheta = 1.0f; // (unused: the map's texels all cover the same solid angle)
            } else {
                const float theta = uv.y() * kPi, phi = uv.x() * 2.0f * kPi;
                sinTheta = std::sin(theta);
                local =
                    Vector3f(std::sin(phi) * sinTheta, std::cos(theta), -std::cos(phi) * sinTheta);
            }
            lRec.wi = Vector3f(m_toWorld * local).normalized();
            if (sinTheta > 0.0f && texelOf(toUV(lRec.wi)) == texel)
                break;
            if (pull > 0.5f)
                return Color3f(0.0f);
            uv += pull * (centre - uv);
        }
        lRec.pdf = m_equalArea ? uvPdf * kInvFourPi : uvPdf / (2.0f * kPi * kPi * sinTheta);
        m_scene.placeBeyond(lRec); // a point beyond the scene, for the shadow ray
        return eval(lRec) / lRec.pdf;
    }

    // A direction from the map's own density (by luminance), then a point of the bounding
    // sphere's disk facing it: L(ω)·πr²/pdf_ω.
    Color3f sampleEmission(EmissionSample &emission, const Point2f &positionSample,
                           const Point2f &directionSample) const override {
        EmitterQueryRecord lRec(m_scene.center);
        Color3f radianceOverPdf = sample(lRec, directionSample);
        if ((radianceOverPdf == 0.0f).all())
            return radianceOverPdf;
        emission.density.direction = lRec.pdf;
        return radianceOverPdf * m_scene.photonRayFrom(lRec.wi, positionSample, emission);
    }

    EmissionDensity emissionDensity(const Point3f &, const Normal3f &,
                                    const Vector3f &direction) const override {
        return densityAtInfinity(m_scene, direction);
    }

    Color3f eval(const EmitterQueryRecord &lRec) const override {
        const Point2f uv = toUV(lRec.wi);
        if (lRec.dwdx.isZero() && lRec.dwdy.isZero())
            return m_scale * m_mipmap->nearest(uv, MIPMap::Wrap::Repeat);
        // (The equal-area square's edges meet mirrored, which no wrap mode follows: its
        // filtered lookups clamp there.)
        const MIPMap::Wrap wrap = m_equalArea ? MIPMap::Wrap::Clamp : MIPMap::Wrap::Repeat;
        // A filtered lookup over the footprint of the directions dw/dx, dw/dy (u wraps).
        auto difference = [&](const Vector3f &dw) {
            Vector2f d = toUV((lRec.wi + dw).normalized()) - uv;
            if (!m_equalArea)
                d.x() -= std::round(d.x());
            return d;
        };
        return m_scale *
               m_mipmap->trilinear(uv, difference(lRec.dwdx), difference(lRec.dwdy), wrap);
    }

    float pdf(const EmitterQueryRecord &lRec) const override {
        if (m_uniform)
            return Warp::squareToUniformSpherePdf(lRec.wi);
        if (m_equalArea)
            return m_distribution.pdf(toUV(lRec.wi)) * kInvFourPi;
        // sin θ from the horizontal components: accurate near the poles, where
        // √(1 − cos²θ) loses its digits.
        const Vector3f local = Vector3f(m_toLocal * lRec.wi).normalized();
        const float sinTheta = std::hypot(local.x(), local.z());
        if (sinTheta <= 0.0f)
            return 0.0f;
        return m_distribution.pdf(toUV(lRec.wi)) / (2.0f * kPi * kPi * sinTheta);
    }

    /// Φ = π r² ∫ L dω: the radiance of every direction crossing the disk of the scene's
    /// bounding sphere, with ∫ L dω = Σ L·(2π/W)(cos θ₀ − cos θ₁) over texels.
    Color3f getPower() const override { return m_integral * m_scene.diskArea(); }

    std::string toString() const override {
        const Bitmap &image = m_mipmap->level(0);
        return fmt::format("EnvironmentMap[filename=\"{}\", {}x{}, scale={}, mapping={}]",
                           m_filename, image.width(), image.height(), m_scale,
                           m_equalArea ? "equalarea" : "latlong");
    }

private:
    /// Texel-constant density over (u, v) ∝ luminance × sin θ at the texel's centre row.
    void buildDistribution() {
        const Bitmap &image = m_mipmap->level(0);
        const int width = image.width(), height = image.height();
        std::vector<float> weights(static_cast<size_t>(width) * height);
        Color3f integral(0.0f);
        double total = 0.0;
        for (int y = 0; y < height; ++y) {
            // The row's exact solid angle per texel is (2π/W)(cos θ₀ − cos θ₁); the midpoint
            // rule's (2π/W)(π/H) sin θ overstates it (by 0.16% at H = 16). An equal-area
            // map's texels all cover (2π/W)·(2/H) = 4π/(W·H).
            const float sinTheta = m_equalArea ? 1.0f : std::sin((y + 0.5f) * kPi / height);
            const float rowSolidAngle =
                m_equalArea ? 2.0f / float(height)
                            : std::cos(y * kPi / height) - std::cos((y + 1) * kPi / height);
            for (int x = 0; x < width; ++x) {
                const Color3f value = image(y, x).max(0.0f);
                const float weight = value.getLuminance() * sinTheta;
                weights[static_cast<size_t>(y) * width + x] = std::max(weight, 0.0f);
                total += weights[static_cast<size_t>(y) * width + x];
                integral += value * rowSolidAngle;
            }
        }
        // A black map: sample uniformly over (u, v) (it is never picked by power anyway).
        if (!(total > 0.0))
            std::fill(weights.begin(), weights.end(), 1.0f);
        m_distribution = Distribution2D(weights, width, height);
        m_integral = m_scale * integral * (2.0f * kPi / float(width));
    }

    /// (u, v) of a world direction: θ from the frame's +y, φ from its −z toward +x. θ by
    /// atan2 of the horizontal length and the height: acos(y) loses half its digits near
    /// the poles (a float y within 6e-8 of 1 leaves θ uncertain by 3.5e-4).
    Point2f toUV(const Vector3f &world) const {
        const Vector3f local = Vector3f(m_toLocal * world).normalized();
        if (m_equalArea) {
            const Point2f uv = Warp::equalAreaSphereToSquare(local);
            return Point2f(std::clamp(uv.x(), 0.0f, 1.0f - 1e-7f),
                           std::clamp(uv.y(), 0.0f, 1.0f - 1e-7f));
        }
        const float theta = std::atan2(std::hypot(local.x(), local.z()), local.y());
        float phi = std::atan2(local.x(), -local.z());
        if (phi < 0.0f)
            phi += 2.0f * kPi;
        return Point2f(std::min(phi * kInvTwoPi, 1.0f - 1e-7f),
                       std::min(theta * kInvPi, 1.0f - 1e-7f));
    }

    /// The texel of level 0 that (u, v) in [0, 1)² falls in, as nearest() and the
    /// distribution's pdf() find it.
    Vector2i texelOf(const Point2f &uv) const {
        const Bitmap &image = m_mipmap->level(0);
        return Vector2i(
            std::min(static_cast<int>(uv.x() * float(image.width())), image.width() - 1),
            std::min(static_cast<int>(uv.y() * float(image.height())), image.height() - 1));
    }

    std::string m_filename;
    float m_scale;
    bool m_uniform;   ///< sample directions uniformly instead of by luminance
    bool m_equalArea; ///< a square equal-area map instead of a lat-long one
    Transform m_toWorld, m_toLocal;
    std::shared_ptr<const MIPMap> m_mipmap;
    Distribution2D m_distribution;
    Color3f m_integral; ///< ∫ L dω over the sphere
    SceneBoundingSphere m_scene;
};

NORI_REGISTER_CLASS(EnvironmentMap, "envmap");
NORI_REGISTER_LOAD_AHEAD(EnvironmentMap, "envmap", kTextureImageReader);
NORI_REGISTER_ALIAS(EnvironmentMap, "environment", environment);

} // namespace
} // namespace nori
