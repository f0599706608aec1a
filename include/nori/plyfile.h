// The PLY polygon file format (Turk 1994; as Paul Bourke's page and pbrt-v4's `plymesh`
// use it): ASCII, binary little- and big-endian, gzip-compressed (.ply.gz), read into the
// arrays of a triangle mesh; and written, binary, for `nori convert`.
#pragma once

#include <nori/meshdata.h>

#include <string>
#include <string_view>

namespace nori {

/// Reads a PLY file (gzip-compressed when it starts with gzip's magic number). Vertices
/// give x, y, z and optionally nx, ny, nz and uv under any of the names PLY writers use
/// (u v, s t, texture_u texture_v, texture_s texture_t); faces give `vertex_indices` (or
/// `vertex_index`), polygons of any size split into fans; other elements and properties
/// are skipped. Throws NoriException with the file and the line (ASCII) or byte offset
/// (binary) of what is malformed.
MeshData readPLY(const std::string &path);
/// As readPLY, from the file's bytes (already inflated); `name` names it in errors.
MeshData parsePLY(std::string_view bytes, const std::string &name);

/// Writes a binary little-endian PLY file (float positions, normals and uvs when present,
/// uchar/int triangle lists). Throws NoriException when it cannot.
void writePLY(const std::string &path, const MeshData &mesh);

} // namespace nori
