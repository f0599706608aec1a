// A system of spherical lens interfaces and aperture stops, traced exactly (Kolb et al.
// 1995, "A realistic camera model for computer graphics"; pbrt-v3 §6.4), and its exit
// pupil. Camera space, in metres: the film is the plane z = 0, the lens's axis is +z, its
// rear vertex at z = rearZ() > 0, the scene beyond its front. The optics run in double:
// the thick-lens fit subtracts nearly equal heights of paraxial rays.
#pragma once

#include <nori/lensfile.h>

#include <Eigen/Core>

#include <cmath>

#include <string>
#include <vector>

namespace nori {

struct LensRay {
    Eigen::Vector3d o, d;
    Eigen::Vector3d at(double t) const { return o + t * d; }
};

class LensSystem {
public:
    /// The rows of a prescription (millimetres) in metres. `apertureDiameter` (mm) sets the
    /// first stop's diameter; 0 keeps the file's; more than the file's is an error (the
    /// barrel allows no wider iris). `fileName` names the lens in errors.
    LensSystem(const std::vector<LensInterfaceRow> &rows, double apertureDiameter,
               const std::string &fileName);

    /// Traces a ray from the film side (o at z < rearZ(), d.z > 0) through every interface
    /// to the scene; false when an aperture clips it or it is totally reflected. The ray
    /// out starts on the front interface; its direction is normalised.
    bool traceFromFilm(const LensRay &in, LensRay *out) const;
    /// The same from the scene side toward the film (d.z < 0).
    bool traceFromScene(const LensRay &in, LensRay *out) const;

    /// The paraxial cardinal points (pbrt-v3 §6.4.3; Hecht, Optics §6.1): principal planes
    /// and focal points as z, from rays parallel to the axis at a small height.
    struct CardinalPoints {
        double frontPrincipalZ, frontFocalZ; ///< of rays entering from the film side
        double rearPrincipalZ, rearFocalZ;   ///< of rays entering from the scene
        /// Effective focal length: from the rear principal plane to the rear focal point.
        double effectiveFocalLength() const { return rearPrincipalZ - rearFocalZ; }
    };
    CardinalPoints cardinalPoints() const;

    /// Moves the whole lens along its axis so that points `distance` metres in front of
    /// the film are imaged on it, by the thick-lens equation 1/s + 1/s' = 1/f measured
    /// from the principal planes (pbrt-v3 §6.4.4). Throws, naming the nearest distance it
    /// can focus at, when `distance` is closer than that.
    void focusAt(double distance);
    /// The nearest focus distance (metres from the film): object and image at least 4f
    /// apart plus the gap between the principal planes, and the rear element in front of
    /// the film.
    double nearestFocusDistance() const;

    double rearZ() const { return m_interfaces.back().thickness; }
    double frontZ() const;
    double rearApertureRadius() const { return m_interfaces.back().apertureRadius; }
    const std::string &fileName() const { return m_fileName; }

private:
    struct Interface {
        double curvatureRadius; ///< 0 for a stop
        double thickness;       ///< to the next interface toward the film
        double eta;             ///< of the medium on the film side
        double apertureRadius;
    };
    /// Intersects interface `index`, whose vertex lies at `vertexZ`, and refracts the ray
    /// through it (either way). False when the ray misses it, is clipped or totally
    /// reflected.
    bool crossInterface(size_t index, double vertexZ, LensRay &ray) const;
    /// The smallest z of the rear interface's surface (its vertex or its rim).
    double rearSurfaceMinZ() const;

    std::vector<Interface> m_interfaces; ///< front to rear, metres
    std::string m_fileName;
};

/// The exit pupil, the part of the rear element through which light from a film point
/// reaches the scene, bounded over the film radius (pbrt-v3 §6.4.5, which tabulates
/// boxes): sampling only there wastes few rays off axis, where vignetting blocks most of
/// the rear element. Here each radius gets an ellipse, fitted around the rays found to
/// pass and padded by their spacing: exact for the round pupil on the axis, and about a
/// third of a box's waste for the cat's-eye pupils off it.
class ExitPupil {
public:
    /// Tabulates `intervals` radii in [0, filmRadius], each from a coarse pass of
    /// samplesPerInterval / 4 rays and a fine one of `samplesPerInterval` rays inside
    /// what the first found; in parallel and deterministic.
    ExitPupil(const LensSystem &lens, double filmRadius, int intervals = 64,
              int samplesPerInterval = 1 << 13);

    /// An ellipse on the rear plane, for a film point on the +x axis; empty (area 0)
    /// where no light passes.
    struct Region {
        Eigen::Vector2d center = Eigen::Vector2d::Zero(), semiAxes = Eigen::Vector2d::Zero();
        double area() const;
        bool contains(const Eigen::Vector2d &p) const;
    };
    /// The point on the rear plane z = lens.rearZ() for `filmPoint` and the uniform
    /// sample `u`, drawn uniformly from the region of its radius (rotated to its angle);
    /// `regionArea` receives the region's area (the inverse of the density), 0 where no
    /// light passes.
    Eigen::Vector3d sample(const Eigen::Vector2d &filmPoint, const Eigen::Vector2d &u,
                           double *regionArea) const;
    /// The region used at film radius r.
    const Region &regionAt(double filmRadius) const;

private:
    std::vector<Region> m_regions;
    double m_filmRadius, m_rearZ;
};

/// The width and height (metres) of a film of diagonal `diagonal` (metres) whose image
/// has `width` × `height` pixels.
inline Eigen::Vector2d filmExtent(double diagonal, int width, int height) {
    const double aspect = double(height) / width;
    const double filmWidth = diagonal / std::sqrt(1.0 + aspect * aspect);
    return Eigen::Vector2d(filmWidth, aspect * filmWidth);
}

/// How many rays from the film toward the rear element the lens blocks, over `samples`
/// film points spread evenly (Halton) over a film of `filmSize` (metres, centred): rays
/// toward the exit pupil's regions, or with `pupil` null toward the whole rear element
/// (a disk), as a camera without the tabulation would trace them.
struct RayLoss {
    double blocked; ///< of the rays traced, the fraction the lens blocks
    double unlit;   ///< of the film points, the fraction with an empty pupil (no ray traced)
};
RayLoss measureRayLoss(const LensSystem &lens, const ExitPupil *pupil,
                       const Eigen::Vector2d &filmSize, int samples);

} // namespace nori
