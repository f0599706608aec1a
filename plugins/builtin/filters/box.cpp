/*
 * box — the box filter: every sample counts fully for the pixel it falls in.
 *
 * Parameters:
 *   radius  float  0.5  half-width of the support, in pixels
 *
 *   <rfilter type="box"/>
 */
#include <nori/rfilter.h>

namespace nori {
namespace {

class BoxFilter : public ReconstructionFilter {
public:
    explicit BoxFilter(const PropertyList &props) {
        m_radius = checkedRadius(props.getFloat("radius", 0.5f), "box");
    }

    // Constant 1/(2r) on [-r, r]: integrates to 1.
    float eval(float x) const override { return std::abs(x) <= m_radius ? 0.5f / m_radius : 0.0f; }

    std::string toString() const override { return fmt::format("BoxFilter[radius={}]", m_radius); }
};

NORI_REGISTER_CLASS(BoxFilter, "box");

} // namespace
} // namespace nori
