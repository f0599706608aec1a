/*
 * tent — the triangle filter (1 − |x|/r), normalised.
 *
 * Parameters:
 *   radius  float  1  half-width of the support, in pixels
 *
 *   <rfilter type="tent"/>
 */
#include <nori/rfilter.h>

namespace nori {
namespace {

class TentFilter : public ReconstructionFilter {
public:
    explicit TentFilter(const PropertyList &props) {
        m_radius = checkedRadius(props.getFloat("radius", 1.0f), "tent");
    }

    // The triangle's area is r, hence the 1/r.
    float eval(float x) const override {
        return std::max(0.0f, 1.0f - std::abs(x) / m_radius) / m_radius;
    }

    std::string toString() const override { return fmt::format("TentFilter[radius={}]", m_radius); }
};

NORI_REGISTER_CLASS(TentFilter, "tent");

} // namespace
} // namespace nori
