// The arrays of a triangle mesh as mesh files hold them (PLY, Mitsuba's serialized
// format), before a Mesh takes them over: what the readers return and the writer takes.
#pragma once

#include <nori/vector.h>

#include <vector>

namespace nori {

/// Positions and triangles; normals and uvs are empty or one per vertex.
struct MeshData {
    std::vector<Point3f> positions;
    std::vector<Normal3f> normals;
    std::vector<Point2f> texCoords;
    std::vector<Vector3i> triangles;
};

} // namespace nori
