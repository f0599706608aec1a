/*
 * checkerboard — two colours in a checker pattern over uv, filtered over the lookup's
 * footprint in closed form (the box-filtered step function of pbrt-v3 §10.5.3), so a
 * receding floor fades to the mean instead of aliasing.
 *
 * Parameters:
 *   color0  color  0.4  colour of the cells whose indices ⌊u·scale⌋ + ⌊v·scale⌋ are even
 *   color1  color  0.2  colour of the other cells
 *   scale   float  2    cells per unit of u and of v
 *
 *   <bsdf type="diffuse">
 *       <texture type="checkerboard" name="albedo"><float name="scale" value="8"/></texture>
 *   </bsdf>
 */
#include <nori/proplist.h>
#include <nori/texture.h>

#include <algorithm>

namespace nori {
namespace {

class Checkerboard : public Texture {
public:
    explicit Checkerboard(const PropertyList &props) {
        m_color0 = props.getColor("color0", Color3f(0.4f));
        m_color1 = props.getColor("color1", Color3f(0.2f));
        m_scale = props.getFloat("scale", 2.0f);
        if (!(m_scale > 0.0f) || !std::isfinite(m_scale))
            throw NoriException("checkerboard: 'scale' must be positive, got {}", m_scale);
    }

    Color3f eval(const TextureQuery &q) const override {
        const double s = double(q.uv.x()) * m_scale, t = double(q.uv.y()) * m_scale;
        if (!std::isfinite(s) || !std::isfinite(t))
            return average();
        // Half-widths of the footprint's bounding box in cell units.
        const double ds = std::max(std::abs(q.dudx), std::abs(q.dudy)) * double(m_scale);
        const double dt = std::max(std::abs(q.dvdx), std::abs(q.dvdy)) * double(m_scale);
        if (std::floor(s - ds) == std::floor(s + ds) && std::floor(t - dt) == std::floor(t + dt))
            return parity(std::floor(s) + std::floor(t)) ? m_color1 : m_color0;
        if (ds > 1.0 || dt > 1.0)
            return average();
        // Fraction of the box in "odd" cells: the integral of the 1D square wave over each
        // axis, combined as for a XOR of the two (pbrt-v3 eq. 10.9).
        const double oddS = (stepIntegral(s + ds) - stepIntegral(s - ds)) / (2.0 * ds);
        const double oddT = (stepIntegral(t + dt) - stepIntegral(t - dt)) / (2.0 * dt);
        const double odd = ds == 0.0 ? (parity(std::floor(s)) ? 1.0 : 0.0) * (1.0 - oddT) +
                                           (parity(std::floor(s)) ? 0.0 : 1.0) * oddT
                           : dt == 0.0 ? (parity(std::floor(t)) ? 1.0 : 0.0) * (1.0 - oddS) +
                                             (parity(std::floor(t)) ? 0.0 : 1.0) * oddS
                                       : oddS + oddT - 2.0 * oddS * oddT;
        return float(1.0 - odd) * m_color0 + float(odd) * m_color1;
    }

    Color3f average() const override { return 0.5f * (m_color0 + m_color1); }
    bool usesFootprint() const override { return true; }

    std::string toString() const override {
        return fmt::format("Checkerboard[color0=({}, {}, {}), color1=({}, {}, {}), scale={}]",
                           m_color0.r(), m_color0.g(), m_color0.b(), m_color1.r(), m_color1.g(),
                           m_color1.b(), m_scale);
    }

private:
    static bool parity(double cellSum) { return std::fmod(std::abs(cellSum), 2.0) == 1.0; }

    /// ∫₀ˣ of the square wave that is 1 on odd cells [2k+1, 2k+2): ⌊x/2⌋ + max(x/2 −
    /// ⌊x/2⌋ − ½, 0)·2 (pbrt-v3's BUMPINT).
    static double stepIntegral(double x) {
        const double half = x / 2.0;
        return std::floor(half) + 2.0 * std::max(half - std::floor(half) - 0.5, 0.0);
    }

    Color3f m_color0, m_color1;
    float m_scale;
};

NORI_REGISTER_CLASS(Checkerboard, "checkerboard");

} // namespace
} // namespace nori
