/*
 * serialized — a triangle mesh from a Mitsuba `serialized` file (Mitsuba 0.6
 * documentation, "serialized"; serializedfile.h): compressed, little-endian, one or more
 * meshes per file, of which `shapeIndex` picks one. Vertex normals and uvs are used when
 * the file has them, unless the file or `faceNormals` asks for flat shading.
 *
 * Parameters:
 *   filename     string     (required)  the file, relative to the XML file's folder
 *   shapeIndex   integer    0           which mesh of the file (from 0)
 *   toWorld      transform  identity    object-to-world transform
 *   faceNormals  boolean    false       ignore the vertex normals (flat shading)
 *   flipNormals  boolean    false       reverse the faces' orientation
 *   uvScale      vector     (1, 1)      uv are scaled by this for textures
 *   normal       texture    —           tangent-space normal map
 *   bump         texture    —           height map for bump mapping
 *   bumpScale    float      1           the heights are scaled by this
 *   visible      boolean    true        false: only a template for tmesh copies
 *
 *   <mesh type="serialized">
 *       <string name="filename" value="tests/data/meshes/quads.serialized"/>
 *       <integer name="shapeIndex" value="1"/>
 *   </mesh>
 */
#include <nori/mesh.h>
#include <nori/serializedfile.h>
#include <nori/shading.h>

namespace nori {
namespace {

class SerializedShape : public Mesh {
public:
    explicit SerializedShape(const PropertyList &props) {
        const std::string filename = props.getPath("filename");
        const int shapeIndex = props.getInteger("shapeIndex", 0);
        const Transform toWorld = props.getTransform("toWorld", Transform());
        const bool faceNormals = props.getBoolean("faceNormals", false);
        const bool flip = props.getBoolean("flipNormals", false);
        readSurfaceParameters(*this, props);
        SerializedMesh mesh = readSerialized(filename, shapeIndex);
        m_name = mesh.name.empty() ? fmt::format("{}[{}]", filename, shapeIndex) : mesh.name;
        takeMeshData(std::move(mesh.data), faceNormals || mesh.faceNormals, flip);
        finishLoading(toWorld);
    }
};

NORI_REGISTER_CLASS(SerializedShape, "serialized");

} // namespace
} // namespace nori
