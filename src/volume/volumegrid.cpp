#include <nori/filesystem.h>
#include <nori/volumegrid.h>

#include <nanovdb/util/GridBuilder.h>
#include <nanovdb/util/GridValidator.h>
#include <nanovdb/util/IO.h>

#include <cstring>

namespace nori {

namespace {

/// Mitsuba's .vol header: "VOL", version 3, encoding (1: float32), resolution,
/// channels, bounding box (min, max) — 48 bytes, little-endian (Mitsuba 0.6 GridDataSource).
constexpr size_t kVolHeaderBytes = 48;

template <typename T> T readScalar(const std::string &bytes, size_t offset) {
    T value;
    std::memcpy(&value, bytes.data() + offset, sizeof(T));
    return value;
}

/// The affine map of a NanoVDB grid from index space to its world (our object) space.
Eigen::Matrix4f nanovdbIndexToObject(const nanovdb::Map &map) {
    const nanovdb::Vec3d origin = map.applyMap(nanovdb::Vec3d(0.0));
    Eigen::Matrix4f matrix = Eigen::Matrix4f::Identity();
    for (int axis = 0; axis < 3; ++axis) {
        nanovdb::Vec3d unit(0.0);
        unit[axis] = 1.0;
        const nanovdb::Vec3d column = map.applyMap(unit) - origin;
        for (int row = 0; row < 3; ++row)
            matrix(row, axis) = float(column[row]);
    }
    for (int row = 0; row < 3; ++row)
        matrix(row, 3) = float(origin[row]);
    return matrix;
}

/// Copies a NanoVDB grid's active bounding box into dense values (voxel centres at the
/// integer index coordinates, OpenVDB's convention).
template <typename ValueT>
VolumeGrid densify(const nanovdb::NanoGrid<ValueT> &grid, int channels, const std::string &filename,
                   const std::string &gridName, uint64_t maxValues) {
    const nanovdb::CoordBBox box = grid.indexBBox();
    if (box.empty())
        throw NoriException("NanoVDB file '{}': grid '{}' has no active voxels", filename,
                            gridName);
    const nanovdb::Coord activeSize = box.dim();
    for (int axis = 0; axis < 3; ++axis)
        if (activeSize[axis] <= 0 || activeSize[axis] > (1 << 20))
            throw NoriException("NanoVDB file '{}': grid '{}' has an invalid bounding box",
                                filename, gridName);
    // One voxel of background around the active voxels, so that lookups fade to it at
    // the edges as they do inside a sparse grid (clamping would smear the border outward).
    const nanovdb::Coord first = box.min() - nanovdb::Coord(1);
    const Vector3i resolution(activeSize[0] + 2, activeSize[1] + 2, activeSize[2] + 2);
    const uint64_t count = uint64_t(resolution.x()) * uint64_t(resolution.y()) *
                           uint64_t(resolution.z()) * uint64_t(channels);
    if (count > maxValues)
        throw NoriException("NanoVDB file '{}': grid '{}' spans {}x{}x{} voxels, more than the {} "
                            "values a dense grid may hold",
                            filename, gridName, activeSize[0], activeSize[1], activeSize[2],
                            maxValues);
    std::vector<float> values(count);
    auto accessor = grid.getAccessor();
    size_t index = 0;
    for (int z = 0; z < resolution.z(); ++z)
        for (int y = 0; y < resolution.y(); ++y)
            for (int x = 0; x < resolution.x(); ++x) {
                const ValueT value = accessor.getValue(first + nanovdb::Coord(x, y, z));
                if constexpr (std::is_same_v<ValueT, float>) {
                    values[index++] = value;
                } else {
                    for (int c = 0; c < 3; ++c)
                        values[index++] = value[c];
                }
            }
    // Unit coordinate u lies at index coordinate first − 1/2 + u·resolution.
    Eigen::Matrix4f unitToIndex = Eigen::Matrix4f::Identity();
    for (int axis = 0; axis < 3; ++axis) {
        unitToIndex(axis, axis) = float(resolution[axis]);
        unitToIndex(axis, 3) = float(first[axis]) - 0.5f;
    }
    return VolumeGrid(resolution, channels, std::move(values),
                      Transform(nanovdbIndexToObject(grid.map()) * unitToIndex), filename);
}

/// Whether every node a lookup can reach lies inside the grid's buffer, 32-byte aligned:
/// the root's tile table, and the upper, lower and leaf nodes through every child offset.
/// NanoVDB's own validator (GridValidator::checkNodes) does this only after computing a
/// checksum that already follows the offsets, and through references that may not be
/// formed to misaligned addresses; so this runs first, on raw addresses.
template <typename ValueT> bool nodesInBounds(const nanovdb::NanoGrid<ValueT> &grid) {
    using RootT = typename nanovdb::NanoGrid<ValueT>::TreeType::RootType;
    using UpperT = typename RootT::ChildNodeType;
    using LowerT = typename UpperT::ChildNodeType;
    using LeafT = typename LowerT::ChildNodeType;
    const auto *bufferStart = reinterpret_cast<const uint8_t *>(&grid);
    const auto begin = reinterpret_cast<uintptr_t>(bufferStart);
    const auto end = begin + grid.gridSize();
    // The node of `size` bytes at base + offset, as a pointer into the buffer, or nullptr
    // when it is not inside. The address is checked as an integer before any pointer to
    // it is formed.
    auto nodeAt = [&](const void *base, int64_t offset, size_t size) -> const uint8_t * {
        const uintptr_t address = reinterpret_cast<uintptr_t>(base) + uintptr_t(offset);
        if (address < begin || address > end || end - address < size ||
            address % NANOVDB_DATA_ALIGNMENT != 0)
            return nullptr;
        return bufferStart + (address - begin);
    };
    const auto *tree = reinterpret_cast<const nanovdb::TreeData<> *>(&grid + 1);
    if (!nodeAt(tree, 0, sizeof(*tree)))
        return false;
    const uint8_t *rootAddress = nodeAt(tree, int64_t(tree->mNodeOffset[3]), sizeof(RootT));
    if (!rootAddress)
        return false;
    const auto *root = reinterpret_cast<const typename RootT::DataType *>(rootAddress);
    if (!nodeAt(root, 0, sizeof(RootT) + uint64_t(root->mTableSize) * sizeof(typename RootT::Tile)))
        return false;
    for (uint32_t i = 0; i < root->mTableSize; ++i) {
        const auto *tile = root->tile(i);
        if (!tile->isChild())
            continue;
        const uint8_t *upperAddress = nodeAt(root, tile->child, sizeof(UpperT));
        if (!upperAddress)
            return false;
        const auto *upper = reinterpret_cast<const typename UpperT::DataType *>(upperAddress);
        for (auto u = upper->mChildMask.beginOn(); u; ++u) {
            const uint8_t *lowerAddress = nodeAt(upper, upper->mTable[*u].child, sizeof(LowerT));
            if (!lowerAddress)
                return false;
            const auto *lower = reinterpret_cast<const typename LowerT::DataType *>(lowerAddress);
            for (auto l = lower->mChildMask.beginOn(); l; ++l)
                if (!nodeAt(lower, lower->mTable[*l].child, sizeof(LeafT)))
                    return false;
        }
    }
    return true;
}

/// Reads a NanoVDB file from its bytes. The segment header and grid metadata are checked
/// here, before NanoVDB sees the data, so that sizes read from a damaged file cannot
/// cause huge allocations or reads past the end; the grid is then checked by NanoVDB's
/// own validator (structure and checksum).
VolumeGrid parseNanoVDB(const std::string &bytes, const std::string &filename, uint64_t maxValues,
                        const std::string &gridName) {
    using nanovdb::io::Header;
    using nanovdb::io::MetaData;
    size_t offset = 0;
    while (offset < bytes.size()) {
        if (bytes.size() - offset < sizeof(Header))
            throw NoriException("NanoVDB file '{}' is truncated (in a segment header)", filename);
        const auto header = readScalar<Header>(bytes, offset);
        offset += sizeof(Header);
        if (header.magic != NANOVDB_MAGIC_NUMBER)
            throw NoriException("NanoVDB file '{}': bad magic number (not a NanoVDB file, or "
                                "damaged)",
                                filename);
        if (header.version.getMajor() != NANOVDB_MAJOR_VERSION_NUMBER)
            throw NoriException("NanoVDB file '{}' is of format version {}.{}.{}; this build "
                                "reads version {}.x",
                                filename, header.version.getMajor(), header.version.getMinor(),
                                header.version.getPatch(), NANOVDB_MAJOR_VERSION_NUMBER);
        if (header.codec != nanovdb::io::Codec::NONE)
            throw NoriException(
                "NanoVDB file '{}' is compressed ({}); write it uncompressed", filename,
                header.codec < nanovdb::io::Codec::END ? nanovdb::io::toStr(header.codec)
                                                       : "an unknown codec");
        // The segment's metadata records, then the grids in the same order.
        std::vector<std::pair<MetaData, std::string>> metas;
        for (int i = 0; i < header.gridCount; ++i) {
            if (bytes.size() - offset < sizeof(MetaData))
                throw NoriException("NanoVDB file '{}' is truncated (in grid metadata)", filename);
            const auto meta = readScalar<MetaData>(bytes, offset);
            offset += sizeof(MetaData);
            if (meta.nameSize > bytes.size() - offset)
                throw NoriException("NanoVDB file '{}' is truncated (in a grid name)", filename);
            std::string name(bytes.data() + offset, meta.nameSize);
            name = name.substr(0, name.find('\0'));
            offset += meta.nameSize;
            metas.emplace_back(meta, name);
        }
        for (const auto &entry : metas) {
            // (Named references, not a structured binding: the lambda below captures them.)
            const MetaData &meta = entry.first;
            const std::string &name = entry.second;
            if (meta.fileSize > bytes.size() - offset)
                throw NoriException("NanoVDB file '{}' is truncated (grid '{}' needs {} bytes, {} "
                                    "remain)",
                                    filename, name, meta.fileSize, bytes.size() - offset);
            const size_t gridOffset = offset;
            offset += meta.fileSize;
            if (!gridName.empty() && name != gridName)
                continue;
            const bool isFloat = meta.gridType == nanovdb::GridType::Float;
            if (!isFloat && meta.gridType != nanovdb::GridType::Vec3f)
                throw NoriException("NanoVDB file '{}': grid '{}' holds {} values; a medium needs "
                                    "a float grid (density) or a Vec3f grid (albedo)",
                                    filename, name,
                                    meta.gridType < nanovdb::GridType::End
                                        ? nanovdb::toStr(meta.gridType)
                                        : "unknown");
            if (meta.gridSize != meta.fileSize || meta.gridSize < sizeof(nanovdb::GridData))
                throw NoriException("NanoVDB file '{}': grid '{}' has inconsistent sizes", filename,
                                    name);
            auto buffer = nanovdb::HostBuffer::create(meta.gridSize);
            std::memcpy(buffer.data(), bytes.data() + gridOffset, meta.gridSize);
            // The buffer holds this one grid: its own header must say so before any of
            // NanoVDB's accessors trust it (GridHandle would follow its grid count).
            const auto *header = reinterpret_cast<const nanovdb::GridData *>(buffer.data());
            const bool consistent = header->mMagic == NANOVDB_MAGIC_NUMBER &&
                                    header->mGridSize == meta.gridSize &&
                                    header->mGridType == meta.gridType && header->mGridIndex == 0 &&
                                    header->mGridCount == 1;
            auto check = [&](const auto *grid) {
                // Bounds first, then the checksum of the header and root (which also covers
                // the root's child pointers), then the full validation with the checksum of
                // every node where the file has one.
                if (!consistent || !nodesInBounds(*grid) ||
                    !nanovdb::validateChecksum(*grid, nanovdb::ChecksumMode::Partial) ||
                    !nanovdb::isValid(*grid, true))
                    throw NoriException("NanoVDB file '{}': grid '{}' is damaged (it fails "
                                        "NanoVDB's validation)",
                                        filename, name);
            };
            if (isFloat) {
                const auto *grid = reinterpret_cast<const nanovdb::NanoGrid<float> *>(header);
                check(grid);
                return densify(*grid, 1, filename, name, maxValues);
            }
            const auto *grid = reinterpret_cast<const nanovdb::NanoGrid<nanovdb::Vec3f> *>(header);
            check(grid);
            return densify(*grid, 3, filename, name, maxValues);
        }
    }
    if (gridName.empty())
        throw NoriException("NanoVDB file '{}' holds no grid", filename);
    throw NoriException("NanoVDB file '{}' holds no grid named '{}'", filename, gridName);
}

} // namespace

VolumeGrid::VolumeGrid(const Vector3i &resolution, int channels, std::vector<float> values,
                       const Transform &unitToObject, const std::string &name)
    : m_resolution(resolution), m_channels(channels), m_values(std::move(values)),
      m_unitToObject(unitToObject), m_name(name) {
    if (!(resolution.minCoeff() > 0) || (channels != 1 && channels != 3) ||
        m_values.size() != size_t(resolution.cast<int64_t>().prod()) * size_t(channels))
        throw NoriException("grid '{}': {}x{}x{} voxels of {} channels do not match {} values",
                            name, resolution.x(), resolution.y(), resolution.z(), channels,
                            m_values.size());
    for (size_t i = 0; i < m_values.size(); ++i) {
        const float value = m_values[i];
        if (!(value >= 0.0f) || !std::isfinite(value)) {
            const size_t voxelIndex = i / size_t(channels);
            const size_t x = voxelIndex % size_t(resolution.x());
            const size_t y = voxelIndex / size_t(resolution.x()) % size_t(resolution.y());
            const size_t z = voxelIndex / (size_t(resolution.x()) * size_t(resolution.y()));
            throw NoriException("grid '{}' holds {} at voxel ({}, {}, {}); values must be finite "
                                "and non-negative",
                                name, value, x, y, z);
        }
        if (i % size_t(channels) == 0)
            m_maximum = std::max(m_maximum, value);
    }
}

VolumeGrid VolumeGrid::load(const std::string &filename, const std::string &gridName) {
    return parse(readBinaryFile(filename, "volume grid"), filename, gridName);
}

VolumeGrid VolumeGrid::parse(const std::string &bytes, const std::string &filename,
                             const std::string &gridName, uint64_t maxValues) {
    if (bytes.compare(0, 3, "VOL") == 0) {
        if (!gridName.empty())
            throw NoriException("'{}' is a .vol file, which holds one unnamed grid; remove the "
                                "grid name '{}'",
                                filename, gridName);
        return parseVol(bytes, filename);
    }
    return parseNanoVDB(bytes, filename, maxValues, gridName);
}

VolumeGrid VolumeGrid::parseVol(const std::string &bytes, const std::string &filename) {
    if (bytes.size() < kVolHeaderBytes || bytes.compare(0, 3, "VOL") != 0)
        throw NoriException(".vol file '{}' is truncated or not a .vol file (its 48-byte header "
                            "is missing)",
                            filename);
    if (bytes[3] != 3)
        throw NoriException(".vol file '{}' has version {}; only version 3 is read", filename,
                            int(bytes[3]));
    const auto encoding = readScalar<int32_t>(bytes, 4);
    if (encoding != 1)
        throw NoriException(".vol file '{}' has encoding {}; only 1 (float32) is read", filename,
                            encoding);
    const Vector3i resolution(readScalar<int32_t>(bytes, 8), readScalar<int32_t>(bytes, 12),
                              readScalar<int32_t>(bytes, 16));
    const auto channels = readScalar<int32_t>(bytes, 20);
    if (!(resolution.minCoeff() > 0))
        throw NoriException(".vol file '{}' has a resolution of {}x{}x{}", filename, resolution.x(),
                            resolution.y(), resolution.z());
    if (channels != 1 && channels != 3)
        throw NoriException(".vol file '{}' has {} channels; a medium needs 1 (density) or 3 "
                            "(albedo)",
                            filename, channels);
    const uint64_t count = uint64_t(resolution.x()) * uint64_t(resolution.y()) *
                           uint64_t(resolution.z()) * uint64_t(channels);
    if (count > kMaxValues)
        throw NoriException(".vol file '{}' claims {} values, more than the {} a grid may hold",
                            filename, count, kMaxValues);
    const uint64_t payload = bytes.size() - kVolHeaderBytes;
    if (payload != count * sizeof(float))
        throw NoriException(".vol file '{}' has {} bytes of data; {}x{}x{} voxels of {} channels "
                            "need {} ({})",
                            filename, payload, resolution.x(), resolution.y(), resolution.z(),
                            channels, count * sizeof(float),
                            payload < count * sizeof(float) ? "truncated" : "trailing bytes");
    Point3f lower, upper;
    for (int axis = 0; axis < 3; ++axis) {
        lower[axis] = readScalar<float>(bytes, 24 + 4 * axis);
        upper[axis] = readScalar<float>(bytes, 36 + 4 * axis);
    }
    if (!lower.allFinite() || !upper.allFinite() || !(upper.array() > lower.array()).all())
        throw NoriException(".vol file '{}' has an empty or invalid bounding box [{}, {}, {}] - "
                            "[{}, {}, {}]",
                            filename, lower.x(), lower.y(), lower.z(), upper.x(), upper.y(),
                            upper.z());
    std::vector<float> values(count);
    std::memcpy(values.data(), bytes.data() + kVolHeaderBytes, count * sizeof(float));
    Eigen::Matrix4f unitToObject = Eigen::Matrix4f::Identity();
    for (int axis = 0; axis < 3; ++axis) {
        unitToObject(axis, axis) = upper[axis] - lower[axis];
        unitToObject(axis, 3) = lower[axis];
    }
    return VolumeGrid(resolution, channels, std::move(values), Transform(unitToObject), filename);
}

void VolumeGrid::writeVol(const std::string &filename) const {
    const Eigen::Matrix4f &m = m_unitToObject.getMatrix();
    if (!m.topLeftCorner<3, 3>().isDiagonal())
        throw NoriException("grid '{}' is not axis-aligned and cannot be written as .vol", m_name);
    std::string bytes = "VOL";
    bytes += char(3);
    auto append = [&](auto value) {
        bytes.append(reinterpret_cast<const char *>(&value), sizeof(value));
    };
    append(int32_t(1));
    for (int axis = 0; axis < 3; ++axis)
        append(int32_t(m_resolution[axis]));
    append(int32_t(m_channels));
    for (int axis = 0; axis < 3; ++axis)
        append(m(axis, 3));
    for (int axis = 0; axis < 3; ++axis)
        append(m(axis, 3) + m(axis, axis));
    bytes.append(reinterpret_cast<const char *>(m_values.data()), m_values.size() * sizeof(float));
    writeBinaryFile(filename, bytes, ".vol file");
}

void VolumeGrid::writeNanoVDB(const std::string &filename, const std::string &gridName) const {
    const Eigen::Matrix4f &m = m_unitToObject.getMatrix();
    const Vector3f voxelSize = m.diagonal().head<3>().cwiseQuotient(m_resolution.cast<float>());
    if (!m.topLeftCorner<3, 3>().isDiagonal() || !(voxelSize.array() == voxelSize.x()).all() ||
        !(voxelSize.x() > 0.0f))
        throw NoriException("grid '{}' does not have cubic, axis-aligned voxels and cannot be "
                            "written as NanoVDB",
                            m_name);
    // The centre of voxel (0, 0, 0) is index (0, 0, 0).
    const nanovdb::Vec3d origin(m(0, 3) + 0.5 * voxelSize.x(), m(1, 3) + 0.5 * voxelSize.x(),
                                m(2, 3) + 0.5 * voxelSize.x());
    const nanovdb::CoordBBox box(
        nanovdb::Coord(0),
        nanovdb::Coord(m_resolution.x() - 1, m_resolution.y() - 1, m_resolution.z() - 1));
    try {
        if (m_channels == 1) {
            nanovdb::GridBuilder<float> builder(0.0f, nanovdb::GridClass::FogVolume);
            builder.setChecksum(nanovdb::ChecksumMode::Full);
            builder([&](const nanovdb::Coord &ijk) { return voxel(ijk[0], ijk[1], ijk[2]); }, box);
            nanovdb::io::writeGrid(filename, builder.getHandle(voxelSize.x(), origin, gridName));
        } else {
            nanovdb::GridBuilder<nanovdb::Vec3f> builder(nanovdb::Vec3f(0.0f));
            builder.setChecksum(nanovdb::ChecksumMode::Full);
            builder(
                [&](const nanovdb::Coord &ijk) {
                    return nanovdb::Vec3f(voxel(ijk[0], ijk[1], ijk[2], 0),
                                          voxel(ijk[0], ijk[1], ijk[2], 1),
                                          voxel(ijk[0], ijk[1], ijk[2], 2));
                },
                box);
            nanovdb::io::writeGrid(filename, builder.getHandle(voxelSize.x(), origin, gridName));
        }
    } catch (const std::runtime_error &error) {
        throw NoriException("cannot write NanoVDB file '{}': {}", filename, error.what());
    }
}

void VolumeGrid::setLayout(VoxelLayout layout) {
    if (layout == VoxelLayout::Corners && m_resolution.minCoeff() < 2)
        throw NoriException("grid '{}' has {}x{}x{} values; values at lattice corners need at "
                            "least 2 along every axis",
                            m_name, m_resolution.x(), m_resolution.y(), m_resolution.z());
    m_layout = layout;
}

Vector3f VolumeGrid::latticeCoordinates(const Point3f &u) const {
    if (m_layout == VoxelLayout::Corners)
        return u.cwiseProduct((m_resolution - Vector3i::Ones()).cast<float>());
    return u.cwiseProduct(m_resolution.cast<float>()) - Vector3f::Constant(0.5f);
}

float VolumeGrid::lookup(const Point3f &u) const {
    if (!((u.array() >= 0.0f).all() && (u.array() <= 1.0f).all()))
        return 0.0f;
    // Trilinear interpolation between the eight nearest values, clamped at the faces.
    const Vector3f x = latticeCoordinates(u);
    const Vector3f lowerF(x.array().floor().matrix());
    const Vector3f f = x - lowerF;
    const Vector3i lower = lowerF.cast<int>();
    const Vector3i last = m_resolution - Vector3i::Ones();
    const Vector3i i0 = lower.cwiseMax(0).cwiseMin(last);
    const Vector3i i1 = (lower + Vector3i::Ones()).cwiseMax(0).cwiseMin(last);
    auto lerp = [](float a, float b, float t) { return a + (b - a) * t; };
    const float c00 = lerp(voxel(i0.x(), i0.y(), i0.z()), voxel(i1.x(), i0.y(), i0.z()), f.x());
    const float c10 = lerp(voxel(i0.x(), i1.y(), i0.z()), voxel(i1.x(), i1.y(), i0.z()), f.x());
    const float c01 = lerp(voxel(i0.x(), i0.y(), i1.z()), voxel(i1.x(), i0.y(), i1.z()), f.x());
    const float c11 = lerp(voxel(i0.x(), i1.y(), i1.z()), voxel(i1.x(), i1.y(), i1.z()), f.x());
    return lerp(lerp(c00, c10, f.y()), lerp(c01, c11, f.y()), f.z());
}

Color3f VolumeGrid::lookupColor(const Point3f &u) const {
    if (m_channels == 1)
        return Color3f(lookup(u));
    if (!((u.array() >= 0.0f).all() && (u.array() <= 1.0f).all()))
        return Color3f(0.0f);
    const Vector3f x = latticeCoordinates(u);
    const Vector3f lowerF(x.array().floor().matrix());
    const Vector3f f = x - lowerF;
    const Vector3i lower = lowerF.cast<int>();
    const Vector3i last = m_resolution - Vector3i::Ones();
    Color3f result(0.0f);
    for (int corner = 0; corner < 8; ++corner) {
        const Vector3i offset(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
        const Vector3i i = (lower + offset).cwiseMax(0).cwiseMin(last);
        float weight = 1.0f;
        for (int axis = 0; axis < 3; ++axis)
            weight *= offset[axis] ? f[axis] : 1.0f - f[axis];
        for (int c = 0; c < 3; ++c)
            result[c] += weight * voxel(i.x(), i.y(), i.z(), c);
    }
    return result;
}

float VolumeGrid::maximumOver(const Point3f &lower, const Point3f &upper) const {
    const Vector3i last = m_resolution - Vector3i::Ones();
    // A point at lattice coordinate x interpolates the values floor(x) and the next.
    const Vector3i first = latticeCoordinates(lower).array().floor().cast<int>().matrix();
    const Vector3i end =
        latticeCoordinates(upper).array().floor().cast<int>().matrix() + Vector3i::Ones();
    const Vector3i from = first.cwiseMax(0).cwiseMin(last), to = end.cwiseMax(0).cwiseMin(last);
    float result = 0.0f;
    for (int z = from.z(); z <= to.z(); ++z)
        for (int y = from.y(); y <= to.y(); ++y)
            for (int x = from.x(); x <= to.x(); ++x)
                result = std::max(result, voxel(x, y, z));
    return result;
}

MajorantGrid::MajorantGrid(const VolumeGrid &grid, int cells, float scale)
    : m_cells(cells), m_bounds(size_t(cells) * cells * cells) {
    const float size = 1.0f / float(cells);
    for (int z = 0; z < cells; ++z)
        for (int y = 0; y < cells; ++y)
            for (int x = 0; x < cells; ++x) {
                const Point3f lower = Point3f(float(x), float(y), float(z)) * size;
                const float bound =
                    scale * grid.maximumOver(lower, lower + Vector3f::Constant(size));
                m_bounds[(size_t(z) * cells + y) * cells + x] = bound;
                m_maximum = std::max(m_maximum, bound);
            }
}

MajorantIterator::MajorantIterator(float tMin, float tMax, float sigma)
    : m_tMin(tMin), m_tMax(tMax), m_sigma(sigma) {}

MajorantIterator::MajorantIterator(const MajorantGrid &grid, const Point3f &origin,
                                   const Vector3f &direction, float tMin, float tMax)
    : m_grid(&grid) {
    // Clip [tMin, tMax] to the unit cube (slab test).
    for (int axis = 0; axis < 3; ++axis) {
        if (direction[axis] == 0.0f) {
            if (origin[axis] < 0.0f || origin[axis] > 1.0f)
                return; // parallel to the slab and outside it: no segment
            continue;
        }
        float t0 = (0.0f - origin[axis]) / direction[axis];
        float t1 = (1.0f - origin[axis]) / direction[axis];
        if (t0 > t1)
            std::swap(t0, t1);
        tMin = std::max(tMin, t0);
        tMax = std::min(tMax, t1);
    }
    if (!(tMin < tMax))
        return;
    m_tMin = tMin;
    m_tMax = tMax;
    const int cells = grid.cells();
    const Point3f start = origin + tMin * direction;
    for (int axis = 0; axis < 3; ++axis) {
        m_cell[axis] = std::clamp(int(start[axis] * float(cells)), 0, cells - 1);
        if (direction[axis] == 0.0f) {
            m_nextCrossing[axis] = kInfinity;
            m_deltaT[axis] = kInfinity;
            m_step[axis] = 0;
            m_stop[axis] = -1;
        } else if (direction[axis] > 0.0f) {
            const float boundary = float(m_cell[axis] + 1) / float(cells);
            m_nextCrossing[axis] = tMin + (boundary - start[axis]) / direction[axis];
            m_deltaT[axis] = 1.0f / (float(cells) * direction[axis]);
            m_step[axis] = 1;
            m_stop[axis] = cells;
        } else {
            const float boundary = float(m_cell[axis]) / float(cells);
            m_nextCrossing[axis] = tMin + (boundary - start[axis]) / direction[axis];
            m_deltaT[axis] = -1.0f / (float(cells) * direction[axis]);
            m_step[axis] = -1;
            m_stop[axis] = -1;
        }
    }
}

bool MajorantIterator::next(MajorantSegment &segment) {
    if (!(m_tMin < m_tMax))
        return false;
    if (!m_grid) {
        segment = {m_tMin, m_tMax, m_sigma};
        m_tMin = m_tMax;
        return true;
    }
    int axis;
    m_nextCrossing.minCoeff(&axis);
    const float tEnd = std::min(m_tMax, m_nextCrossing[axis]);
    segment = {m_tMin, tEnd, m_grid->cell(m_cell.x(), m_cell.y(), m_cell.z())};
    m_tMin = tEnd;
    m_cell[axis] += m_step[axis];
    m_nextCrossing[axis] += m_deltaT[axis];
    if (m_cell[axis] == m_stop[axis])
        m_tMin = m_tMax; // left the grid
    return true;
}

} // namespace nori
