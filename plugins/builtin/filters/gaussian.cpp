/*
 * gaussian — a Gaussian truncated at the radius and shifted to reach zero there
 * (PBR 4th ed. §8.8.3), normalised to integrate to 1. Nori's default filter.
 *
 * Parameters:
 *   radius  float  2    half-width of the support, in pixels
 *   stddev  float  0.5  standard deviation, in pixels
 *
 *   <rfilter type="gaussian">
 *       <float name="stddev" value="0.25"/>
 *   </rfilter>
 */
#include <nori/rfilter.h>

namespace nori {
namespace {

class GaussianFilter : public ReconstructionFilter {
public:
    explicit GaussianFilter(const PropertyList &props) {
        m_radius = checkedRadius(props.getFloat("radius", 2.0f), "gaussian");
        m_stddev = props.getFloat("stddev", 0.5f);
        if (!(m_stddev > 0.0f))
            throw NoriException("gaussian filter: 'stddev' must be positive, got {}", m_stddev);
        m_alpha = -1.0f / (2.0f * m_stddev * m_stddev);
        m_tail = std::exp(m_alpha * m_radius * m_radius);
        // ∫_{-r}^{r} exp(-x²/2σ²) − exp(-r²/2σ²) dx = σ√(2π)·erf(r/(σ√2)) − 2r·exp(-r²/2σ²).
        const double sigma = m_stddev, r = m_radius;
        const double integral =
            sigma * std::sqrt(2.0 * kPiDouble) * std::erf(r / (sigma * M_SQRT2)) -
            2.0 * r * std::exp(-r * r / (2.0 * sigma * sigma));
        m_normalization = static_cast<float>(1.0 / integral);
    }

    float eval(float x) const override {
        return std::max(0.0f, std::exp(m_alpha * x * x) - m_tail) * m_normalization;
    }

    std::string toString() const override {
        return fmt::format("GaussianFilter[radius={}, stddev={}]", m_radius, m_stddev);
    }

private:
    float m_stddev, m_alpha, m_tail, m_normalization;
};

NORI_REGISTER_CLASS(GaussianFilter, "gaussian");

} // namespace
} // namespace nori
