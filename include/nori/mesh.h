// Triangle meshes: vertex arrays and faces, with the per-triangle intersection code.
// Loaders (plugins/builtin/shapes/obj.cpp) fill the arrays and call finishLoading().
#pragma once

#include <nori/dpdf.h>
#include <nori/meshdata.h>
#include <nori/shape.h>
#include <nori/sphericaltriangle.h>
#include <nori/transform.h>

#include <array>
#include <mutex>
#include <optional>
#include <vector>

namespace nori {

class Mesh : public Shape {
public:
    uint32_t getPrimitiveCount() const override { return static_cast<uint32_t>(m_faces.size()); }
    BoundingBox3f getPrimitiveBoundingBox(uint32_t index) const override;
    Point3f getPrimitiveCentroid(uint32_t index) const override;
    /// The watertight ray–triangle test (triangle.h); hitCoords are the barycentrics of
    /// vertices 1 and 2.
    bool rayIntersect(uint32_t index, const Ray3f &ray, float &t,
                      Point2f &hitCoords) const override;
    void setHitInformation(uint32_t index, const Ray3f &ray, const Point2f &hitCoords,
                           Intersection &its) const override;
    /// The barycentric interpolations of setHitInformation alone (an alpha mask's test).
    void hitPoint(uint32_t index, const Ray3f &ray, float t, const Point2f &hitCoords, Point3f &p,
                  Point2f &uv) const override;
    /// Shades like a copy of the mesh loaded with toWorld: vertex normals are mapped and
    /// normalised one by one before they are interpolated.
    void setInstancedHitInformation(uint32_t index, const Ray3f &ray, const Point2f &hitCoords,
                                    const AffineMap &toWorld, const AffineMap &toLocal,
                                    Intersection &its) const override;

    float surfaceArea(uint32_t index) const;
    float getArea() const override { return m_triangleAreas.getSum(); }
    /// Whether every edge (between vertices at the same positions, so uv and normal seams
    /// do not count as borders) is shared by an even number of triangles.
    bool isClosed() const override;
    /// A triangle chosen by area, then a uniform point on it (PBR 4th ed. §6.5.4); the
    /// normal is the geometric one on the side of the vertex normals.
    ShapeSample sampleSurface(const Point2f &sample) const override;
    /// The cone of the faces' normals as sampleSurface() orients them: a face whose
    /// vertex normals disagree about its front adds both of its sides.
    DirectionCone normalBounds() const override;
    /// For a mesh whose normals lie within 90° of one direction w (a planar light, say),
    /// from bounds activate() computes when the mesh carries an emitter; false otherwise.
    bool facesAwayFrom(const Point3f &ref) const override;
    /// Shape's checks, then, for an area light's mesh, the bounds facesAwayFrom() reads.
    void activate() override;
    /// Seen from a point ref within kSolidAngleSamplingReach radii of its bounding
    /// sphere's centre, a mesh of at most kMaxSolidAngleTriangles triangles, each
    /// subtending a solid angle within the bounds of sphericaltriangle.h, is sampled
    /// in solid angle: a triangle chosen in proportion to its solid angle, then a direction
    /// within it (Arvo 1995), uniform (density 1/Ω of the whole mesh) or, given refNormal,
    /// with the sample first warped bilinearly by the cosines of the triangle's corners to
    /// it, so that directions of large cos θ come more often (density
    /// bilinear(u)/Ω; PBR 4th ed. §6.5.4). Otherwise (a larger or a distant mesh, a
    /// triangle nearly a point or nearly a hemisphere, ref in a triangle's plane), by area
    /// as Shape does. pdfFromReference makes the same choices.
    ShapeSample sampleFromReference(const Point3f &ref, const Normal3f &refNormal,
                                    const Point2f &sample) const override;
    float pdfFromReference(const Point3f &ref, const Normal3f &refNormal,
                           const ShapeSample &point) const override;
    /// Meshes with more triangles are sampled by area: the choice by solid angle costs one
    /// solid angle per triangle for every sample and every density.
    static constexpr uint32_t kMaxSolidAngleTriangles = 8;
    /// Farther away, in radii of the bounding sphere, a light is sampled by area: seen
    /// within a cone of half-angle 30°, its area density d²/cos θ varies little enough that
    /// the spherical trigonometry (about a quarter of a diffuse Cornell box's render time)
    /// does not pay for itself (scripts/bench_lights.sh; docs/design/figures.md).
    static constexpr float kSolidAngleSamplingReach = 2.0f;

    const std::vector<Point3f> &positions() const { return m_positions; }
    const std::vector<Normal3f> &normals() const { return m_normals; }
    const std::vector<Point2f> &texCoords() const { return m_texCoords; }
    const std::vector<Vector3i> &faces() const { return m_faces; }
    const std::string &getName() const { return m_name; }

    /// Nori 2's accessors, for course code. The matrices hold one column per vertex
    /// (3 × n positions and normals, 2 × n uvs; 0 columns when absent) and per triangle
    /// (3 × m vertex indices); they are made from the arrays above on first use.
    uint32_t getTriangleCount() const { return getPrimitiveCount(); }
    uint32_t getVertexCount() const { return static_cast<uint32_t>(m_positions.size()); }
    const MatrixXf &getVertexPositions() const { return nori2Arrays().positions; }
    const MatrixXf &getVertexNormals() const { return nori2Arrays().normals; }
    const MatrixXf &getVertexTexCoords() const { return nori2Arrays().texCoords; }
    const MatrixXu &getIndices() const { return nori2Arrays().indices; }
    using Shape::getBoundingBox;
    BoundingBox3f getBoundingBox(uint32_t index) const { return getPrimitiveBoundingBox(index); }
    Point3f getCentroid(uint32_t index) const { return getPrimitiveCentroid(index); }
    /// Nori 2's ray–triangle test: on a hit, the barycentrics u, v of vertices 1 and 2
    /// and the distance t.
    using Shape::rayIntersect;
    bool rayIntersect(uint32_t index, const Ray3f &ray, float &u, float &v, float &t) const;

    std::string toString() const override;

protected:
    /// The interpolated vertex normal at barycentrics (b1, b2) of a triangle, unit
    /// length, or zero when the mesh has no normals (or they cancel).
    Vector3f interpolatedNormal(uint32_t index, float b1, float b2) const;
    /// The geometric normal, flipped into the hemisphere of the interpolated vertex
    /// normal where the mesh has normals: the front side is where the normals point.
    Vector3f faceForward(const Vector3f &geoNormal, uint32_t index, float b1, float b2) const;

    /// Applies toWorld to the vertex data, drops triangles that are degenerate (zero
    /// area) or have non-finite vertices, with a warning that counts them, and computes
    /// the bounding box. Normals and texture coordinates are optional (empty) but, when
    /// present, one per vertex.
    void finishLoading(const Transform &toWorld);
    /// Takes the arrays of a mesh file: its vertex normals unless `faceNormals` (flat
    /// shading), and with `flipNormals` every face turned over (winding and normals).
    void takeMeshData(MeshData &&data, bool faceNormals, bool flipNormals);
    /// The shading frame and the normal's uv derivatives at barycentrics (b1, b2), from
    /// its.geoFrame and its.dpdu; with toWorld and toLocal, of the instance's copy.
    void setShadingFrame(uint32_t index, float b1, float b2, const AffineMap *toWorld,
                         const AffineMap *toLocal, Intersection &its) const;
    /// Per-vertex tangents from the uvs (empty without uvs).
    void computeTangents();
    /// The point at barycentrics (b1, b2) of a triangle: position, front-side geometric
    /// normal and uv; pdf left 0.
    ShapeSample pointOnTriangle(uint32_t index, float b1, float b2) const;
    /// Each triangle as seen from ref, and the sum of their solid angles, when the mesh is
    /// sampled in solid angle from ref (see sampleFromReference); false otherwise.
    using SphericalTriangles = std::array<SphericalTriangle, kMaxSolidAngleTriangles>;
    bool sphericalTrianglesFrom(const Point3f &ref, SphericalTriangles &triangles,
                                float &total) const;

    std::string m_name;               ///< e.g. the file name, for messages
    std::vector<Point3f> m_positions; ///< vertex positions
    std::vector<Normal3f> m_normals;  ///< per-vertex normals, or empty
    std::vector<Point2f> m_texCoords; ///< per-vertex uvs, or empty
    std::vector<Vector3i> m_faces;    ///< vertex indices of each triangle
    std::vector<Vector3f> m_tangents; ///< per-vertex tangents (along dp/du) when there are uvs
    DiscretePDF m_triangleAreas;      ///< for sampling a triangle by area

private:
    /// What facesAwayFrom() needs (activate() sets it for an emitter's mesh whose normal
    /// cone (w, θ) has θ < 90°): w, the least w·p over the vertices, |n − w| ≤ √(2 − 2 cos θ)
    /// for every normal n, and the bounding sphere that bounds |ref − p|.
    struct BackBounds {
        Vector3f w;
        float leastOffset = 0.0f, normalSpread = 0.0f;
        Point3f center;
        float radius = 0.0f;
    };
    std::optional<BackBounds> m_backBounds;

    struct Nori2Arrays {
        MatrixXf positions, normals, texCoords;
        MatrixXu indices;
    };
    const Nori2Arrays &nori2Arrays() const;
    mutable std::once_flag m_nori2Once;
    mutable Nori2Arrays m_nori2Arrays;
};

} // namespace nori
