/*
 * trianglemesh — a triangle mesh written in the scene file itself, as pbrt-v4's
 * `trianglemesh` shape is (pbrt-v4 file format, "Shapes"): vertex positions, the
 * triangles' vertex indices, and optionally one normal and one uv per vertex, each a list
 * of numbers separated by spaces or commas. For a few triangles (a Cornell box's walls, a
 * light's quad) where a mesh file would be clutter; the pbrt-v4 importer writes small
 * inline meshes this way. Numbers are read as floats exactly as written, so a mesh
 * round-trips through its text bit for bit. With normals, the front side is where they
 * point, as for every mesh.
 *
 * Parameters:
 *   positions    string     (required)  x y z of every vertex
 *   indices      string     0 1 2       three vertex indices (from 0) per triangle;
 *                                       may be left out for a single triangle
 *   normals      string     ""          nx ny nz of every vertex (or none)
 *   uvs          string     ""          u v of every vertex (or none)
 *   toWorld      transform  identity    object-to-world transform
 *   flipNormals  boolean    false       reverse the faces' orientation
 *   uvScale      vector     (1, 1)      uv are scaled by this for textures
 *   normal       texture    —           tangent-space normal map
 *   bump         texture    —           height map for bump mapping
 *   bumpScale    float      1           the heights are scaled by this
 *   visible      boolean    true        false: only a template for tmesh copies
 *
 *   <mesh type="trianglemesh">
 *       <string name="positions" value="-1 -1 0, 1 -1 0, 1 1 0, -1 1 0"/>
 *       <string name="indices" value="0 1 2, 2 3 0"/>
 *   </mesh>
 *
 *   <mesh type="trianglemesh">
 *       <string name="positions" value="0 0 0, 1 0 0, 0 1 0"/>
 *       <string name="normals" value="0 0 1, 0 0 1, 0 0 1"/>
 *       <string name="uvs" value="0 0, 1 0, 0 1"/>
 *   </mesh>
 */
#include <nori/mesh.h>
#include <nori/shading.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <type_traits>

namespace nori {
namespace {

/// The numbers of a list separated by spaces, tabs, newlines or commas, read with
/// strtof/strtol (correctly rounded, so "%.9g" text gives back the same float).
template <typename Number>
std::vector<Number> readNumbers(const std::string &text, const std::string &what) {
    std::vector<Number> numbers;
    const char *cursor = text.c_str();
    for (;;) {
        while (*cursor == ' ' || *cursor == ',' || *cursor == '\t' || *cursor == '\n' ||
               *cursor == '\r')
            ++cursor;
        if (*cursor == '\0')
            break;
        char *end = nullptr;
        errno = 0;
        Number value;
        if constexpr (std::is_integral_v<Number>) {
            const long parsed = std::strtol(cursor, &end, 10);
            if (end != cursor && (parsed < 0 || parsed > std::numeric_limits<Number>::max()))
                throw NoriException("trianglemesh: '{}' holds {}, which is no vertex index", what,
                                    parsed);
            value = static_cast<Number>(parsed);
        } else {
            value = std::strtof(cursor, &end);
        }
        if (end == cursor || errno == ERANGE)
            throw NoriException("trianglemesh: '{}' holds \"{}\" at number {}, which is not a "
                                "{}",
                                what, std::string(cursor, strcspn(cursor, " ,\t\r\n")),
                                numbers.size() + 1,
                                std::is_integral_v<Number> ? "vertex index" : "number");
        numbers.push_back(value);
        cursor = end;
    }
    return numbers;
}

class TriangleMeshShape : public Mesh {
public:
    explicit TriangleMeshShape(const PropertyList &props) {
        m_name = "trianglemesh";
        const std::vector<float> positions =
            readNumbers<float>(props.getString("positions"), "positions");
        const std::vector<float> normals =
            readNumbers<float>(props.getString("normals", ""), "normals");
        const std::vector<float> uvs = readNumbers<float>(props.getString("uvs", ""), "uvs");
        if (positions.empty() || positions.size() % 3 != 0)
            throw NoriException("trianglemesh: 'positions' must hold x y z per vertex, got {} "
                                "numbers",
                                positions.size());
        const size_t vertexCount = positions.size() / 3;
        std::vector<uint32_t> indices;
        if (props.has("indices"))
            indices = readNumbers<uint32_t>(props.getString("indices"), "indices");
        else if (vertexCount == 3)
            indices = {0, 1, 2};
        else
            throw NoriException("trianglemesh: 'indices' is required for {} vertices (only a "
                                "single triangle may leave it out)",
                                vertexCount);
        if (indices.empty() || indices.size() % 3 != 0)
            throw NoriException("trianglemesh: 'indices' must hold three per triangle, got {}",
                                indices.size());
        if (!normals.empty() && normals.size() != positions.size())
            throw NoriException("trianglemesh: 'normals' has {} numbers for {} vertices (3 each)",
                                normals.size(), vertexCount);
        if (!uvs.empty() && uvs.size() != 2 * vertexCount)
            throw NoriException("trianglemesh: 'uvs' has {} numbers for {} vertices (2 each)",
                                uvs.size(), vertexCount);

        MeshData data;
        data.positions.reserve(vertexCount);
        for (size_t i = 0; i < vertexCount; ++i)
            data.positions.emplace_back(positions[3 * i], positions[3 * i + 1],
                                        positions[3 * i + 2]);
        for (size_t i = 0; i < normals.size() / 3; ++i)
            data.normals.emplace_back(normals[3 * i], normals[3 * i + 1], normals[3 * i + 2]);
        for (size_t i = 0; i < uvs.size() / 2; ++i)
            data.texCoords.emplace_back(uvs[2 * i], uvs[2 * i + 1]);
        for (size_t i = 0; i < indices.size(); i += 3) {
            for (size_t corner = 0; corner < 3; ++corner)
                if (indices[i + corner] >= vertexCount)
                    throw NoriException("trianglemesh: triangle {} uses vertex {}, but there are "
                                        "only {} vertices",
                                        i / 3, indices[i + corner], vertexCount);
            data.triangles.emplace_back(static_cast<int>(indices[i]),
                                        static_cast<int>(indices[i + 1]),
                                        static_cast<int>(indices[i + 2]));
        }
        readSurfaceParameters(*this, props);
        takeMeshData(std::move(data), false, props.getBoolean("flipNormals", false));
        finishLoading(props.getTransform("toWorld", Transform()));
    }
};

NORI_REGISTER_CLASS(TriangleMeshShape, "trianglemesh");

} // namespace
} // namespace nori
