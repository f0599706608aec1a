#include <nori/common.h>
#include <nori/compression.h>
#include <nori/filesystem.h>
#include <nori/plyfile.h>
#include <nori/strutil.h>

#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <map>
#include <optional>

namespace nori {

namespace {

enum class Encoding { Ascii, BinaryLittle, BinaryBig };

enum class ScalarType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

size_t sizeOf(ScalarType type) {
    switch (type) {
    case ScalarType::Int8:
    case ScalarType::UInt8:
        return 1;
    case ScalarType::Int16:
    case ScalarType::UInt16:
        return 2;
    case ScalarType::Int32:
    case ScalarType::UInt32:
    case ScalarType::Float32:
        return 4;
    case ScalarType::Float64:
        return 8;
    }
    return 0;
}

std::optional<ScalarType> scalarTypeOf(const std::string &name) {
    static const std::map<std::string, ScalarType> kTypes = {
        {"char", ScalarType::Int8},      {"int8", ScalarType::Int8},
        {"uchar", ScalarType::UInt8},    {"uint8", ScalarType::UInt8},
        {"short", ScalarType::Int16},    {"int16", ScalarType::Int16},
        {"ushort", ScalarType::UInt16},  {"uint16", ScalarType::UInt16},
        {"int", ScalarType::Int32},      {"int32", ScalarType::Int32},
        {"uint", ScalarType::UInt32},    {"uint32", ScalarType::UInt32},
        {"float", ScalarType::Float32},  {"float32", ScalarType::Float32},
        {"double", ScalarType::Float64}, {"float64", ScalarType::Float64}};
    const auto it = kTypes.find(name);
    return it == kTypes.end() ? std::nullopt : std::optional<ScalarType>(it->second);
}

struct Property {
    std::string name;
    ScalarType type = ScalarType::Float32; ///< of the value, or of a list's entries
    bool isList = false;
    ScalarType countType = ScalarType::UInt8; ///< of a list's length
};

struct Element {
    std::string name;
    size_t count = 0;
    std::vector<Property> properties;
};

/// Reads the values of the body, ASCII or binary, and says where it is in errors.
class BodyReader {
public:
    BodyReader(std::string_view bytes, size_t offset, Encoding encoding, size_t line,
               const std::string &name)
        : m_bytes(bytes), m_offset(offset), m_encoding(encoding), m_line(line), m_name(name) {}

    double read(ScalarType type) {
        return m_encoding == Encoding::Ascii ? readAscii() : readBinary(type);
    }

    /// A list's length, of type `countType`: a whole number no larger than what is left
    /// (ASCII files can write any number there, "nan" included).
    size_t readListLength(ScalarType countType, const std::string &what) {
        const double length = read(countType);
        if (!(length >= 0.0 && length <= static_cast<double>(remaining())) ||
            length != std::floor(length))
            fail(fmt::format("{} has a bad length {}", what, length));
        return static_cast<size_t>(length);
    }

    size_t remaining() const { return m_bytes.size() - m_offset; }
    bool isAscii() const { return m_encoding == Encoding::Ascii; }

    [[noreturn]] void fail(const std::string &message) const {
        if (m_encoding == Encoding::Ascii)
            throw NoriException("{}: line {}: {}", m_name, m_line, message);
        throw NoriException("{}: byte {}: {}", m_name, m_offset, message);
    }

private:
    double readAscii() {
        while (m_offset < m_bytes.size() &&
               std::isspace(static_cast<unsigned char>(m_bytes[m_offset]))) {
            if (m_bytes[m_offset] == '\n')
                ++m_line;
            ++m_offset;
        }
        if (m_offset == m_bytes.size())
            fail("the file ends before its elements do");
        const char *begin = m_bytes.data() + m_offset, *end = m_bytes.data() + m_bytes.size();
        double value = 0.0;
        const auto [next, error] = std::from_chars(begin, end, value);
        if (error != std::errc() ||
            (next < end && !std::isspace(static_cast<unsigned char>(*next)))) {
            const char *stop = begin;
            while (stop < end && !std::isspace(static_cast<unsigned char>(*stop)) &&
                   stop - begin < 32)
                ++stop;
            fail(fmt::format("'{}' is not a number", std::string(begin, stop)));
        }
        m_offset += static_cast<size_t>(next - begin);
        return value;
    }

    double readBinary(ScalarType type) {
        switch (type) {
        case ScalarType::Int8:
            return readBinary<int8_t>();
        case ScalarType::UInt8:
            return readBinary<uint8_t>();
        case ScalarType::Int16:
            return readBinary<int16_t>();
        case ScalarType::UInt16:
            return readBinary<uint16_t>();
        case ScalarType::Int32:
            return readBinary<int32_t>();
        case ScalarType::UInt32:
            return readBinary<uint32_t>();
        case ScalarType::Float32:
            return readBinary<float>();
        case ScalarType::Float64:
            return readBinary<double>();
        }
        return 0.0;
    }

    /// The next value of type T, in the file's byte order (the machine's is little-endian).
    template <typename T> double readBinary() {
        if (remaining() < sizeof(T))
            fail("the file ends before its elements do");
        unsigned char raw[sizeof(T)];
        std::memcpy(raw, m_bytes.data() + m_offset, sizeof(T));
        if (m_encoding == Encoding::BinaryBig)
            std::reverse(raw, raw + sizeof(T));
        m_offset += sizeof(T);
        T value;
        std::memcpy(&value, raw, sizeof(T));
        return static_cast<double>(value);
    }

    std::string_view m_bytes;
    size_t m_offset;
    Encoding m_encoding;
    size_t m_line;
    const std::string &m_name;
};

/// The header: its elements, the encoding, and where the body starts.
struct Header {
    Encoding encoding = Encoding::Ascii;
    std::vector<Element> elements;
    size_t bodyOffset = 0;
    size_t bodyLine = 0; ///< the line the body starts on (ASCII)
};

Header parseHeader(std::string_view bytes, const std::string &name) {
    Header header;
    size_t offset = 0, lineNumber = 0;
    bool sawFormat = false;
    auto fail = [&](const std::string &message) {
        throw NoriException("{}: line {}: {}", name, lineNumber, message);
    };
    while (true) {
        const size_t newline = bytes.find('\n', offset);
        if (newline == std::string_view::npos) {
            lineNumber += 1;
            fail("the header has no 'end_header' line");
        }
        std::string line(bytes.substr(offset, newline - offset));
        offset = newline + 1;
        ++lineNumber;
        if (!line.empty() && line.back() == '\r')
            line.pop_back();
        const std::vector<std::string> tokens = tokenize(line, " \t");
        if (lineNumber == 1) {
            if (tokens.size() != 1 || tokens[0] != "ply")
                fail("not a PLY file (its first line is not 'ply')");
            continue;
        }
        if (tokens.empty() || tokens[0] == "comment" || tokens[0] == "obj_info")
            continue;
        const std::string &keyword = tokens[0];
        if (keyword == "end_header")
            break;
        if (keyword == "format") {
            if (tokens.size() != 3)
                fail("'format' takes an encoding and a version");
            if (tokens[1] == "ascii")
                header.encoding = Encoding::Ascii;
            else if (tokens[1] == "binary_little_endian")
                header.encoding = Encoding::BinaryLittle;
            else if (tokens[1] == "binary_big_endian")
                header.encoding = Encoding::BinaryBig;
            else
                fail(fmt::format("unknown format '{}' (ascii, binary_little_endian or "
                                 "binary_big_endian)",
                                 tokens[1]));
            sawFormat = true;
        } else if (keyword == "element") {
            if (tokens.size() != 3)
                fail("'element' takes a name and a count");
            Element element;
            element.name = tokens[1];
            const char *begin = tokens[2].data(), *end = begin + tokens[2].size();
            const auto [next, error] = std::from_chars(begin, end, element.count);
            if (error != std::errc() || next != end)
                fail(fmt::format("the count of element '{}' is not a number: '{}'", tokens[1],
                                 tokens[2]));
            header.elements.push_back(element);
        } else if (keyword == "property") {
            if (header.elements.empty())
                fail("a 'property' before any 'element'");
            Property property;
            if (tokens.size() == 5 && tokens[1] == "list") {
                const auto countType = scalarTypeOf(tokens[2]), type = scalarTypeOf(tokens[3]);
                if (!countType || !type)
                    fail(fmt::format("unknown type '{}' in a list property",
                                     countType ? tokens[3] : tokens[2]));
                if (*countType == ScalarType::Float32 || *countType == ScalarType::Float64)
                    fail("a list's length must have an integer type");
                property = {tokens[4], *type, true, *countType};
            } else if (tokens.size() == 3) {
                const auto type = scalarTypeOf(tokens[1]);
                if (!type)
                    fail(fmt::format("unknown property type '{}'", tokens[1]));
                property = {tokens[2], *type, false, ScalarType::UInt8};
            } else {
                fail("'property' takes a type and a name, or 'list', two types and a name");
            }
            header.elements.back().properties.push_back(property);
        } else {
            fail(fmt::format("unknown header line '{}'", keyword));
        }
    }
    if (!sawFormat)
        throw NoriException("{}: the header has no 'format' line", name);
    header.bodyOffset = offset;
    header.bodyLine = lineNumber + 1;
    return header;
}

/// The index of the property called one of `names`, or -1.
int findProperty(const Element &element, std::initializer_list<const char *> names) {
    for (size_t i = 0; i < element.properties.size(); ++i)
        for (const char *name : names)
            if (element.properties[i].name == name && !element.properties[i].isList)
                return static_cast<int>(i);
    return -1;
}

/// Checks that `count` items of at least `minimumBytes` each fit in what is left, so that
/// a header claiming billions of vertices is refused before anything is allocated.
void checkCount(const BodyReader &reader, const Element &element, size_t minimumBytes) {
    // (+ 1: the last ASCII value of a file needs no separator after it.)
    if (minimumBytes > 0 && element.count > (reader.remaining() + 1) / minimumBytes)
        reader.fail(fmt::format("element '{}' claims {} items, more than the {} bytes left can "
                                "hold",
                                element.name, element.count, reader.remaining()));
}

/// The fewest bytes one item of the element takes (lists at their shortest).
size_t minimumItemBytes(const Element &element, bool ascii) {
    size_t bytes = 0;
    for (const Property &property : element.properties)
        bytes += ascii ? 2 : (property.isList ? sizeOf(property.countType) : sizeOf(property.type));
    return bytes;
}

} // namespace

MeshData parsePLY(std::string_view bytes, const std::string &name) {
    const Header header = parseHeader(bytes, name);
    BodyReader reader(bytes, header.bodyOffset, header.encoding, header.bodyLine, name);
    MeshData mesh;
    bool sawVertices = false, sawFaces = false;
    size_t vertexCount = 0;
    for (const Element &element : header.elements) {
        checkCount(reader, element, minimumItemBytes(element, reader.isAscii()));
        const size_t propertyCount = element.properties.size();
        std::vector<double> values(propertyCount);
        if (element.name == "vertex") {
            if (sawVertices)
                reader.fail("a second 'vertex' element");
            sawVertices = true;
            const int x = findProperty(element, {"x"}), y = findProperty(element, {"y"}),
                      z = findProperty(element, {"z"});
            if (x < 0 || y < 0 || z < 0)
                throw NoriException("{}: the 'vertex' element has no x, y and z properties", name);
            const int nx = findProperty(element, {"nx"}), ny = findProperty(element, {"ny"}),
                      nz = findProperty(element, {"nz"});
            const int u = findProperty(element, {"u", "s", "texture_u", "texture_s"}),
                      v = findProperty(element, {"v", "t", "texture_v", "texture_t"});
            const bool hasNormals = nx >= 0 && ny >= 0 && nz >= 0, hasUVs = u >= 0 && v >= 0;
            vertexCount = element.count;
            mesh.positions.reserve(vertexCount);
            if (hasNormals)
                mesh.normals.reserve(vertexCount);
            if (hasUVs)
                mesh.texCoords.reserve(vertexCount);
            for (size_t i = 0; i < element.count; ++i) {
                for (size_t p = 0; p < propertyCount; ++p) {
                    const Property &property = element.properties[p];
                    if (property.isList) { // a list on a vertex: read past it
                        const size_t length = reader.readListLength(
                            property.countType, fmt::format("list '{}'", property.name));
                        for (size_t k = 0; k < length; ++k)
                            reader.read(property.type);
                    } else {
                        values[p] = reader.read(property.type);
                    }
                }
                auto at = [&values](int index) {
                    return static_cast<float>(values[size_t(index)]);
                };
                mesh.positions.emplace_back(at(x), at(y), at(z));
                if (hasNormals)
                    mesh.normals.emplace_back(at(nx), at(ny), at(nz));
                if (hasUVs)
                    mesh.texCoords.emplace_back(at(u), at(v));
            }
        } else if (element.name == "face") {
            if (!sawVertices)
                reader.fail("the 'face' element comes before the 'vertex' element");
            if (sawFaces)
                reader.fail("a second 'face' element");
            sawFaces = true;
            int indices = -1;
            for (size_t p = 0; p < propertyCount; ++p)
                if (element.properties[p].isList &&
                    (element.properties[p].name == "vertex_indices" ||
                     element.properties[p].name == "vertex_index"))
                    indices = static_cast<int>(p);
            if (indices < 0)
                throw NoriException("{}: the 'face' element has no 'vertex_indices' list", name);
            mesh.triangles.reserve(element.count);
            std::vector<int> polygon;
            for (size_t i = 0; i < element.count; ++i) {
                for (size_t p = 0; p < propertyCount; ++p) {
                    const Property &property = element.properties[p];
                    if (!property.isList) {
                        reader.read(property.type);
                        continue;
                    }
                    const size_t n =
                        reader.readListLength(property.countType, fmt::format("face {}'s list", i));
                    if (static_cast<int>(p) != indices) {
                        for (size_t k = 0; k < n; ++k)
                            reader.read(property.type);
                        continue;
                    }
                    if (n < 3)
                        reader.fail(
                            fmt::format("face {} has {} vertices; a face needs 3 or more", i, n));
                    polygon.clear();
                    for (size_t k = 0; k < n; ++k) {
                        const double index = reader.read(property.type);
                        if (!(index >= 0 && index < static_cast<double>(vertexCount)) ||
                            index != std::floor(index))
                            reader.fail(fmt::format("face {} names vertex {}, but there are {}", i,
                                                    index, vertexCount));
                        polygon.push_back(static_cast<int>(index));
                    }
                    // A convex polygon as a fan about its first vertex.
                    for (size_t k = 1; k + 1 < n; ++k)
                        mesh.triangles.emplace_back(polygon[0], polygon[k], polygon[k + 1]);
                }
            }
        } else if (!element.properties.empty()) {
            // Another element (edges, materials, ...): read past it. (Without properties its
            // items take no bytes, however many a hostile header claims: nothing to read.)
            for (size_t i = 0; i < element.count; ++i)
                for (const Property &property : element.properties) {
                    if (!property.isList) {
                        reader.read(property.type);
                        continue;
                    }
                    const size_t length = reader.readListLength(
                        property.countType, fmt::format("list '{}'", property.name));
                    for (size_t k = 0; k < length; ++k)
                        reader.read(property.type);
                }
        }
    }
    if (!sawVertices)
        throw NoriException("{}: no 'vertex' element", name);
    if (!sawFaces)
        throw NoriException("{}: no 'face' element (point clouds are not meshes)", name);
    return mesh;
}

MeshData readPLY(const std::string &path) {
    std::string bytes = readBinaryFile(path, "PLY mesh file");
    if (isGzip(bytes))
        bytes = inflateBytes(bytes, CompressedFormat::Gzip, path, kMaxInflatedMeshBytes);
    return parsePLY(bytes, path);
}

void writePLY(const std::string &path, const MeshData &mesh) {
    std::string header = "ply\nformat binary_little_endian 1.0\ncomment written by nori\n";
    header +=
        fmt::format("element vertex {}\nproperty float x\nproperty float y\nproperty float z\n",
                    mesh.positions.size());
    if (!mesh.normals.empty())
        header += "property float nx\nproperty float ny\nproperty float nz\n";
    if (!mesh.texCoords.empty())
        header += "property float u\nproperty float v\n";
    header += fmt::format("element face {}\nproperty list uchar int vertex_indices\nend_header\n",
                          mesh.triangles.size());
    std::string bytes = header;
    auto append = [&bytes](const auto &value) {
        // Little-endian, as the machine stores it.
        bytes.append(reinterpret_cast<const char *>(&value), sizeof(value));
    };
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        for (int k = 0; k < 3; ++k)
            append(mesh.positions[i][k]);
        if (!mesh.normals.empty())
            for (int k = 0; k < 3; ++k)
                append(mesh.normals[i][k]);
        if (!mesh.texCoords.empty())
            for (int k = 0; k < 2; ++k)
                append(mesh.texCoords[i][k]);
    }
    for (const Vector3i &triangle : mesh.triangles) {
        append(static_cast<uint8_t>(3));
        for (int k = 0; k < 3; ++k)
            append(static_cast<int32_t>(triangle[k]));
    }
    writeBinaryFile(path, bytes, "PLY mesh file");
}

} // namespace nori
