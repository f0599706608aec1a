// A dense voxel grid for heterogeneous media (density, albedo), read from Mitsuba's
// binary .vol format or from a NanoVDB file, and the coarse majorant grid that bounds it.
//
// Values sit at voxel centres by default (Mitsuba 3's, pbrt-v4's and OpenVDB's convention):
// along x, voxel i covers the unit coordinate interval [i/nx, (i+1)/nx] and its value holds
// at (i + 1/2)/nx. Mitsuba 0.4-0.6's gridvolume puts value i at the lattice point i/(nx - 1)
// instead (VoxelLayout::Corners). Lookups are trilinear between those points, clamped to the
// edge inside the unit cube, zero outside it.
#pragma once

#include <nori/color.h>
#include <nori/transform.h>

#include <string>
#include <vector>

namespace nori {

/// Where a grid's values hold in the unit cube (see the top of this file).
enum class VoxelLayout { Centres, Corners };

class VolumeGrid {
public:
    VolumeGrid() = default;
    /// `values` has resolution.prod() · channels entries, x fastest, then y, then z, the
    /// channels of a voxel together. `unitToObject` maps the unit cube onto the grid's
    /// extent in object space. Throws when a value is NaN, infinite or negative.
    VolumeGrid(const Vector3i &resolution, int channels, std::vector<float> values,
               const Transform &unitToObject, const std::string &name);

    /// Reads a grid file, recognised by its content: Mitsuba's .vol ("VOL" version 3,
    /// float32 data) or NanoVDB (a float or Vec3f grid, uncompressed; the first grid, or
    /// the one named `gridName`). Every malformed, truncated or unsupported file, and
    /// every NaN, infinite or negative value, is a NoriException naming the file.
    static VolumeGrid load(const std::string &filename, const std::string &gridName = "");
    /// The most voxels × channels a grid may hold (4 GiB of floats): a file claiming more
    /// is an error rather than an allocation that fails later.
    static constexpr uint64_t kMaxValues = uint64_t(1) << 30;

    /// load() for a file's bytes; `filename` is for messages. A sparse NanoVDB grid whose
    /// dense copy would exceed `maxValues` is an error (the fuzz target lowers it, since
    /// a few hundred bytes can describe a grid that fills the limit).
    static VolumeGrid parse(const std::string &bytes, const std::string &filename,
                            const std::string &gridName = "", uint64_t maxValues = kMaxValues);
    /// Parses the bytes of a Mitsuba .vol file; `filename` is for messages.
    static VolumeGrid parseVol(const std::string &bytes, const std::string &filename);

    /// Writes the grid as a Mitsuba .vol file (its object-space bounding box in the header;
    /// the grid must be axis-aligned in object space).
    void writeVol(const std::string &filename) const;
    /// Writes the grid as a NanoVDB file with one float (1 channel) or Vec3f (3 channels)
    /// grid named `gridName`; zero voxels stay inactive.
    void writeNanoVDB(const std::string &filename, const std::string &gridName) const;

    /// Places the values at voxel centres (the default) or at lattice corners; Corners
    /// needs at least two values along every axis.
    void setLayout(VoxelLayout layout);
    VoxelLayout layout() const { return m_layout; }

    /// The trilinear value at unit-cube coordinates u: channel 0, or all three channels
    /// (a one-channel grid gives grey).
    float lookup(const Point3f &u) const;
    Color3f lookupColor(const Point3f &u) const;

    /// The largest value (channel 0) any lookup returns in the box of unit coordinates
    /// [lower, upper]: the maximum over the voxels whose values the trilinear stencil of
    /// a point in the box can reach.
    float maximumOver(const Point3f &lower, const Point3f &upper) const;

    const Vector3i &resolution() const { return m_resolution; }
    int channels() const { return m_channels; }
    const Transform &unitToObject() const { return m_unitToObject; }
    /// The largest value of channel 0.
    float maximum() const { return m_maximum; }
    const std::string &name() const { return m_name; }
    /// The value of voxel (x, y, z), channel c.
    float voxel(int x, int y, int z, int c = 0) const {
        return m_values[((size_t(z) * m_resolution.y() + y) * m_resolution.x() + x) * m_channels +
                        c];
    }

private:
    /// Unit-cube coordinates as lattice coordinates: value (i, j, k) holds at (i, j, k).
    Vector3f latticeCoordinates(const Point3f &u) const;

    Vector3i m_resolution = Vector3i::Zero();
    VoxelLayout m_layout = VoxelLayout::Centres;
    int m_channels = 1;
    std::vector<float> m_values;
    Transform m_unitToObject;
    float m_maximum = 0.0f;
    std::string m_name; ///< the file (for messages)
};

/// A coarse grid of upper bounds of a medium's extinction over the unit cube, and the
/// ray segments it cuts a ray into (pbrt-v4 §11.4.3): delta and ratio tracking sample
/// each segment against its own bound, so thin regions are not stepped through at the
/// density of the thickest one.
class MajorantGrid {
public:
    MajorantGrid() = default;
    /// Bounds `grid` (channel 0, times `scale`) with `cells`³ cells.
    MajorantGrid(const VolumeGrid &grid, int cells, float scale);

    int cells() const { return m_cells; }
    float cell(int x, int y, int z) const {
        return m_bounds[(size_t(z) * m_cells + y) * m_cells + x];
    }
    float maximum() const { return m_maximum; }

private:
    int m_cells = 0;
    std::vector<float> m_bounds;
    float m_maximum = 0.0f;
};

/// One piece of a ray with a constant upper bound of the extinction along it.
struct MajorantSegment {
    float tMin, tMax;
    float sigmaMajorant;
};

/// Walks a ray through the cells of a MajorantGrid with a 3D DDA (Amanatides and Woo
/// 1987), cell by cell in order, or yields one segment with one bound (a homogeneous
/// medium). The ray is given in the grid's unit-cube space, with the parameter t of the
/// world ray (the direction is not normalised), so segments are in world t.
class MajorantIterator {
public:
    /// No segment at all.
    MajorantIterator() = default;
    /// A single segment [tMin, tMax] with bound `sigma`.
    MajorantIterator(float tMin, float tMax, float sigma);
    /// The cells of `grid` that the ray's [tMin, tMax] crosses (clipped to the unit cube).
    MajorantIterator(const MajorantGrid &grid, const Point3f &origin, const Vector3f &direction,
                     float tMin, float tMax);

    /// The next segment; false when the ray has left the grid or reached tMax.
    bool next(MajorantSegment &segment);

private:
    const MajorantGrid *m_grid = nullptr;
    float m_tMin = 0.0f, m_tMax = -1.0f, m_sigma = 0.0f;
    // DDA state: the current cell, the t at which each axis reaches its next cell
    // boundary, the t-step between boundaries, the cell step and the cell past the end.
    Vector3i m_cell = Vector3i::Zero(), m_step = Vector3i::Zero(), m_stop = Vector3i::Zero();
    Vector3f m_nextCrossing = Vector3f::Zero(), m_deltaT = Vector3f::Zero();
};

} // namespace nori
