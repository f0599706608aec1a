/*
 * mitchell — the Mitchell–Netravali cubic ("Reconstruction Filters in Computer
 * Graphics", 1988), stretched to the radius. It has negative lobes.
 *
 * Parameters:
 *   radius  float  2    half-width of the support, in pixels
 *   B       float  1/3  the cubic's B parameter
 *   C       float  1/3  the cubic's C parameter
 *
 *   <rfilter type="mitchell"/>
 */
#include <nori/rfilter.h>

namespace nori {
namespace {

class MitchellNetravaliFilter : public ReconstructionFilter {
public:
    explicit MitchellNetravaliFilter(const PropertyList &props) {
        m_radius = checkedRadius(props.getFloat("radius", 2.0f), "mitchell");
        m_B = props.getFloat("B", 1.0f / 3.0f);
        m_C = props.getFloat("C", 1.0f / 3.0f);
    }

    // The cubic k(t) on |t| < 2 integrates to 1 for every B, C; t = 2x/r maps the
    // support to [-r, r] and the factor 2/r keeps the integral at 1.
    float eval(float x) const override {
        const float t = std::abs(2.0f * x / m_radius);
        const float t2 = t * t, t3 = t2 * t;
        float k = 0.0f;
        if (t < 1.0f)
            k = (12 - 9 * m_B - 6 * m_C) * t3 + (-18 + 12 * m_B + 6 * m_C) * t2 + (6 - 2 * m_B);
        else if (t < 2.0f)
            k = (-m_B - 6 * m_C) * t3 + (6 * m_B + 30 * m_C) * t2 + (-12 * m_B - 48 * m_C) * t +
                (8 * m_B + 24 * m_C);
        return k * (1.0f / 6.0f) * (2.0f / m_radius);
    }

    std::string toString() const override {
        return fmt::format("MitchellNetravaliFilter[radius={}, B={}, C={}]", m_radius, m_B, m_C);
    }

private:
    float m_B, m_C;
};

NORI_REGISTER_CLASS(MitchellNetravaliFilter, "mitchell");

} // namespace
} // namespace nori
