/*
 * homogeneous — a medium of constant density (PBR 4th ed. §11.4.1). Coloured coefficients
 * are sampled without bias by spectral MIS: the free-flight distance follows one channel
 * chosen uniformly, and its density is the average over the channels, the one-sample
 * balance heuristic (PBR 3rd ed. §15.2.1; Wilkie et al. 2014, "Hero wavelength spectral
 * sampling").
 *
 * Parameters:
 *   sigmaS, sigma_s  color  0     scattering coefficient (per unit length)
 *   sigmaA, sigma_a  color  0     absorption coefficient
 *   sigmaT, sigma_t  color  1     extinction coefficient σa + σs (instead of sigmaS and
 *                                 sigmaA)
 *   albedo  color  0.75  single-scattering albedo σs/σt, in [0, 1] (with sigmaT)
 *   scale   float  1     multiplies the coefficients (a unit change)
 *
 * Children: a <phase>, the phase function (isotropic by default).
 *
 *   <medium type="homogeneous" name="interior"><color name="sigmaS" value="0.5, 1, 2"/>
 *       <color name="sigmaA" value="0.05"/><phase type="hg"><float name="g"
 * value="0.7"/></phase></medium>
 */
#include <nori/medium.h>
#include <nori/phase.h>

namespace nori {
namespace {

class HomogeneousMedium : public Medium {
public:
    explicit HomogeneousMedium(const PropertyList &props) {
        readCoefficients(props, "homogeneous", m_sigmaT, m_albedo);
        m_sigmaS = m_sigmaT * m_albedo;
    }

    MediumSample sampleFreeFlight(const Ray3f &ray, PCG32 &rng) const override {
        const int channel = std::min(int(rng.nextFloat() * 3.0f), 2);
        const float distance = m_sigmaT[channel] > 0.0f
                                   ? -std::log1p(-rng.nextFloat()) / m_sigmaT[channel]
                                   : kInfinity;
        MediumSample result;
        result.scattered = distance < ray.maxt - ray.mint;
        result.t = result.scattered ? ray.mint + distance : ray.maxt;
        result.p = ray(result.t);
        const float travelled = result.t - ray.mint;
        // exp(−σt·∞) is 0 where σt > 0 and 1 where σt = 0 (not NaN).
        const Color3f transmittance =
            (m_sigmaT > 0.0f).select((-m_sigmaT * travelled).exp(), Color3f(1.0f));
        // The density of this outcome: σt·T per unit length at a collision, T for passing,
        // averaged over the three ways of choosing the channel.
        const Color3f density =
            result.scattered ? Color3f(m_sigmaT * transmittance) : transmittance;
        const float pdf = density.mean();
        if (!(pdf > 0.0f)) {
            result.weight = Color3f(0.0f);
            return result;
        }
        result.weight =
            (result.scattered ? Color3f(m_sigmaS * transmittance) : transmittance) / pdf;
        return result;
    }

    Color3f sigmaT(const Point3f &) const override { return m_sigmaT; }

    MajorantIterator majorants(const Ray3f &, float tMin, float tMax) const override {
        return MajorantIterator(tMin, tMax, m_sigmaT.maxCoeff());
    }

    std::string toString() const override {
        return fmt::format("HomogeneousMedium[sigmaT={}, albedo={}, phase={}]", m_sigmaT.toString(),
                           m_albedo.toString(), m_phase->toString());
    }

private:
    Color3f m_sigmaT, m_albedo, m_sigmaS;
};

NORI_REGISTER_CLASS(HomogeneousMedium, "homogeneous");

} // namespace
} // namespace nori
