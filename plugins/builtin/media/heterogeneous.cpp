/*
 * heterogeneous — a medium whose density varies in space, read from a voxel grid:
 * Mitsuba's binary .vol or a NanoVDB float grid, looked up trilinearly (PBR 4th ed.
 * §11.4.2-11.4.3). σt = scale · density is grey; the albedo may be coloured. Free
 * flights are sampled by delta tracking against a majorant grid of `majorantResolution`³
 * cells walked by a DDA, so sparse regions are crossed in few steps.
 *
 * Parameters:
 *   filename            string     (required)  the density grid (.vol or .nvdb), relative to the
 * scene gridName            string     ""          the NanoVDB grid to read (default: the first)
 *   scale               float      1           σt per unit of density
 *   albedo              color      0.75        single-scattering albedo σs/σt, in [0, 1]
 *   albedoFilename      string     ""          a grid of albedos (1 or 3 channels) instead
 *   toWorld             transform  identity    places the grid's object space in the world
 *   fileBounds          boolean    true        the grid spans the bounding box its file states
 *                                              (false: the unit cube, before toWorld)
 *   majorantResolution  integer    16          majorant cells per axis (1: one global bound)
 *   valuesAt            string     "centres"   where a grid's values hold: "centres" of its
 *                                              voxels (Mitsuba 3, pbrt-v4, OpenVDB) or the
 *                                              "corners" of its bounding box's lattice, value i
 *                                              at i/(n - 1) (Mitsuba 0.4-0.6's gridvolume)
 *
 * Children: a <phase>, the phase function (isotropic by default).
 *
 *   <medium type="heterogeneous"><string name="filename" value="scenes/media/cloud.vol"/>
 *       <float name="scale" value="8"/></medium>
 */
#include <nori/medium.h>
#include <nori/phase.h>

namespace nori {
namespace {

class HeterogeneousMedium : public Medium {
public:
    explicit HeterogeneousMedium(const PropertyList &props) {
        m_filename = props.getPath("filename");
        m_gridName = props.getString("gridName", "");
        m_scale = props.getFloat("scale", 1.0f);
        if (!(m_scale >= 0.0f) || !std::isfinite(m_scale))
            throw NoriException("heterogeneous: 'scale' must be finite and non-negative, got {}",
                                m_scale);
        m_albedoFilename = props.has("albedoFilename") ? props.getPath("albedoFilename") : "";
        if (!m_albedoFilename.empty() && props.has("albedo"))
            throw NoriException("heterogeneous: give 'albedo' or 'albedoFilename', not both");
        m_albedo = props.getColor("albedo", Color3f(0.75f));
        if (!m_albedo.allFinite() || (m_albedo < 0.0f).any() || (m_albedo > 1.0f).any())
            throw NoriException("heterogeneous: 'albedo' must lie in [0, 1], got {}",
                                m_albedo.toString());
        m_toWorld = props.getTransform("toWorld", Transform());
        m_majorantResolution = props.getInteger("majorantResolution", 16);
        if (m_majorantResolution < 1 || m_majorantResolution > 256)
            throw NoriException("heterogeneous: 'majorantResolution' must lie in [1, 256], got {}",
                                m_majorantResolution);

        const std::string valuesAt = props.getString("valuesAt", "centres");
        if (valuesAt != "centres" && valuesAt != "corners")
            throw NoriException("heterogeneous: 'valuesAt' is \"centres\" or \"corners\", got "
                                "\"{}\"",
                                valuesAt);
        const VoxelLayout layout =
            valuesAt == "corners" ? VoxelLayout::Corners : VoxelLayout::Centres;

        m_density = VolumeGrid::load(m_filename, m_gridName);
        m_density.setLayout(layout);
        if (m_density.channels() != 1)
            throw NoriException("heterogeneous: the density grid '{}' has {} channels; it needs 1",
                                m_filename, m_density.channels());
        const bool fileBounds = props.getBoolean("fileBounds", true);
        m_worldToUnit = (fileBounds ? m_toWorld * m_density.unitToObject() : m_toWorld).inverse();
        m_majorants = MajorantGrid(m_density, m_majorantResolution, m_scale);
        if (!m_albedoFilename.empty()) {
            m_albedoGrid = VolumeGrid::load(m_albedoFilename);
            m_albedoGrid.setLayout(layout);
            for (int z = 0; z < m_albedoGrid.resolution().z(); ++z)
                for (int y = 0; y < m_albedoGrid.resolution().y(); ++y)
                    for (int x = 0; x < m_albedoGrid.resolution().x(); ++x)
                        for (int c = 0; c < m_albedoGrid.channels(); ++c)
                            if (m_albedoGrid.voxel(x, y, z, c) > 1.0f)
                                throw NoriException("heterogeneous: the albedo grid '{}' holds {} "
                                                    "at voxel ({}, {}, {}); albedos lie in [0, 1]",
                                                    m_albedoFilename,
                                                    m_albedoGrid.voxel(x, y, z, c), x, y, z);
            m_worldToAlbedoUnit =
                (fileBounds ? m_toWorld * m_albedoGrid.unitToObject() : m_toWorld).inverse();
        }
    }

    MediumSample sampleFreeFlight(const Ray3f &ray, PCG32 &rng) const override {
        // Delta tracking (Woodcock et al. 1965; PBR 4th ed. §14.2.1): with σt grey, a
        // tentative collision is real with probability σt/σ̄ and the weight of a real
        // one, σs·T/(σt·T), is the albedo.
        MediumSample result;
        const bool passed = forEachTentativeCollision(ray, rng, [&](float t, float sigmaMajorant) {
            const Point3f p = ray(t);
            if (rng.nextFloat() * sigmaMajorant >= density(p) * m_scale)
                return true; // a null collision
            result = {true, t, p, albedo(p)};
            return false;
        });
        if (!passed)
            return result;
        result.t = ray.maxt;
        result.p = ray(ray.maxt);
        return result;
    }

    Color3f sigmaT(const Point3f &p) const override { return Color3f(density(p) * m_scale); }

    MajorantIterator majorants(const Ray3f &ray, float tMin, float tMax) const override {
        return MajorantIterator(m_majorants, m_worldToUnit * ray.o, m_worldToUnit * ray.d, tMin,
                                tMax);
    }

    std::string toString() const override {
        return fmt::format("HeterogeneousMedium[filename=\"{}\", {}x{}x{}, scale={}, albedo={}, "
                           "majorantResolution={}, phase={}]",
                           m_filename, m_density.resolution().x(), m_density.resolution().y(),
                           m_density.resolution().z(), m_scale,
                           m_albedoFilename.empty() ? m_albedo.toString()
                                                    : "\"" + m_albedoFilename + "\"",
                           m_majorantResolution, m_phase->toString());
    }

private:
    float density(const Point3f &p) const { return m_density.lookup(m_worldToUnit * p); }

    Color3f albedo(const Point3f &p) const {
        if (m_albedoFilename.empty())
            return m_albedo;
        return m_albedoGrid.lookupColor(m_worldToAlbedoUnit * p);
    }

    std::string m_filename, m_gridName, m_albedoFilename;
    float m_scale;
    Color3f m_albedo;
    Transform m_toWorld, m_worldToUnit, m_worldToAlbedoUnit;
    int m_majorantResolution;
    VolumeGrid m_density, m_albedoGrid;
    MajorantGrid m_majorants;
};

NORI_REGISTER_CLASS(HeterogeneousMedium, "heterogeneous");

} // namespace
} // namespace nori
