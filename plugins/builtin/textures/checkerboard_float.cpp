/*
 * checkerboard_float — the course's scalar checkerboard, point-sampled: value1 on the
 * cells where i + j is even, i = ⌊u/scale.x − delta.x⌋, j = ⌊v/scale.y − delta.y⌋. For
 * float parameters such as a roughness.
 *
 * Parameters:
 *   delta   point   (0, 0)  offset of the pattern, in cells
 *   scale   vector  (1, 1)  size of a cell in uv
 *   value1  float   0       value of the even cells
 *   value2  float   1       value of the odd cells
 *
 *   <bsdf type="roughconductor">
 *       <texture type="checkerboard_float" name="alpha">
 *           <vector name="scale" value="0.25, 0.25"/>
 *           <float name="value1" value="0.05"/> <float name="value2" value="0.4"/>
 *       </texture>
 *   </bsdf>
 */
#include <nori/proplist.h>
#include <nori/texture.h>

namespace nori {
namespace {

class CheckerboardFloat : public Texture {
public:
    explicit CheckerboardFloat(const PropertyList &props) : m_pattern(props, "checkerboard_float") {
        m_value1 = props.getFloat("value1", 0.0f);
        m_value2 = props.getFloat("value2", 1.0f);
    }

    Color3f eval(const TextureQuery &q) const override { return Color3f(evalFloat(q)); }
    float evalFloat(const TextureQuery &q) const override {
        return m_pattern.even(q.uv) ? m_value1 : m_value2;
    }

    Color3f average() const override { return Color3f(0.5f * (m_value1 + m_value2)); }

    std::string toString() const override {
        return fmt::format("CheckerboardFloat[delta=({}, {}), scale=({}, {}), values={}/{}]",
                           m_pattern.delta.x(), m_pattern.delta.y(), m_pattern.scale.x(),
                           m_pattern.scale.y(), m_value1, m_value2);
    }

private:
    CourseCheckerboard m_pattern;
    float m_value1, m_value2;
};

NORI_REGISTER_CLASS(CheckerboardFloat, "checkerboard_float");

} // namespace
} // namespace nori
