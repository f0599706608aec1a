// Mitsuba's `serialized` mesh files (Mitsuba 0.6 documentation, "serialized"): one or more
// meshes, each a zlib stream of flags, counts and arrays behind a two-short header, with a
// table of their offsets at the end of the file. Little-endian.
#pragma once

#include <nori/meshdata.h>

#include <string>
#include <string_view>

namespace nori {

/// The mesh of a serialized file's bytes, and whether it asks for face normals.
struct SerializedMesh {
    MeshData data;
    std::string name;         ///< the mesh's name (format version 4), or ""
    bool faceNormals = false; ///< the file's flag 0x0010: shade with the faces' normals
};

/// Mesh number `shapeIndex` (from 0) of a serialized file's bytes; `name` names the file in
/// errors. Throws NoriException naming what is malformed and where (the byte offset).
SerializedMesh parseSerialized(std::string_view bytes, int shapeIndex, const std::string &name);

/// As parseSerialized, from the file at `path`.
SerializedMesh readSerialized(const std::string &path, int shapeIndex);

} // namespace nori
