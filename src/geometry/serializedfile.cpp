#include <nori/common.h>
#include <nori/compression.h>
#include <nori/filesystem.h>
#include <nori/serializedfile.h>

#include <cstring>
#include <limits>

namespace nori {

namespace {

constexpr uint16_t kFormatIdentifier = 0x041C;
// The flags of a mesh (Mitsuba 0.6's TriMesh::EMeshFlags).
constexpr uint32_t kVertexNormals = 0x0001, kTexCoords = 0x0002, kVertexColors = 0x0008,
                   kFaceNormals = 0x0010, kSinglePrecision = 0x1000, kDoublePrecision = 0x2000;

/// Reads little-endian values from bytes, every read bounds-checked.
class Reader {
public:
    Reader(std::string_view bytes, const std::string &name, std::string what)
        : m_bytes(bytes), m_name(name), m_what(std::move(what)) {}

    template <typename T> T read() {
        if (m_bytes.size() - m_offset < sizeof(T))
            fail(fmt::format("ends early ({} bytes, a {}-byte value wanted at {})", m_bytes.size(),
                             sizeof(T), m_offset));
        T value;
        std::memcpy(&value, m_bytes.data() + m_offset, sizeof(T)); // the machine is little-endian
        m_offset += sizeof(T);
        return value;
    }
    std::string readString() {
        const size_t end = m_bytes.find('\0', m_offset);
        if (end == std::string_view::npos)
            fail("has a name without its terminating NUL");
        std::string text(m_bytes.substr(m_offset, end - m_offset));
        m_offset = end + 1;
        return text;
    }
    size_t remaining() const { return m_bytes.size() - m_offset; }
    void seek(size_t offset) { m_offset = offset; }

    [[noreturn]] void fail(const std::string &message) const {
        throw NoriException("serialized mesh file '{}': {} {}", m_name, m_what, message);
    }

private:
    std::string_view m_bytes;
    const std::string &m_name;
    std::string m_what;
    size_t m_offset = 0;
};

} // namespace

SerializedMesh parseSerialized(std::string_view bytes, int shapeIndex, const std::string &name) {
    Reader file(bytes, name, "the file");
    const auto identifier = file.read<uint16_t>();
    const auto version = file.read<uint16_t>();
    if (identifier != kFormatIdentifier)
        file.fail(
            fmt::format("starts with {:#06x}, not the format's identifier 0x041c", identifier));
    if (version != 3 && version != 4)
        file.fail(fmt::format("has format version {}; versions 3 and 4 are read", version));

    // The offset table at the end: the count last, before it one offset per mesh (64-bit
    // in version 4, 32-bit in version 3).
    const size_t offsetSize = version == 4 ? 8 : 4;
    if (bytes.size() < 4 + 4)
        file.fail("is too short for its table of meshes");
    file.seek(bytes.size() - 4);
    const auto count = file.read<uint32_t>();
    if (count == 0 || count > (bytes.size() - 8) / offsetSize)
        file.fail(
            fmt::format("claims {} meshes, which its {} bytes cannot hold", count, bytes.size()));
    if (shapeIndex < 0 || static_cast<uint32_t>(shapeIndex) >= count)
        throw NoriException("serialized mesh file '{}': 'shapeIndex' {} is out of range (the "
                            "file holds {} meshes, 0 to {})",
                            name, shapeIndex, count, count - 1);
    file.seek(bytes.size() - 4 - offsetSize * (count - static_cast<uint32_t>(shapeIndex)));
    const uint64_t offset = version == 4 ? file.read<uint64_t>() : file.read<uint32_t>();
    if (offset > bytes.size() - 4)
        file.fail(fmt::format("places mesh {} at byte {}, past its end", shapeIndex, offset));
    file.seek(offset);
    if (file.read<uint16_t>() != kFormatIdentifier || file.read<uint16_t>() != version)
        file.fail(fmt::format("has no mesh header at byte {} (mesh {})", offset, shapeIndex));

    const std::string what = fmt::format("mesh {} (at byte {})", shapeIndex, offset);
    const std::string inflated =
        inflateBytes(bytes.substr(offset + 4), CompressedFormat::Zlib,
                     fmt::format("'{}' {}", name, what), kMaxInflatedMeshBytes);
    Reader mesh(inflated, name, what);
    SerializedMesh result;
    const auto flags = mesh.read<uint32_t>();
    if (version == 4)
        result.name = mesh.readString();
    const auto vertexCount = mesh.read<uint64_t>();
    const auto triangleCount = mesh.read<uint64_t>();
    const bool doubles = (flags & kDoublePrecision) != 0;
    if (doubles == ((flags & kSinglePrecision) != 0))
        mesh.fail(fmt::format("has the flags {:#x}: neither or both of single and double precision",
                              flags));
    const size_t scalar = doubles ? 8 : 4;
    const size_t perVertex =
        scalar * (3 + ((flags & kVertexNormals) ? 3 : 0) + ((flags & kTexCoords) ? 2 : 0) +
                  ((flags & kVertexColors) ? 3 : 0));
    if (vertexCount > static_cast<uint64_t>(std::numeric_limits<int>::max()))
        mesh.fail(fmt::format("has {} vertices; at most {} are supported", vertexCount,
                              std::numeric_limits<int>::max()));
    const bool wideIndices = vertexCount > std::numeric_limits<uint32_t>::max();
    const uint64_t perTriangle = 3 * uint64_t(wideIndices ? 8 : 4);
    // The counts must fit what was inflated before anything is allocated.
    if (vertexCount > mesh.remaining() / perVertex ||
        triangleCount > mesh.remaining() / perTriangle ||
        vertexCount * perVertex + triangleCount * perTriangle > mesh.remaining())
        mesh.fail(fmt::format("claims {} vertices and {} triangles, more than its {} bytes hold",
                              vertexCount, triangleCount, mesh.remaining()));
    auto readScalar = [&]() -> float {
        return doubles ? static_cast<float>(mesh.read<double>()) : mesh.read<float>();
    };
    MeshData &data = result.data;
    data.positions.resize(vertexCount);
    for (Point3f &p : data.positions)
        for (int k = 0; k < 3; ++k)
            p[k] = readScalar();
    if (flags & kVertexNormals) {
        data.normals.resize(vertexCount);
        for (Normal3f &n : data.normals)
            for (int k = 0; k < 3; ++k)
                n[k] = readScalar();
    }
    if (flags & kTexCoords) {
        data.texCoords.resize(vertexCount);
        for (Point2f &uv : data.texCoords)
            for (int k = 0; k < 2; ++k)
                uv[k] = readScalar();
    }
    if (flags & kVertexColors) // not used for shading: read past them
        for (uint64_t i = 0; i < 3 * vertexCount; ++i)
            readScalar();
    data.triangles.resize(triangleCount);
    for (uint64_t i = 0; i < triangleCount; ++i)
        for (int k = 0; k < 3; ++k) {
            const uint64_t index = wideIndices ? mesh.read<uint64_t>() : mesh.read<uint32_t>();
            if (index >= vertexCount)
                mesh.fail(fmt::format("triangle {} names vertex {}, but there are {}", i, index,
                                      vertexCount));
            data.triangles[i][k] = static_cast<int>(index);
        }
    result.faceNormals = (flags & kFaceNormals) != 0;
    return result;
}

SerializedMesh readSerialized(const std::string &path, int shapeIndex) {
    return parseSerialized(readBinaryFile(path, "serialized mesh file"), shapeIndex, path);
}

} // namespace nori
