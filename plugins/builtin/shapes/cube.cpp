/*
 * cube — the cube [−1, 1]³ with outward normals, placed by `toWorld` (Mitsuba 0.6
 * documentation, "cube"): twelve triangles, four vertices per face so each face has its
 * own flat normal and uv from (0, 0) to (1, 1). Closed, so it can bound a medium.
 *
 * Parameters:
 *   toWorld      transform  identity  object-to-world transform
 *   flipNormals  boolean    false     normals point inward
 *   uvScale      vector     (1, 1)    uv are scaled by this for textures
 *   convention   string     ""        "mitsuba": each face's uv as Mitsuba's cube lays them
 *                                     out (0.6 and 3; by default face n has u along the
 *                                     next axis after n's and v = n × u)
 *   normal       texture    —         tangent-space normal map
 *   bump         texture    —         height map for bump mapping
 *   bumpScale    float      1         the heights are scaled by this
 *   visible      boolean    true      false: only a template for tmesh copies
 *
 *   <mesh type="cube">
 *       <transform name="toWorld"><scale value="0.3, 0.6, 0.3"/></transform>
 *   </mesh>
 */
#include <nori/mesh.h>
#include <nori/shading.h>

namespace nori {
namespace {

class Cube : public Mesh {
public:
    explicit Cube(const PropertyList &props) {
        m_name = "cube";
        const Transform toWorld = props.getTransform("toWorld", Transform());
        const bool flip = props.getBoolean("flipNormals", false);
        const std::string convention = props.getString("convention", "");
        if (!convention.empty() && convention != "mitsuba")
            throw NoriException("cube: 'convention' is \"mitsuba\" or absent, got \"{}\"",
                                convention);
        const bool mitsuba = convention == "mitsuba";
        readSurfaceParameters(*this, props);
        // Each face: its outward normal n and two axes u, v with u × v = n, so the corners
        // n ± u ± v in the order (−,−), (+,−), (+,+), (−,+) wind counter-clockwise about n.
        const Vector3f axes[3] = {Vector3f(1, 0, 0), Vector3f(0, 1, 0), Vector3f(0, 0, 1)};
        for (int axis = 0; axis < 3; ++axis)
            for (const float sign : {1.0f, -1.0f}) {
                const Vector3f n = sign * axes[axis];
                const Vector3f u = axes[(axis + 1) % 3];
                const Vector3f v = n.cross(u);
                const int first = static_cast<int>(m_positions.size());
                const Point2f corners[4] = {Point2f(0, 0), Point2f(1, 0), Point2f(1, 1),
                                            Point2f(0, 1)};
                for (const Point2f &corner : corners) {
                    const Point3f p(n + (2.0f * corner.x() - 1.0f) * u +
                                    (2.0f * corner.y() - 1.0f) * v);
                    m_positions.push_back(p);
                    m_texCoords.push_back(mitsuba ? mitsubaUV(p, axis, sign) : corner);
                }
                m_faces.emplace_back(first, first + 1, first + 2);
                m_faces.emplace_back(first + 2, first + 3, first);
            }
        if (flip)
            for (Vector3i &face : m_faces)
                std::swap(face.y(), face.z());
        finishLoading(toWorld);
    }

private:
    /// Mitsuba's uv on the face of outward normal sign·e_axis, at the corner p of [−1, 1]³:
    /// u = (a·p + 1)/2 and v = (b·p + 1)/2 with the signed axes a, b its cube's vertex
    /// table gives each face (Mitsuba 0.6 and 3, shapes/cube.cpp).
    static Point2f mitsubaUV(const Point3f &p, int axis, float sign) {
        // {a, b} per face, an axis index and its sign: 1 + index, negated for −.
        static const int table[3][2][2] = {
            {{2, -3}, {2, 3}},  // +x: (y, −z); −x: (y, z)
            {{-1, -3}, {3, 1}}, // +y: (−x, −z); −y: (z, x)
            {{2, 1}, {-2, 1}},  // +z: (y, x); −z: (−y, x)
        };
        const int *ab = table[axis][sign > 0.0f ? 0 : 1];
        const auto coordinate = [&](int code) {
            const float value = p[std::abs(code) - 1];
            return 0.5f * ((code > 0 ? value : -value) + 1.0f);
        };
        return Point2f(coordinate(ab[0]), coordinate(ab[1]));
    }
};

NORI_REGISTER_CLASS(Cube, "cube");

} // namespace
} // namespace nori
