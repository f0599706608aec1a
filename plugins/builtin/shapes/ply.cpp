/*
 * ply — a triangle mesh read from a PLY file (plyfile.h): ASCII or binary (either byte
 * order), plain or gzip-compressed (.ply.gz), triangles and polygons (split into fans),
 * vertex normals and uvs under the names PLY writers use (u v, s t, texture_u texture_v,
 * texture_s texture_t). Used when every vertex has them; otherwise the geometric normal
 * and barycentric uvs are, as for `obj`. The same file as an OBJ renders the same.
 *
 * Parameters:
 *   filename     string     (required)  PLY file, relative to the XML file's folder
 *   toWorld      transform  identity    object-to-world transform
 *   faceNormals  boolean    false       ignore the file's vertex normals (flat shading)
 *   flipNormals  boolean    false       reverse the faces' orientation
 *   uvScale      vector     (1, 1)      uv are scaled by this for textures
 *   normal       texture    —           tangent-space normal map
 *   bump         texture    —           height map for bump mapping
 *   bumpScale    float      1           the heights are scaled by this
 *   visible      boolean    true        false: only a template for tmesh copies
 *
 *   <mesh type="ply">
 *       <string name="filename" value="tests/data/meshes/quad.ply"/>
 *   </mesh>
 */
#include <nori/loadahead.h>
#include <nori/mesh.h>
#include <nori/plyfile.h>
#include <nori/shading.h>

namespace nori {
namespace {

class PlyShape : public Mesh {
public:
    explicit PlyShape(const PropertyList &props) {
        m_name = props.getPath("filename");
        const Transform toWorld = props.getTransform("toWorld", Transform());
        const bool faceNormals = props.getBoolean("faceNormals", false);
        const bool flip = props.getBoolean("flipNormals", false);
        readSurfaceParameters(*this, props);
        takeMeshData(LoadAhead::takeOrRead<MeshData>("ply", m_name, readPLY), faceNormals, flip);
        finishLoading(toWorld);
    }
};

NORI_REGISTER_CLASS(PlyShape, "ply");
NORI_REGISTER_READER(
    "ply", [](const std::string &path) { return std::any(readPLY(path)); },
    LoadAhead::Sharing::PerElement);
NORI_REGISTER_LOAD_AHEAD(PlyShape, "ply", "ply");

} // namespace
} // namespace nori
