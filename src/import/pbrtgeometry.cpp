// Tessellation of pbrt-v4's partial quadrics, bilinear patches and Loop subdivision
// surfaces (see pbrtgeometry.h).
#include "import/pbrtgeometry.h"

#include <nori/common.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

namespace nori::pbrt {
namespace {

/// A (columns + 1) × (rows + 1) grid of vertices made by `vertex(s, t)` for s, t ∈ [0, 1],
/// and two triangles per cell, wound so that their normal follows the vertex normals.
template <typename Vertex> MeshData grid(int columns, int rows, Vertex &&vertex) {
    MeshData mesh;
    for (int j = 0; j <= rows; ++j)
        for (int i = 0; i <= columns; ++i) {
            const float s = float(i) / float(columns), t = float(j) / float(rows);
            Point3f p;
            Normal3f n;
            vertex(s, t, p, n);
            mesh.positions.push_back(p);
            mesh.normals.push_back(n);
            mesh.texCoords.emplace_back(s, t);
        }
    const auto index = [columns](int i, int j) { return j * (columns + 1) + i; };
    for (int j = 0; j < rows; ++j)
        for (int i = 0; i < columns; ++i) {
            Vector3i a(index(i, j), index(i + 1, j), index(i + 1, j + 1));
            Vector3i b(index(i, j), index(i + 1, j + 1), index(i, j + 1));
            // Wind each triangle so that its geometric normal agrees with the vertex
            // normals (the grid's orientation depends on the parameterisation).
            for (Vector3i *face : {&a, &b}) {
                const Vector3f e1 = mesh.positions[(*face)[1]] - mesh.positions[(*face)[0]];
                const Vector3f e2 = mesh.positions[(*face)[2]] - mesh.positions[(*face)[0]];
                const Vector3f n =
                    mesh.normals[(*face)[0]] + mesh.normals[(*face)[1]] + mesh.normals[(*face)[2]];
                if (e1.cross(e2).dot(n) < 0.0f)
                    std::swap((*face)[1], (*face)[2]);
            }
            mesh.triangles.push_back(a);
            mesh.triangles.push_back(b);
        }
    return mesh;
}

int segmentsFor(float phiMax, int segments) {
    return std::max(3, int(std::ceil(float(segments) * phiMax / (2.0f * kPi))));
}

} // namespace

MeshData tessellateSphere(float radius, float zMin, float zMax, float phiMax, int segments) {
    const float z0 = std::clamp(std::min(zMin, zMax), -radius, radius);
    const float z1 = std::clamp(std::max(zMin, zMax), -radius, radius);
    const float theta0 = std::acos(std::clamp(z0 / radius, -1.0f, 1.0f));
    const float theta1 = std::acos(std::clamp(z1 / radius, -1.0f, 1.0f));
    const int rows = std::max(2, int(std::ceil(float(segments) / 2.0f * (theta0 - theta1) / kPi)));
    return grid(segmentsFor(phiMax, segments), rows,
                [&](float u, float v, Point3f &p, Normal3f &n) {
                    const float phi = u * phiMax, theta = theta0 + v * (theta1 - theta0);
                    n = Normal3f(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                                 std::cos(theta));
                    p = Point3f(radius * n.x(), radius * n.y(), radius * n.z());
                });
}

MeshData tessellateDisk(float height, float radius, float innerRadius, float phiMax, int segments) {
    return grid(segmentsFor(phiMax, segments), std::max(1, segments / 8),
                [&](float u, float v, Point3f &p, Normal3f &n) {
                    const float phi = u * phiMax, r = radius - v * (radius - innerRadius);
                    p = Point3f(r * std::cos(phi), r * std::sin(phi), height);
                    n = Normal3f(0.0f, 0.0f, 1.0f);
                });
}

MeshData tessellateCylinder(float radius, float zMin, float zMax, float phiMax, int segments) {
    const float z0 = std::min(zMin, zMax), z1 = std::max(zMin, zMax);
    return grid(segmentsFor(phiMax, segments), 1, [&](float u, float v, Point3f &p, Normal3f &n) {
        const float phi = u * phiMax;
        n = Normal3f(std::cos(phi), std::sin(phi), 0.0f);
        p = Point3f(radius * n.x(), radius * n.y(), z0 + v * (z1 - z0));
    });
}

MeshData bilinearPatchesToTriangles(MeshData patches, const std::vector<int> &indices) {
    // Vertices p00, p10, p01, p11: the quad's boundary runs p00 → p10 → p11 → p01.
    for (size_t i = 0; i + 3 < indices.size(); i += 4) {
        const int p00 = indices[i], p10 = indices[i + 1], p01 = indices[i + 2],
                  p11 = indices[i + 3];
        patches.triangles.emplace_back(p00, p10, p11);
        patches.triangles.emplace_back(p00, p11, p01);
    }
    return patches;
}

namespace {

using Edge = std::pair<int, int>;

Edge edgeOf(int a, int b) {
    return {std::min(a, b), std::max(a, b)};
}

/// The topology one subdivision step needs: each edge's opposite vertices (one on a
/// boundary, two inside), each vertex's neighbours and its neighbours along boundaries.
struct Topology {
    std::map<Edge, std::vector<int>> opposite;
    std::vector<std::set<int>> neighbours, boundaryNeighbours;

    explicit Topology(const MeshData &mesh)
        : neighbours(mesh.positions.size()), boundaryNeighbours(mesh.positions.size()) {
        for (const Vector3i &face : mesh.triangles)
            for (int k = 0; k < 3; ++k) {
                const int a = face[k], b = face[(k + 1) % 3], c = face[(k + 2) % 3];
                opposite[edgeOf(a, b)].push_back(c);
                neighbours[size_t(a)].insert(b);
                neighbours[size_t(b)].insert(a);
            }
        for (const auto &[edge, others] : opposite)
            if (others.size() == 1) {
                boundaryNeighbours[size_t(edge.first)].insert(edge.second);
                boundaryNeighbours[size_t(edge.second)].insert(edge.first);
            }
    }

    bool onBoundary(size_t vertex) const { return !boundaryNeighbours[vertex].empty(); }
};

/// Loop's weight β for an interior vertex of valence n (Warren's simplification).
float loopBeta(size_t valence) {
    return valence == 3 ? 3.0f / 16.0f : 3.0f / (8.0f * float(valence));
}

Point3f weightedSum(const Point3f &center, float centerWeight, const std::set<int> &ring,
                    float ringWeight, const std::vector<Point3f> &positions) {
    Vector3f sum = centerWeight * Vector3f(center);
    for (int other : ring)
        sum += ringWeight * Vector3f(positions[size_t(other)]);
    return Point3f(sum);
}

} // namespace

MeshData loopSubdivide(MeshData mesh, int levels) {
    mesh.normals.clear();
    mesh.texCoords.clear();
    for (int level = 0; level < levels; ++level) {
        const Topology topology(mesh);
        const std::vector<Point3f> &p = mesh.positions;
        MeshData next;
        // Even vertices: the old ones, smoothed.
        for (size_t v = 0; v < p.size(); ++v) {
            if (topology.onBoundary(v)) {
                const std::set<int> &ring = topology.boundaryNeighbours[v];
                next.positions.push_back(
                    ring.size() == 2 ? weightedSum(p[v], 0.75f, ring, 0.125f, p) : p[v]);
            } else if (topology.neighbours[v].empty()) {
                next.positions.push_back(p[v]);
            } else {
                const size_t n = topology.neighbours[v].size();
                const float beta = loopBeta(n);
                next.positions.push_back(
                    weightedSum(p[v], 1.0f - float(n) * beta, topology.neighbours[v], beta, p));
            }
        }
        // Odd vertices: one per edge.
        std::map<Edge, int> edgeVertex;
        for (const auto &[edge, others] : topology.opposite) {
            const Vector3f a = p[size_t(edge.first)], b = p[size_t(edge.second)];
            Vector3f position = 0.5f * (a + b);
            if (others.size() == 2)
                position = 0.375f * (a + b) + 0.125f * (Vector3f(p[size_t(others[0])]) +
                                                        Vector3f(p[size_t(others[1])]));
            edgeVertex[edge] = int(next.positions.size());
            next.positions.emplace_back(position);
        }
        for (const Vector3i &face : mesh.triangles) {
            const int a = face[0], b = face[1], c = face[2];
            const int ab = edgeVertex.at(edgeOf(a, b)), bc = edgeVertex.at(edgeOf(b, c)),
                      ca = edgeVertex.at(edgeOf(c, a));
            next.triangles.emplace_back(a, ab, ca);
            next.triangles.emplace_back(b, bc, ab);
            next.triangles.emplace_back(c, ca, bc);
            next.triangles.emplace_back(ab, bc, ca);
        }
        mesh = std::move(next);
    }

    // The limit positions (PBR 3rd ed. §3.8.3): γ = 1/(n + 3/(8β)) inside, the boundary
    // rule (1/5, 3/5, 1/5).
    const Topology topology(mesh);
    std::vector<Point3f> limit(mesh.positions.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
        if (topology.onBoundary(v)) {
            const std::set<int> &ring = topology.boundaryNeighbours[v];
            limit[v] = ring.size() == 2
                           ? weightedSum(mesh.positions[v], 0.6f, ring, 0.2f, mesh.positions)
                           : mesh.positions[v];
        } else if (topology.neighbours[v].empty()) {
            limit[v] = mesh.positions[v];
        } else {
            const size_t n = topology.neighbours[v].size();
            const float gamma = 1.0f / (float(n) + 3.0f / (8.0f * loopBeta(n)));
            limit[v] = weightedSum(mesh.positions[v], 1.0f - float(n) * gamma,
                                   topology.neighbours[v], gamma, mesh.positions);
        }
    }
    mesh.positions = std::move(limit);

    mesh.normals.assign(mesh.positions.size(), Normal3f(0.0f, 0.0f, 0.0f));
    for (const Vector3i &face : mesh.triangles) {
        const Vector3f e1 = mesh.positions[size_t(face[1])] - mesh.positions[size_t(face[0])];
        const Vector3f e2 = mesh.positions[size_t(face[2])] - mesh.positions[size_t(face[0])];
        const Vector3f areaNormal = e1.cross(e2); // length: twice the triangle's area
        for (int k = 0; k < 3; ++k)
            mesh.normals[size_t(face[k])] += areaNormal;
    }
    for (Normal3f &n : mesh.normals) {
        const float length = n.norm();
        n = length > 0.0f ? Normal3f(n / length) : Normal3f(0.0f, 0.0f, 1.0f);
    }
    return mesh;
}

} // namespace nori::pbrt
