/*
 * rectangle — the square [−1, 1]² in the plane z = 0, facing +z, placed by `toWorld`
 * (Mitsuba 0.6 documentation, "rectangle"): a studio light, a window, a floor. Two
 * triangles with uv from (0, 0) at (−1, −1) to (1, 1) at (1, 1); as an area light, it is
 * sampled as meshes are (by solid angle when near, by area when far).
 *
 * Parameters:
 *   toWorld      transform  identity  object-to-world transform (any affine map: a
 *                                     parallelogram)
 *   flipNormals  boolean    false     face −z instead
 *   uvScale      vector     (1, 1)    uv are scaled by this for textures
 *   normal       texture    —         tangent-space normal map
 *   bump         texture    —         height map for bump mapping
 *   bumpScale    float      1         the heights are scaled by this
 *   visible      boolean    true      false: only a template for tmesh copies
 *
 *   <mesh type="rectangle">
 *       <transform name="toWorld"><scale value="0.5"/> <translate value="0, 2, 0"/></transform>
 *   </mesh>
 */
#include <nori/mesh.h>
#include <nori/shading.h>

namespace nori {
namespace {

class Rectangle : public Mesh {
public:
    explicit Rectangle(const PropertyList &props) {
        m_name = "rectangle";
        const Transform toWorld = props.getTransform("toWorld", Transform());
        const bool flip = props.getBoolean("flipNormals", false);
        readSurfaceParameters(*this, props);
        m_positions = {Point3f(-1, -1, 0), Point3f(1, -1, 0), Point3f(1, 1, 0), Point3f(-1, 1, 0)};
        m_texCoords = {Point2f(0, 0), Point2f(1, 0), Point2f(1, 1), Point2f(0, 1)};
        // Counter-clockwise seen from +z: the geometric normal is +z.
        m_faces = {Vector3i(0, 1, 2), Vector3i(2, 3, 0)};
        if (flip)
            for (Vector3i &face : m_faces)
                std::swap(face.y(), face.z());
        finishLoading(toWorld);
    }
};

NORI_REGISTER_CLASS(Rectangle, "rectangle");

} // namespace
} // namespace nori
