#include <nori/mesh.h>
#include <nori/triangle.h>
#include <nori/warp.h>

#include <algorithm>
#include <array>
#include <iostream>
#include <limits>
#include <map>
#include <unordered_map>

namespace nori {

namespace {

/// b0·x0 + b1·x1 + b2·x2: a hit's position or uv from its barycentrics (one function, so
/// that an alpha mask's test and the shading of the same hit compute the same point).
template <typename T>
T barycentricMix(float b0, float b1, float b2, const T &x0, const T &x1, const T &x2) {
    return b0 * x0 + b1 * x1 + b2 * x2;
}

/// The uv of a face's corners: the mesh's own, or the barycentric parameterisation.
std::array<Point2f, 3> faceCornerUVs(const std::vector<Point2f> &texCoords, const Vector3i &face) {
    if (texCoords.empty())
        return {Point2f(0.0f, 0.0f), Point2f(1.0f, 0.0f), Point2f(0.0f, 1.0f)};
    return {texCoords[face[0]], texCoords[face[1]], texCoords[face[2]]};
}

} // namespace

BoundingBox3f Mesh::getPrimitiveBoundingBox(uint32_t index) const {
    const Vector3i &face = m_faces[index];
    BoundingBox3f box(m_positions[face[0]]);
    box.expandBy(m_positions[face[1]]);
    box.expandBy(m_positions[face[2]]);
    return box;
}

Point3f Mesh::getPrimitiveCentroid(uint32_t index) const {
    const Vector3i &face = m_faces[index];
    return (m_positions[face[0]] + m_positions[face[1]] + m_positions[face[2]]) / 3.0f;
}

float Mesh::surfaceArea(uint32_t index) const {
    const Vector3i &face = m_faces[index];
    const Point3f &p0 = m_positions[face[0]], &p1 = m_positions[face[1]],
                  &p2 = m_positions[face[2]];
    return 0.5f * Vector3f((p1 - p0).cross(p2 - p0)).norm();
}

bool Mesh::rayIntersect(uint32_t index, const Ray3f &ray, float &t, Point2f &hitCoords) const {
    const Vector3i &face = m_faces[index];
    return intersectTriangle(WatertightRay(ray), m_positions[face[0]], m_positions[face[1]],
                             m_positions[face[2]], t, hitCoords.x(), hitCoords.y());
}

void Mesh::hitPoint(uint32_t index, const Ray3f &ray, float t, const Point2f &hitCoords, Point3f &p,
                    Point2f &uv) const {
    (void)ray;
    (void)t;
    const Vector3i &face = m_faces[index];
    const float b1 = hitCoords.x(), b2 = hitCoords.y(), b0 = 1.0f - b1 - b2;
    p = barycentricMix(b0, b1, b2, m_positions[face[0]], m_positions[face[1]],
                       m_positions[face[2]]);
    const auto [uv0, uv1, uv2] = faceCornerUVs(m_texCoords, face);
    uv = barycentricMix(b0, b1, b2, uv0, uv1, uv2);
}

void Mesh::setHitInformation(uint32_t index, const Ray3f &ray, const Point2f &hitCoords,
                             Intersection &its) const {
    (void)ray;
    const Vector3i &face = m_faces[index];
    const float b1 = hitCoords.x(), b2 = hitCoords.y(), b0 = 1.0f - b1 - b2;
    const Point3f &p0 = m_positions[face[0]], &p1 = m_positions[face[1]],
                  &p2 = m_positions[face[2]];

    its.p = barycentricMix(b0, b1, b2, p0, p1, p2);
    // Error of the barycentric interpolation (PBR 4th ed. §6.8.5, eq. 6.33).
    its.pError = gammaBound(7) *
                 Vector3f((b0 * p0).cwiseAbs() + (b1 * p1).cwiseAbs() + (b2 * p2).cwiseAbs());
    its.primIndex = index;
    its.shape = its.mesh = this;

    const auto [uv0, uv1, uv2] = faceCornerUVs(m_texCoords, face);
    its.uv = barycentricMix(b0, b1, b2, uv0, uv1, uv2);

    Vector3f edge1 = p1 - p0, edge2 = p2 - p0;
    const Vector3f geoNormal = faceForward(edge1.cross(edge2).normalized(), index, b1, b2);
    its.geoFrame = Frame(geoNormal);

    // dp/du and dp/dv from the 2x2 system [du1 dv1; du2 dv2] [dpdu; dpdv] = [e1; e2]
    // (PBR 4th ed. §6.5.3); a degenerate uv mapping falls back to the frame's tangents.
    Vector2f duv1 = uv1 - uv0, duv2 = uv2 - uv0;
    float determinant = duv1.x() * duv2.y() - duv1.y() * duv2.x();
    if (std::abs(determinant) > 1e-12f) {
        float invDet = 1.0f / determinant;
        its.dpdu = (duv2.y() * edge1 - duv1.y() * edge2) * invDet;
        its.dpdv = (duv1.x() * edge2 - duv2.x() * edge1) * invDet;
    } else {
        its.dpdu = its.geoFrame.s;
        its.dpdv = its.geoFrame.t;
    }

    setShadingFrame(index, b1, b2, nullptr, nullptr, its);
}

void Mesh::setInstancedHitInformation(uint32_t index, const Ray3f &ray, const Point2f &hitCoords,
                                      const AffineMap &toWorld, const AffineMap &toLocal,
                                      Intersection &its) const {
    Shape::setInstancedHitInformation(index, ray, hitCoords, toWorld, toLocal, its);
    // Shade as a copy loaded with toWorld would: from the vertex normals mapped and
    // normalised one by one (finishLoading), not from the mapped interpolated normal.
    setShadingFrame(index, hitCoords.x(), hitCoords.y(), &toWorld, &toLocal, its);
}

void Mesh::setShadingFrame(uint32_t index, float b1, float b2, const AffineMap *toWorld,
                           const AffineMap *toLocal, Intersection &its) const {
    const Vector3i &face = m_faces[index];
    const float b0 = 1.0f - b1 - b2;
    // The vertex normals (unit), in world space for an instance's hit.
    Vector3f normals[3];
    if (!m_normals.empty())
        for (int i = 0; i < 3; ++i) {
            normals[i] = m_normals[face[i]];
            if (toLocal) {
                normals[i] = toLocal->applyTransposeToNormal(normals[i]);
                const float length = normals[i].norm();
                if (length > 0.0f)
                    normals[i] /= length;
            }
        }

    // Shading frame: the interpolated normal, with s along the interpolated per-vertex
    // tangent where the mesh has uvs (smooth across triangles, for normal maps), else
    // along dp/du, both made orthogonal to the normal (Gram–Schmidt).
    Vector3f shadingNormal = Vector3f::Zero();
    if (!m_normals.empty()) {
        const Vector3f n = b0 * normals[0] + b1 * normals[1] + b2 * normals[2];
        if (n.norm() > 0.0f)
            shadingNormal = n.normalized();
    }
    if (shadingNormal.isZero())
        shadingNormal = its.geoFrame.n;
    Vector3f tangent = its.dpdu;
    if (!m_tangents.empty()) {
        tangent = b0 * m_tangents[face[0]] + b1 * m_tangents[face[1]] + b2 * m_tangents[face[2]];
        if (toWorld)
            tangent = toWorld->applyToVector(tangent);
    }
    tangent -= shadingNormal * shadingNormal.dot(tangent);
    if (tangent.squaredNorm() > 1e-20f) {
        tangent.normalize();
        its.shFrame = Frame(tangent, shadingNormal.cross(tangent), shadingNormal);
    } else {
        its.shFrame = Frame(shadingNormal);
    }

    // Derivatives of the (unnormalised) interpolated normal w.r.t. uv, from the same 2x2
    // system as dp/du with the normal differences (pbrt-v3 §3.6.2).
    its.dndu = its.dndv = Vector3f::Zero();
    if (m_normals.empty())
        return;
    // The mesh's uvs, or the barycentric parameterisation (as in setHitInformation).
    const Vector2f duv1 = m_texCoords.empty()
                              ? Vector2f(1.0f, 0.0f)
                              : Vector2f(m_texCoords[face[1]] - m_texCoords[face[0]]);
    const Vector2f duv2 = m_texCoords.empty()
                              ? Vector2f(0.0f, 1.0f)
                              : Vector2f(m_texCoords[face[2]] - m_texCoords[face[0]]);
    const float determinant = duv1.x() * duv2.y() - duv1.y() * duv2.x();
    if (std::abs(determinant) > 1e-12f) {
        const Vector3f dn1 = normals[1] - normals[0], dn2 = normals[2] - normals[0];
        const float invDet = 1.0f / determinant;
        its.dndu = (duv2.y() * dn1 - duv1.y() * dn2) * invDet;
        its.dndv = (duv1.x() * dn2 - duv2.x() * dn1) * invDet;
    }
}

Vector3f Mesh::interpolatedNormal(uint32_t index, float b1, float b2) const {
    if (m_normals.empty())
        return Vector3f::Zero();
    const Vector3i &face = m_faces[index];
    const Vector3f n =
        (1.0f - b1 - b2) * m_normals[face[0]] + b1 * m_normals[face[1]] + b2 * m_normals[face[2]];
    const float length = n.norm();
    return length > 0.0f ? Vector3f(n / length) : Vector3f::Zero();
}

Vector3f Mesh::faceForward(const Vector3f &geoNormal, uint32_t index, float b1, float b2) const {
    // The vertex normals decide which side is the front, whatever the winding, as in
    // pbrt (PBR 4th ed. §6.5.3): emission, light sampling and BSDF sides then agree.
    const Vector3f shadingNormal = interpolatedNormal(index, b1, b2);
    return geoNormal.dot(shadingNormal) < 0.0f ? Vector3f(-geoNormal) : geoNormal;
}

void Mesh::takeMeshData(MeshData &&data, bool faceNormals, bool flipNormals) {
    m_positions = std::move(data.positions);
    m_texCoords = std::move(data.texCoords);
    if (!faceNormals)
        m_normals = std::move(data.normals);
    m_faces = std::move(data.triangles);
    if (flipNormals) {
        for (Vector3i &face : m_faces)
            std::swap(face.y(), face.z());
        for (Normal3f &normal : m_normals)
            normal = -normal;
    }
}

void Mesh::finishLoading(const Transform &toWorld) {
    for (Point3f &p : m_positions)
        p = toWorld * p;
    for (Normal3f &n : m_normals) {
        n = toWorld * n;
        float length = n.norm();
        if (length > 0.0f)
            n /= length;
    }

    // Triangles that no ray can hit (zero area) or that would poison the BVH (NaN or
    // infinite vertices) are dropped.
    size_t degenerate = 0, nonFinite = 0;
    auto unusable = [&](const Vector3i &face) {
        const Point3f &p0 = m_positions[face[0]], &p1 = m_positions[face[1]],
                      &p2 = m_positions[face[2]];
        if (!p0.allFinite() || !p1.allFinite() || !p2.allFinite()) {
            ++nonFinite;
            return true;
        }
        if (Vector3f(p1 - p0).cross(Vector3f(p2 - p0)).squaredNorm() == 0.0f) {
            ++degenerate;
            return true;
        }
        return false;
    };
    m_faces.erase(std::remove_if(m_faces.begin(), m_faces.end(), unusable), m_faces.end());
    if (degenerate > 0 || nonFinite > 0)
        std::cerr << fmt::format("Warning: mesh '{}': skipped {} degenerate (zero-area) and {} "
                                 "non-finite triangles\n",
                                 m_name, degenerate, nonFinite);
    if (m_faces.empty())
        std::cerr << fmt::format("Warning: mesh '{}' has no triangles\n", m_name);

    m_bbox = BoundingBox3f();
    for (const Vector3i &face : m_faces)
        for (int i = 0; i < 3; ++i)
            m_bbox.expandBy(m_positions[face[i]]);

    computeTangents();

    m_triangleAreas.clear();
    m_triangleAreas.reserve(m_faces.size());
    for (uint32_t i = 0; i < m_faces.size(); ++i)
        m_triangleAreas.append(surfaceArea(i));
    if (!m_faces.empty())
        m_triangleAreas.normalize();
}

ShapeSample Mesh::pointOnTriangle(uint32_t index, float b1, float b2) const {
    const float b0 = 1.0f - b1 - b2;
    const Vector3i &face = m_faces[index];
    const Point3f &p0 = m_positions[face[0]], &p1 = m_positions[face[1]],
                  &p2 = m_positions[face[2]];
    ShapeSample result;
    result.primitive = index;
    result.p = b0 * p0 + b1 * p1 + b2 * p2;
    result.n = faceForward(Vector3f(p1 - p0).cross(Vector3f(p2 - p0)).normalized(), index, b1, b2);
    result.uv = m_texCoords.empty()
                    ? Point2f(b1, b2)
                    : Point2f(b0 * m_texCoords[face[0]] + b1 * m_texCoords[face[1]] +
                              b2 * m_texCoords[face[2]]);
    return result;
}

ShapeSample Mesh::sampleSurface(const Point2f &sample) const {
    float u = sample.x();
    const uint32_t index = static_cast<uint32_t>(m_triangleAreas.sampleReuse(u));
    // Uniform barycentrics: b1 = 1 − √u, b2 = v √u.
    const float root = std::sqrt(u);
    ShapeSample result = pointOnTriangle(index, 1.0f - root, sample.y() * root);
    result.pdf = 1.0f / getArea();
    return result;
}

DirectionCone Mesh::normalBounds() const {
    DirectionCone cone;
    const auto add = [&cone](const Vector3f &n) {
        if (!cone.contains(n))
            cone = coneUnion(cone, DirectionCone(n));
    };
    for (uint32_t i = 0; i < m_faces.size(); ++i) {
        const Vector3i &face = m_faces[i];
        const Vector3f edge1 = m_positions[face[1]] - m_positions[face[0]];
        const Vector3f edge2 = m_positions[face[2]] - m_positions[face[0]];
        const Vector3f geoNormal = edge1.cross(edge2).normalized();
        if (!geoNormal.allFinite())
            continue; // a degenerate face has no area, so no sample lands on it
        if (m_normals.empty()) {
            add(geoNormal);
            continue;
        }
        // faceForward's choice, from the interpolated vertex normal: one side when the
        // three vertex normals agree (so does every convex combination), else both.
        bool front = false, back = false;
        for (int k = 0; k < 3; ++k) {
            const float side = geoNormal.dot(m_normals[face[k]]);
            front = front || side >= 0.0f;
            back = back || side < 0.0f;
        }
        if (front)
            add(geoNormal);
        if (back)
            add(-geoNormal);
    }
    return cone.isEmpty() ? DirectionCone::entireSphere() : cone;
}

void Mesh::activate() {
    Shape::activate();
    m_backBounds.reset();
    if (!getEmitter() || m_faces.empty())
        return;
    const DirectionCone normals = normalBounds();
    if (normals.isEmpty() || !(normals.cosTheta > 0.0f))
        return;
    BackBounds bounds;
    bounds.w = normals.w;
    bounds.leastOffset = kInfinity;
    for (const Vector3i &face : m_faces)
        for (int k = 0; k < 3; ++k)
            bounds.leastOffset = std::min(bounds.leastOffset, bounds.w.dot(m_positions[face[k]]));
    bounds.normalSpread = std::sqrt(2.0f - 2.0f * std::min(normals.cosTheta, 1.0f));
    bounds.center = m_bbox.getCenter();
    bounds.radius = 0.5f * m_bbox.getExtents().norm();
    m_backBounds = bounds;
}

bool Mesh::facesAwayFrom(const Point3f &ref) const {
    if (!m_backBounds)
        return false;
    const BackBounds &bounds = *m_backBounds;
    // For a point p of the mesh and its normal n: n·(ref − p) = w·(ref − p) + (n − w)·(ref − p)
    // ≤ w·ref − min w·p + |n − w|·(|ref − c| + r), with (c, r) the bounding sphere. The
    // margin keeps points within rounding of the plane of a planar light on the safe side.
    float ahead = bounds.w.dot(ref) - bounds.leastOffset;
    if (bounds.normalSpread > 0.0f)
        ahead += bounds.normalSpread * ((ref - bounds.center).norm() + bounds.radius);
    return ahead < -1e-5f * (std::abs(bounds.leastOffset) + bounds.radius);
}

bool Mesh::sphericalTrianglesFrom(const Point3f &ref, SphericalTriangles &triangles,
                                  float &total) const {
    if (m_faces.size() > kMaxSolidAngleTriangles)
        return false;
    // Farther than twice the radius of its bounding sphere, the light is sampled by area.
    const float radius = kSolidAngleSamplingReach * 0.5f * m_bbox.getExtents().norm();
    if ((m_bbox.getCenter() - ref).squaredNorm() > radius * radius)
        return false;
    total = 0.0f;
    for (uint32_t i = 0; i < m_faces.size(); ++i) {
        const Vector3i &face = m_faces[i];
        triangles[i] = SphericalTriangle((m_positions[face[0]] - ref).normalized(),
                                         (m_positions[face[1]] - ref).normalized(),
                                         (m_positions[face[2]] - ref).normalized());
        const float solidAngle = triangles[i].solidAngle;
        if (!(solidAngle >= kMinSphericalTriangleSolidAngle &&
              solidAngle <= kMaxSphericalTriangleSolidAngle))
            return false;
        total += solidAngle;
    }
    return total > 0.0f;
}

ShapeSample Mesh::sampleFromReference(const Point3f &ref, const Normal3f &refNormal,
                                      const Point2f &sample) const {
    SphericalTriangles triangles;
    float total = 0.0f;
    if (!sphericalTrianglesFrom(ref, triangles, total))
        return areaSampleFromReference(ref, sample);
    // Choose triangle i with probability Ω_i/Ω and reuse the rest of sample.x().
    uint32_t index = 0;
    float u = sample.x() * total;
    while (index + 1 < m_faces.size() && u >= triangles[index].solidAngle)
        u -= triangles[index++].solidAngle;
    Point2f triangleSample(std::clamp(u / triangles[index].solidAngle, 0.0f, 1.0f), sample.y());
    float warpDensity = 1.0f;
    if (!refNormal.isZero()) {
        const std::array<float, 4> weights = cosineCornerWeights(triangles[index], refNormal);
        triangleSample = Warp::squareToBilinear(triangleSample, weights);
        warpDensity = Warp::squareToBilinearPdf(triangleSample, weights);
    }

    const std::optional<Vector3f> direction =
        sampleSphericalTriangle(triangles[index], triangleSample);
    if (!direction)
        return {};
    const Vector3i &face = m_faces[index];
    const std::optional<Point2f> barycentrics = barycentricsAlong(
        m_positions[face[0]], m_positions[face[1]], m_positions[face[2]], ref, *direction);
    if (!barycentrics)
        return {};
    ShapeSample result = pointOnTriangle(index, barycentrics->x(), barycentrics->y());
    result.pdf = warpDensity / total;
    return result;
}

float Mesh::pdfFromReference(const Point3f &ref, const Normal3f &refNormal,
                             const ShapeSample &point) const {
    SphericalTriangles triangles;
    float total = 0.0f;
    if (!sphericalTrianglesFrom(ref, triangles, total))
        return areaPdfFromReference(ref, point.p, point.n);
    if (refNormal.isZero())
        return 1.0f / total;
    // The warp's density at the sample that gives the direction toward p, in p's triangle:
    // the one the query names (a ray hit's, a sample's), else the one whose three edge
    // planes have the direction most inside (directions within rounding of an edge shared
    // by two triangles could be either's).
    const Vector3f w = (point.p - ref).normalized();
    uint32_t index = point.primitive;
    if (index >= m_faces.size()) {
        float mostInside = -std::numeric_limits<float>::infinity();
        for (uint32_t i = 0; i < m_faces.size(); ++i) {
            const SphericalTriangle &triangle = triangles[i];
            // The planes' normals a × b, b × c, c × a point inward when a·(b × c) > 0.
            const float orientation =
                triangle.a.dot(triangle.b.cross(triangle.c)) > 0.0f ? 1.0f : -1.0f;
            const float inside = std::min({orientation * w.dot(triangle.a.cross(triangle.b)),
                                           orientation * w.dot(triangle.b.cross(triangle.c)),
                                           orientation * w.dot(triangle.c.cross(triangle.a))});
            if (inside > mostInside) {
                mostInside = inside;
                index = i;
            }
        }
    }
    const std::optional<Point2f> sample = invertSphericalTriangleSample(triangles[index], w);
    if (!sample)
        return 0.0f;
    return Warp::squareToBilinearPdf(*sample, cosineCornerWeights(triangles[index], refNormal)) /
           total;
}

void Mesh::computeTangents() {
    m_tangents.clear();
    if (m_texCoords.empty())
        return;
    // Each triangle adds its unit dp/du weighted by its area to its three vertices
    // (Lengyel 2001, "Computing Tangent Space Basis Vectors for an Arbitrary Mesh").
    m_tangents.assign(m_positions.size(), Vector3f::Zero());
    for (const Vector3i &face : m_faces) {
        const Vector3f edge1 = m_positions[face[1]] - m_positions[face[0]];
        const Vector3f edge2 = m_positions[face[2]] - m_positions[face[0]];
        const Vector2f duv1 = m_texCoords[face[1]] - m_texCoords[face[0]];
        const Vector2f duv2 = m_texCoords[face[2]] - m_texCoords[face[0]];
        const float determinant = duv1.x() * duv2.y() - duv1.y() * duv2.x();
        if (!(std::abs(determinant) > 1e-12f))
            continue;
        Vector3f dpdu = (duv2.y() * edge1 - duv1.y() * edge2) / determinant;
        if (!(dpdu.squaredNorm() > 0.0f) || !dpdu.allFinite())
            continue;
        const float area = 0.5f * edge1.cross(edge2).norm();
        dpdu = dpdu.normalized() * area;
        for (int i = 0; i < 3; ++i)
            m_tangents[face[i]] += dpdu;
    }
}

bool Mesh::isClosed() const {
    // Vertices at the same position are one vertex here.
    std::map<std::array<float, 3>, uint32_t> positionIds;
    std::vector<uint32_t> idOfVertex(m_positions.size());
    for (size_t i = 0; i < m_positions.size(); ++i) {
        const Point3f &p = m_positions[i];
        idOfVertex[i] =
            positionIds
                .emplace(std::array<float, 3>{p.x(), p.y(), p.z()}, uint32_t(positionIds.size()))
                .first->second;
    }
    std::unordered_map<uint64_t, uint32_t> edgeUses;
    for (const Vector3i &face : m_faces)
        for (int k = 0; k < 3; ++k) {
            const uint32_t a = idOfVertex[face[k]], b = idOfVertex[face[(k + 1) % 3]];
            ++edgeUses[(uint64_t(std::min(a, b)) << 32) | std::max(a, b)];
        }
    return std::all_of(edgeUses.begin(), edgeUses.end(),
                       [](const auto &edge) { return edge.second % 2 == 0; });
}

std::string Mesh::toString() const {
    return fmt::format("Mesh[name=\"{}\", vertices={}, triangles={}, normals={}, uvs={}]", m_name,
                       m_positions.size(), m_faces.size(), !m_normals.empty(),
                       !m_texCoords.empty());
}

const Mesh::Nori2Arrays &Mesh::nori2Arrays() const {
    std::call_once(m_nori2Once, [this] {
        Nori2Arrays &arrays = m_nori2Arrays;
        const auto vertices = static_cast<Eigen::Index>(m_positions.size());
        arrays.positions.resize(3, vertices);
        for (Eigen::Index i = 0; i < vertices; ++i)
            arrays.positions.col(i) = m_positions[static_cast<size_t>(i)];
        arrays.normals.resize(3, static_cast<Eigen::Index>(m_normals.size()));
        for (Eigen::Index i = 0; i < arrays.normals.cols(); ++i)
            arrays.normals.col(i) = m_normals[static_cast<size_t>(i)];
        arrays.texCoords.resize(2, static_cast<Eigen::Index>(m_texCoords.size()));
        for (Eigen::Index i = 0; i < arrays.texCoords.cols(); ++i)
            arrays.texCoords.col(i) = m_texCoords[static_cast<size_t>(i)];
        arrays.indices.resize(3, static_cast<Eigen::Index>(m_faces.size()));
        for (Eigen::Index i = 0; i < arrays.indices.cols(); ++i)
            arrays.indices.col(i) = m_faces[static_cast<size_t>(i)].cast<uint32_t>();
    });
    return m_nori2Arrays;
}

bool Mesh::rayIntersect(uint32_t index, const Ray3f &ray, float &u, float &v, float &t) const {
    Point2f barycentrics;
    if (!rayIntersect(index, ray, t, barycentrics))
        return false;
    u = barycentrics.x();
    v = barycentrics.y();
    return true;
}

} // namespace nori
