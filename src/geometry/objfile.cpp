#include <nori/common.h>
#include <nori/filesystem.h>
#include <nori/objfile.h>
#include <nori/strutil.h>

#include <charconv>

namespace nori {

namespace {

/// Indices of one face corner into the position, uv and normal arrays (-1: absent).
struct Corner {
    int position = -1, texCoord = -1, normal = -1;
};

/// Splits a line at spaces, tabs and carriage returns into views of the text: no copies.
void splitFields(std::string_view line, std::vector<std::string_view> &fields) {
    fields.clear();
    size_t start = 0;
    while (true) {
        start = line.find_first_not_of(" \t\r", start);
        if (start == std::string_view::npos)
            return;
        const size_t end = std::min(line.find_first_of(" \t\r", start), line.size());
        fields.push_back(line.substr(start, end - start));
        start = end;
    }
}

/// Reads the records one line at a time. The arrays it grows are its only allocations:
/// a line, a field or a corner costs none.
class ObjReader {
public:
    explicit ObjReader(const std::string &name) : m_name(name) {}

    MeshData read(std::string_view text) {
        size_t offset = 0;
        while (offset < text.size()) {
            const size_t newline = std::min(text.find('\n', offset), text.size());
            ++m_lineNumber;
            readRecord(text.substr(offset, newline - offset));
            offset = newline + 1;
        }
        return mesh();
    }

private:
    void readRecord(std::string_view line) {
        splitFields(line, m_fields);
        if (m_fields.empty() || m_fields[0][0] == '#')
            return;
        const std::string_view keyword = m_fields[0];
        if (keyword == "v")
            m_positions.push_back(Point3f(readVector(3, "vertex position")));
        else if (keyword == "vt")
            m_texCoords.push_back(Point2f(readVector(2, "texture coordinate").head<2>()));
        else if (keyword == "vn")
            m_normals.push_back(Normal3f(readVector(3, "vertex normal")));
        else if (keyword == "f")
            readFace();
        // Other records (o, g, s, usemtl, mtllib, l, p, ...) do not affect geometry.
    }

    [[noreturn]] void fail(const std::string &message) const {
        throw NoriException("{}:{}: {}", m_name, m_lineNumber, message);
    }

    /// A number as toFloat reads it (strtof: hex, "+1", "inf" too); from_chars reads the
    /// common decimal forms without a copy, anything else goes to toFloat, which accepts
    /// it or says what is wrong.
    float toNumber(std::string_view field, const char *what) const {
        float value = 0.0f;
        const auto [next, error] =
            std::from_chars(field.data(), field.data() + field.size(), value);
        if (error == std::errc() && next == field.data() + field.size())
            return value;
        try {
            return toFloat(std::string(field), what);
        } catch (const NoriException &error) {
            fail(error.what());
        }
    }

    /// Reads `count` numbers after the keyword (extra ones, such as w, are allowed).
    Vector3f readVector(size_t count, const char *what) const {
        if (m_fields.size() < count + 1)
            fail(fmt::format("{} needs {} numbers, got {}", what, count, m_fields.size() - 1));
        Vector3f result(0.0f);
        for (size_t i = 0; i < count; ++i)
            result[static_cast<int>(i)] = toNumber(m_fields[i + 1], what);
        return result;
    }

    /// A 1-based index, or negative relative to the end; returns a 0-based index.
    int resolveIndex(std::string_view field, size_t available, const char *what) const {
        int index = 0;
        const auto [next, error] =
            std::from_chars(field.data(), field.data() + field.size(), index);
        if (error != std::errc() || next != field.data() + field.size()) {
            try { // what from_chars does not read ("+3"), toInt reads or explains
                index = toInt(std::string(field), what);
            } catch (const NoriException &error) {
                fail(error.what());
            }
        }
        const long resolved = index > 0 ? index - 1 : static_cast<long>(available) + index;
        if (index == 0 || resolved < 0 || resolved >= static_cast<long>(available))
            fail(fmt::format("{} index {} is out of range (there are {} so far)", what, field,
                             available));
        return static_cast<int>(resolved);
    }

    /// The output vertex of a face's "p", "p/t", "p//n" or "p/t/n" field.
    int cornerIndex(std::string_view field) {
        std::string_view parts[3];
        size_t partCount = 0, start = 0;
        while (true) {
            const size_t slash = field.find('/', start);
            if (partCount == 3)
                fail(fmt::format("malformed face vertex '{}'", field));
            parts[partCount++] = field.substr(
                start, slash == std::string_view::npos ? std::string_view::npos : slash - start);
            if (slash == std::string_view::npos)
                break;
            start = slash + 1;
        }
        if (parts[0].empty())
            fail(fmt::format("malformed face vertex '{}'", field));
        Corner corner;
        corner.position = resolveIndex(parts[0], m_positions.size(), "vertex");
        if (partCount > 1 && !parts[1].empty())
            corner.texCoord = resolveIndex(parts[1], m_texCoords.size(), "texture coordinate");
        if (partCount > 2 && !parts[2].empty())
            corner.normal = resolveIndex(parts[2], m_normals.size(), "normal");
        return findOrAddCorner(corner);
    }

    /// Corners are told apart by a chain per position (most positions have one corner,
    /// seams a few), numbered in the order they first appear.
    int findOrAddCorner(const Corner &corner) {
        if (m_firstCorner.size() < m_positions.size())
            m_firstCorner.resize(m_positions.size(), -1);
        int &first = m_firstCorner[static_cast<size_t>(corner.position)];
        for (int c = first; c >= 0; c = m_nextCorner[static_cast<size_t>(c)]) {
            const Corner &known = m_corners[static_cast<size_t>(c)];
            if (known.texCoord == corner.texCoord && known.normal == corner.normal)
                return c;
        }
        const int index = static_cast<int>(m_corners.size());
        m_corners.push_back(corner);
        m_nextCorner.push_back(first);
        first = index;
        return index;
    }

    void readFace() {
        if (m_fields.size() < 4)
            fail(fmt::format("a face needs at least 3 vertices, got {}", m_fields.size() - 1));
        m_polygon.clear();
        for (size_t i = 1; i < m_fields.size(); ++i)
            m_polygon.push_back(cornerIndex(m_fields[i]));
        // A convex polygon as a fan around its first vertex.
        for (size_t i = 1; i + 1 < m_polygon.size(); ++i)
            m_triangles.emplace_back(m_polygon[0], m_polygon[i], m_polygon[i + 1]);
    }

    /// One vertex per corner; uvs and normals when every corner has one.
    MeshData mesh() {
        const bool allHaveUVs = std::all_of(m_corners.begin(), m_corners.end(),
                                            [](const Corner &c) { return c.texCoord >= 0; });
        const bool allHaveNormals = std::all_of(m_corners.begin(), m_corners.end(),
                                                [](const Corner &c) { return c.normal >= 0; });
        MeshData data;
        data.positions.reserve(m_corners.size());
        if (allHaveUVs)
            data.texCoords.reserve(m_corners.size());
        if (allHaveNormals)
            data.normals.reserve(m_corners.size());
        for (const Corner &corner : m_corners) {
            data.positions.push_back(m_positions[static_cast<size_t>(corner.position)]);
            if (allHaveUVs)
                data.texCoords.push_back(m_texCoords[static_cast<size_t>(corner.texCoord)]);
            if (allHaveNormals)
                data.normals.push_back(m_normals[static_cast<size_t>(corner.normal)]);
        }
        data.triangles = std::move(m_triangles);
        return data;
    }

    const std::string &m_name;
    size_t m_lineNumber = 0;
    std::vector<std::string_view> m_fields; ///< of the current line
    std::vector<int> m_polygon;             ///< corners of the current face
    std::vector<Point3f> m_positions;
    std::vector<Point2f> m_texCoords;
    std::vector<Normal3f> m_normals;
    std::vector<Corner> m_corners;     ///< unique face corners, one per output vertex
    std::vector<int> m_firstCorner;    ///< per position: its latest corner, or -1
    std::vector<int> m_nextCorner;     ///< per corner: the position's previous corner, or -1
    std::vector<Vector3i> m_triangles; ///< indices into m_corners
};

} // namespace

MeshData parseOBJ(std::string_view text, const std::string &name) {
    return ObjReader(name).read(text);
}

MeshData readOBJ(const std::string &path) {
    return parseOBJ(readTextFile(path, "OBJ mesh file"), path);
}

} // namespace nori
