/*
 * obj — a triangle mesh read from a Wavefront OBJ file: v/vt/vn records, faces with
 * 1-based or negative (relative) indices, triangles, quads and convex polygons (split
 * into a fan). Normals and texture coordinates are used when every face vertex has
 * one; otherwise the geometric normal and barycentric uvs are.
 *
 * Parameters:
 *   filename       string     (required)  OBJ file, relative to the XML file's folder
 *   toWorld        transform  identity    object-to-world transform
 *   faceNormals    boolean    false       ignore the file's vertex normals (flat shading)
 *   flipNormals    boolean    false       reverse the faces' orientation (winding and
 *                                         normals)
 *   flipTexCoords  boolean    false       v → 1 − v (for files whose v runs down the
 *                                         image; Mitsuba's flipTexCoords=false)
 *   uvScale        vector     (1, 1)      uv are scaled by this for textures (a <float>
 *                                         scales both)
 *   normal         texture    —           tangent-space normal map (decoded as 2c − 1;
 *                                         tangents follow dp/du, smoothed per vertex)
 *   bump           texture    —           height map for bump mapping (instead of
 *                                         normal)
 *   bumpScale      float      1           the heights are scaled by this
 *   visible        boolean    true        false: the mesh is only a template that its
 *                                         tmesh children copy (course exporters write one)
 *
 * Children: a <bsdf>, an <emitter> (an area light), and <mesh type="tmesh"> copies.
 *
 *   <mesh type="obj">
 *       <string name="filename" value="scenes/cbox/meshes/floor.obj"/>
 *   </mesh>
 *
 *   <mesh type="obj">
 *       <string name="filename" value="scenes/textured/meshes/floor.obj"/>
 *       <float name="uvScale" value="4"/>
 *       <texture type="image" name="normal">
 *           <string name="filename" value="scenes/textured/textures/bricks_normal.png"/>
 *       </texture>
 *   </mesh>
 */
#include <nori/filesystem.h>
#include <nori/mesh.h>
#include <nori/meshdata.h>
#include <nori/shading.h>
#include <nori/strutil.h>

#include <map>
#include <sstream>
#include <tuple>

namespace nori {
namespace {

/// Indices of one face corner into the position, uv and normal arrays (-1: absent).
struct Corner {
    int position = -1, texCoord = -1, normal = -1;
    bool operator<(const Corner &o) const {
        return std::tie(position, texCoord, normal) < std::tie(o.position, o.texCoord, o.normal);
    }
};

class ObjParser {
public:
    explicit ObjParser(std::string filename) : m_filename(std::move(filename)) {}

    /// Reads the file; positions, uvs and normals are filled per unique corner.
    void parse(std::istream &in) {
        std::string line;
        while (std::getline(in, line)) {
            ++m_lineNumber;
            const std::vector<std::string> tokens = tokenize(line, " \t\r");
            if (tokens.empty() || tokens[0][0] == '#')
                continue;
            const std::string &keyword = tokens[0];
            if (keyword == "v")
                m_positions.push_back(Point3f(readVector(tokens, 3, "vertex position")));
            else if (keyword == "vt")
                m_texCoords.push_back(
                    Point2f(readVector(tokens, 2, "texture coordinate").head<2>()));
            else if (keyword == "vn")
                m_normals.push_back(Normal3f(readVector(tokens, 3, "vertex normal")));
            else if (keyword == "f")
                readFace(tokens);
            // Other records (o, g, s, usemtl, mtllib, l, p, ...) do not affect geometry.
        }
    }

    std::vector<Corner> corners;     ///< unique face corners, one per output vertex
    std::vector<Vector3i> triangles; ///< indices into `corners`

    const std::vector<Point3f> &rawPositions() const { return m_positions; }
    const std::vector<Point2f> &rawTexCoords() const { return m_texCoords; }
    const std::vector<Normal3f> &rawNormals() const { return m_normals; }

private:
    [[noreturn]] void fail(const std::string &message) const {
        throw NoriException("{}:{}: {}", m_filename, m_lineNumber, message);
    }

    /// Reads `count` numbers after the keyword (extra ones, such as w, are allowed).
    Vector3f readVector(const std::vector<std::string> &tokens, size_t count, const char *what) {
        if (tokens.size() < count + 1)
            fail(fmt::format("{} needs {} numbers, got {}", what, count, tokens.size() - 1));
        Vector3f result(0.0f);
        for (size_t i = 0; i < count; ++i) {
            try {
                result[static_cast<int>(i)] = toFloat(tokens[i + 1], what);
            } catch (const NoriException &error) {
                fail(error.what());
            }
        }
        return result;
    }

    /// A 1-based index, or negative relative to the end; returns a 0-based index.
    int resolveIndex(const std::string &text, size_t available, const char *what) {
        int index = 0;
        try {
            index = toInt(text, what);
        } catch (const NoriException &error) {
            fail(error.what());
        }
        const long resolved = index > 0 ? index - 1 : static_cast<long>(available) + index;
        if (index == 0 || resolved < 0 || resolved >= static_cast<long>(available))
            fail(fmt::format("{} index {} is out of range (there are {} so far)", what, text,
                             available));
        return static_cast<int>(resolved);
    }

    int cornerIndex(const std::string &token) {
        // "p", "p/t", "p//n" or "p/t/n".
        std::vector<std::string> parts;
        std::string::size_type start = 0;
        while (true) {
            std::string::size_type slash = token.find('/', start);
            parts.push_back(token.substr(start, slash - start));
            if (slash == std::string::npos)
                break;
            start = slash + 1;
        }
        if (parts.size() > 3 || parts[0].empty())
            fail(fmt::format("malformed face vertex '{}'", token));
        Corner corner;
        corner.position = resolveIndex(parts[0], m_positions.size(), "vertex");
        if (parts.size() > 1 && !parts[1].empty())
            corner.texCoord = resolveIndex(parts[1], m_texCoords.size(), "texture coordinate");
        if (parts.size() > 2 && !parts[2].empty())
            corner.normal = resolveIndex(parts[2], m_normals.size(), "normal");
        auto [it, inserted] = m_cornerIndices.emplace(corner, static_cast<int>(corners.size()));
        if (inserted)
            corners.push_back(corner);
        return it->second;
    }

    void readFace(const std::vector<std::string> &tokens) {
        if (tokens.size() < 4)
            fail(fmt::format("a face needs at least 3 vertices, got {}", tokens.size() - 1));
        std::vector<int> polygon;
        for (size_t i = 1; i < tokens.size(); ++i)
            polygon.push_back(cornerIndex(tokens[i]));
        // A convex polygon as a fan around its first vertex.
        for (size_t i = 1; i + 1 < polygon.size(); ++i)
            triangles.emplace_back(polygon[0], polygon[i], polygon[i + 1]);
    }

    std::string m_filename;
    size_t m_lineNumber = 0;
    std::vector<Point3f> m_positions;
    std::vector<Point2f> m_texCoords;
    std::vector<Normal3f> m_normals;
    std::map<Corner, int> m_cornerIndices;
};

class WavefrontOBJ : public Mesh {
public:
    explicit WavefrontOBJ(const PropertyList &props) {
        m_name = props.getPath("filename");
        const Transform toWorld = props.getTransform("toWorld", Transform());
        const bool faceNormals = props.getBoolean("faceNormals", false);
        const bool flipNormals = props.getBoolean("flipNormals", false);
        const bool flipTexCoords = props.getBoolean("flipTexCoords", false);
        readSurfaceParameters(*this, props);

        std::istringstream in(readTextFile(m_name, "OBJ mesh file"));
        ObjParser parser(m_name);
        parser.parse(in);

        const bool allHaveUVs = std::all_of(parser.corners.begin(), parser.corners.end(),
                                            [](const Corner &c) { return c.texCoord >= 0; });
        const bool allHaveNormals = std::all_of(parser.corners.begin(), parser.corners.end(),
                                                [](const Corner &c) { return c.normal >= 0; });
        MeshData data;
        for (const Corner &corner : parser.corners) {
            data.positions.push_back(parser.rawPositions()[corner.position]);
            if (allHaveUVs) {
                Point2f uv = parser.rawTexCoords()[corner.texCoord];
                if (flipTexCoords)
                    uv.y() = 1.0f - uv.y();
                data.texCoords.push_back(uv);
            }
            if (allHaveNormals)
                data.normals.push_back(parser.rawNormals()[corner.normal]);
        }
        data.triangles = std::move(parser.triangles);
        takeMeshData(std::move(data), faceNormals, flipNormals);
        finishLoading(toWorld);
    }
};

NORI_REGISTER_CLASS(WavefrontOBJ, "obj");

} // namespace
} // namespace nori
