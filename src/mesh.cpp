#include <nori/mesh.h>

namespace nori {

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
    const Point3f &p0 = m_positions[face[0]], &p1 = m_positions[face[1]],
                  &p2 = m_positions[face[2]];
    Vector3f edge1 = p1 - p0, edge2 = p2 - p0;
    Vector3f pvec = ray.d.cross(edge2);
    float det = edge1.dot(pvec);
    if (det == 0.0f || !std::isfinite(det))
        return false;
    float invDet = 1.0f / det;
    Vector3f tvec = ray.o - p0;
    float u = tvec.dot(pvec) * invDet;
    if (u < 0.0f || u > 1.0f)
        return false;
    Vector3f qvec = tvec.cross(edge1);
    float v = ray.d.dot(qvec) * invDet;
    if (v < 0.0f || u + v > 1.0f)
        return false;
    t = edge2.dot(qvec) * invDet;
    if (!(t >= ray.mint && t <= ray.maxt))
        return false;
    hitCoords = Point2f(u, v);
    return true;
}

void Mesh::setHitInformation(uint32_t index, const Ray3f &ray, const Point2f &hitCoords,
                             Intersection &its) const {
    (void)ray;
    const Vector3i &face = m_faces[index];
    const float b1 = hitCoords.x(), b2 = hitCoords.y(), b0 = 1.0f - b1 - b2;
    const Point3f &p0 = m_positions[face[0]], &p1 = m_positions[face[1]],
                  &p2 = m_positions[face[2]];

    its.p = b0 * p0 + b1 * p1 + b2 * p2;
    its.primIndex = index;
    its.shape = this;

    // Texture coordinates: the mesh's own, or the barycentric parameterisation.
    Point2f uv0(0.0f, 0.0f), uv1(1.0f, 0.0f), uv2(0.0f, 1.0f);
    if (!m_texCoords.empty()) {
        uv0 = m_texCoords[face[0]];
        uv1 = m_texCoords[face[1]];
        uv2 = m_texCoords[face[2]];
    }
    its.uv = b0 * uv0 + b1 * uv1 + b2 * uv2;

    Vector3f edge1 = p1 - p0, edge2 = p2 - p0;
    Vector3f geoNormal = edge1.cross(edge2).normalized();
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

    if (!m_normals.empty()) {
        Vector3f shadingNormal =
            (b0 * m_normals[face[0]] + b1 * m_normals[face[1]] + b2 * m_normals[face[2]]);
        float length = shadingNormal.norm();
        its.shFrame = length > 0.0f ? Frame(Vector3f(shadingNormal / length)) : its.geoFrame;
    } else {
        its.shFrame = its.geoFrame;
    }
}

void Mesh::finishLoading(const Transform &toWorld) {
    m_bbox = BoundingBox3f();
    for (Point3f &p : m_positions) {
        p = toWorld * p;
        m_bbox.expandBy(p);
    }
    for (Normal3f &n : m_normals) {
        n = toWorld * n;
        float length = n.norm();
        if (length > 0.0f)
            n /= length;
    }
}

std::string Mesh::toString() const {
    return fmt::format("Mesh[name=\"{}\", vertices={}, triangles={}, normals={}, uvs={}]", m_name,
                       m_positions.size(), m_faces.size(), !m_normals.empty(),
                       !m_texCoords.empty());
}

} // namespace nori
