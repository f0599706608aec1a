/*
 * checkerboard_color — the course's colour checkerboard, point-sampled: value1 on the
 * cells where i + j is even, i = ⌊u/scale.x − delta.x⌋, j = ⌊v/scale.y − delta.y⌋.
 *
 * Parameters:
 *   delta   point   (0, 0)  offset of the pattern, in cells
 *   scale   vector  (1, 1)  size of a cell in uv
 *   value1  color   0       colour of the even cells
 *   value2  color   1       colour of the odd cells
 *
 *   <bsdf type="diffuse">
 *       <texture type="checkerboard_color" name="albedo">
 *           <point name="delta" value="0.5, 0.5"/> <vector name="scale" value="0.1, 0.1"/>
 *           <color name="value1" value="0.8, 0.8, 0.8"/> <color name="value2" value="0.2, 0.2,
 * 0.2"/>
 *       </texture>
 *   </bsdf>
 */
#include <nori/proplist.h>
#include <nori/texture.h>

namespace nori {
namespace {

class CheckerboardColor : public Texture {
public:
    explicit CheckerboardColor(const PropertyList &props) : m_pattern(props, "checkerboard_color") {
        m_value1 = props.getColor("value1", Color3f(0.0f));
        m_value2 = props.getColor("value2", Color3f(1.0f));
    }

    Color3f eval(const TextureQuery &q) const override {
        return m_pattern.even(q.uv) ? m_value1 : m_value2;
    }

    Color3f average() const override { return 0.5f * (m_value1 + m_value2); }

    std::string toString() const override {
        return fmt::format("CheckerboardColor[delta=({}, {}), scale=({}, {})]", m_pattern.delta.x(),
                           m_pattern.delta.y(), m_pattern.scale.x(), m_pattern.scale.y());
    }

private:
    CourseCheckerboard m_pattern;
    Color3f m_value1, m_value2;
};

NORI_REGISTER_CLASS(CheckerboardColor, "checkerboard_color");

} // namespace
} // namespace nori
