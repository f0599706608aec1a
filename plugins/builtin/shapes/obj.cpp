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
#include <nori/loadahead.h>
#include <nori/mesh.h>
#include <nori/objfile.h>
#include <nori/shading.h>

namespace nori {
namespace {

class WavefrontOBJ : public Mesh {
public:
    explicit WavefrontOBJ(const PropertyList &props) {
        m_name = props.getPath("filename");
        const Transform toWorld = props.getTransform("toWorld", Transform());
        const bool faceNormals = props.getBoolean("faceNormals", false);
        const bool flipNormals = props.getBoolean("flipNormals", false);
        const bool flipTexCoords = props.getBoolean("flipTexCoords", false);
        readSurfaceParameters(*this, props);

        MeshData data = LoadAhead::takeOrRead<MeshData>("obj", m_name, readOBJ);
        if (flipTexCoords)
            for (Point2f &uv : data.texCoords)
                uv.y() = 1.0f - uv.y();
        takeMeshData(std::move(data), faceNormals, flipNormals);
        finishLoading(toWorld);
    }
};

NORI_REGISTER_CLASS(WavefrontOBJ, "obj");
NORI_REGISTER_READER(
    "obj", [](const std::string &path) { return std::any(readOBJ(path)); },
    LoadAhead::Sharing::PerElement);
NORI_REGISTER_LOAD_AHEAD(WavefrontOBJ, "obj", "obj");

} // namespace
} // namespace nori
