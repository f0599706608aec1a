// The Wavefront OBJ format's geometry (v, vt, vn and f records; Wavefront's "Advanced
// Visualizer" manual, appendix B1), read into the arrays of a triangle mesh.
#pragma once

#include <nori/meshdata.h>

#include <string>
#include <string_view>

namespace nori {

/// Reads an OBJ file. Faces take 1-based or negative (relative) indices as `p`, `p/t`,
/// `p//n` or `p/t/n`; polygons are split into fans about their first vertex. The mesh has
/// one vertex per distinct (position, uv, normal) corner, in the order the faces first use
/// them; uvs and normals are kept only when every corner has one. Other records (o, g, s,
/// usemtl, mtllib, l, p, ...) are skipped. Throws NoriException with the file and the line
/// of what is malformed.
MeshData readOBJ(const std::string &path);
/// As readOBJ, from the file's text; `name` names it in errors.
MeshData parseOBJ(std::string_view text, const std::string &name);

} // namespace nori
