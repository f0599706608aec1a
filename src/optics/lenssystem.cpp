#include <nori/common.h>
#include <nori/fresnel.h>
#include <nori/lenssystem.h>
#include <nori/lowdiscrepancy.h>
#include <nori/parallel.h>
#include <nori/warp.h>

#include <algorithm>
#include <cmath>

namespace nori {

namespace {

constexpr double kMillimetre = 1e-3;

} // namespace

LensSystem::LensSystem(const std::vector<LensInterfaceRow> &rows, double apertureDiameter,
                       const std::string &fileName)
    : m_fileName(fileName) {
    bool irisSet = false;
    for (const LensInterfaceRow &row : rows) {
        Interface surface{row.curvatureRadius * kMillimetre, row.thickness * kMillimetre, row.eta,
                          0.5 * row.apertureDiameter * kMillimetre};
        if (row.curvatureRadius == 0.0 && !irisSet && apertureDiameter > 0.0) {
            // The file's own diameter, read as a float from the XML, passes.
            if (apertureDiameter > row.apertureDiameter * (1.0 + 1e-6))
                throw NoriException("'apertureDiameter' {:g} mm is wider than the aperture "
                                    "stop of {} (line {}), which opens to {:g} mm",
                                    float(apertureDiameter), fileName, row.line,
                                    row.apertureDiameter);
            surface.apertureRadius =
                0.5 * std::min(apertureDiameter, row.apertureDiameter) * kMillimetre;
        }
        irisSet = irisSet || row.curvatureRadius == 0.0;
        m_interfaces.push_back(surface);
    }
    if (apertureDiameter > 0.0 && !irisSet)
        throw NoriException("'apertureDiameter' is given, but {} has no aperture stop (a row "
                            "of radius 0) to set",
                            fileName);
}

double LensSystem::frontZ() const {
    double z = 0.0;
    for (const Interface &surface : m_interfaces)
        z += surface.thickness;
    return z;
}

bool LensSystem::crossInterface(size_t index, double vertexZ, LensRay &ray) const {
    const Interface &surface = m_interfaces[index];
    const bool isStop = surface.curvatureRadius == 0.0;
    double t;
    Eigen::Vector3d center(0.0, 0.0, vertexZ - surface.curvatureRadius);
    if (isStop) {
        t = (vertexZ - ray.o.z()) / ray.d.z();
    } else {
        // |o + t d − c|² = R²; of the two roots, the one on the cap around the vertex:
        // the nearer one when the ray meets the sphere from the vertex's side.
        const Eigen::Vector3d oc = ray.o - center;
        const double a = ray.d.squaredNorm(), b = oc.dot(ray.d);
        const double c = oc.squaredNorm() - surface.curvatureRadius * surface.curvatureRadius;
        const double discriminant = b * b - a * c;
        if (discriminant < 0.0)
            return false;
        const double root = std::sqrt(discriminant);
        const bool nearer = (ray.d.z() > 0.0) == (surface.curvatureRadius < 0.0);
        t = nearer ? (-b - root) / a : (-b + root) / a;
    }
    if (!(t > 0.0) || !std::isfinite(t))
        return false;
    const Eigen::Vector3d hit = ray.at(t);
    if (hit.head<2>().squaredNorm() > surface.apertureRadius * surface.apertureRadius)
        return false;
    ray.o = hit;
    if (isStop)
        return true;
    // The normal on the incoming side; refract() wants the direction pointing away.
    Eigen::Vector3d normal = (hit - center).normalized();
    const Eigen::Vector3d away = -ray.d.normalized();
    if (normal.dot(away) < 0.0)
        normal = -normal;
    // Row i's index is the medium behind (film side) the interface; the one in front is
    // row i − 1's, or air.
    const double etaFront = index > 0 ? m_interfaces[index - 1].eta : 1.0;
    const bool towardScene = ray.d.z() > 0.0;
    const double etaBefore = towardScene ? surface.eta : etaFront;
    const double etaAfter = towardScene ? etaFront : surface.eta;
    return refract(away, normal, etaAfter / etaBefore, ray.d);
}

bool LensSystem::traceFromFilm(const LensRay &in, LensRay *out) const {
    LensRay ray = in;
    double vertexZ = 0.0;
    for (size_t i = m_interfaces.size(); i-- > 0;) {
        vertexZ += m_interfaces[i].thickness;
        if (!crossInterface(i, vertexZ, ray))
            return false;
    }
    if (out)
        *out = {ray.o, ray.d.normalized()};
    return true;
}

bool LensSystem::traceFromScene(const LensRay &in, LensRay *out) const {
    LensRay ray = in;
    double vertexZ = frontZ();
    for (size_t i = 0; i < m_interfaces.size(); ++i) {
        if (!crossInterface(i, vertexZ, ray))
            return false;
        vertexZ -= m_interfaces[i].thickness;
    }
    if (out)
        *out = {ray.o, ray.d.normalized()};
    return true;
}

double LensSystem::rearSurfaceMinZ() const {
    // A rear surface with its centre toward the film (radius > 0) bulges toward the scene,
    // so its rim, sag R − sqrt(R² − a²) behind the vertex, is nearest the film.
    const Interface &rear = m_interfaces.back();
    const double radius = rear.curvatureRadius, a = rear.apertureRadius;
    const double sag = radius > 0.0 ? radius - std::sqrt(radius * radius - a * a) : 0.0;
    return rearZ() - sag;
}

LensSystem::CardinalPoints LensSystem::cardinalPoints() const {
    // Paraxial: a height far inside every aperture, where sin θ ≈ θ holds to ~1e-6.
    double smallestAperture = kInfinity;
    for (const Interface &surface : m_interfaces)
        smallestAperture = std::min(smallestAperture, surface.apertureRadius);
    const double height = 1e-3 * smallestAperture;

    // The ray out of the lens for a ray in parallel to the axis at `height`: it crosses
    // the axis at the focal point, and the height it came in at on the principal plane.
    auto cardinal = [&](const LensRay &in, bool fromScene, double &principalZ, double &focalZ) {
        LensRay out;
        const bool passed = fromScene ? traceFromScene(in, &out) : traceFromFilm(in, &out);
        if (!passed)
            throw NoriException("{}: a paraxial ray does not pass through the lens (is an "
                                "aperture almost closed?)",
                                m_fileName);
        if (std::abs(out.d.x()) < 1e-12)
            throw NoriException("{}: the lens is afocal (parallel rays leave it parallel), so "
                                "it cannot form an image on the film",
                                m_fileName);
        focalZ = out.at(-out.o.x() / out.d.x()).z();
        principalZ = out.at((height - out.o.x()) / out.d.x()).z();
    };
    CardinalPoints points{};
    const double frontStart = frontZ() + m_interfaces.front().apertureRadius + 1e-3;
    cardinal({Eigen::Vector3d(height, 0.0, frontStart), Eigen::Vector3d(0.0, 0.0, -1.0)}, true,
             points.rearPrincipalZ, points.rearFocalZ);
    const double rearStart = rearSurfaceMinZ() - 1e-3;
    cardinal({Eigen::Vector3d(height, 0.0, rearStart), Eigen::Vector3d(0.0, 0.0, 1.0)}, false,
             points.frontPrincipalZ, points.frontFocalZ);
    return points;
}

double LensSystem::nearestFocusDistance() const {
    const CardinalPoints points = cardinalPoints();
    // Object and image distances s, s' from the principal planes with 1/s + 1/s' = 1/f
    // have a real solution only when s + s' ≥ 4f.
    return 4.0 * points.effectiveFocalLength() + points.frontPrincipalZ - points.rearPrincipalZ;
}

void LensSystem::focusAt(double distance) {
    const CardinalPoints points = cardinalPoints();
    const double f = points.effectiveFocalLength();
    if (!(f > 0.0))
        throw NoriException("{}: the lens diverges light (effective focal length {} mm), so "
                            "it cannot form an image on the film",
                            m_fileName, float(f / kMillimetre));
    // Moving the lens by δ toward the scene: s = distance − z_P − δ, s' = z_P' + δ, and
    // 1/s + 1/s' = 1/f becomes δ² − (a − b)δ + (a + b)f − ab = 0 with a = distance − z_P,
    // b = z_P'. Of its roots, the one that tends to f − z_P' (focus at infinity).
    const double a = distance - points.frontPrincipalZ, b = points.rearPrincipalZ;
    const double discriminant = (a + b) * (a + b - 4.0 * f);
    if (!(a + b > 0.0) || !(discriminant >= 0.0))
        throw NoriException("{}: 'focusDistance' {:g} is closer than this lens can focus: the "
                            "nearest is {:.4g} (four focal lengths of {:.2f} mm plus the "
                            "principal planes' gap, from the film)",
                            m_fileName, float(distance), nearestFocusDistance(), f / kMillimetre);
    const double delta = 0.5 * ((a - b) - std::sqrt(discriminant));
    m_interfaces.back().thickness += delta;
    if (!(rearSurfaceMinZ() > 0.0))
        throw NoriException("{}: focused at {:g}, the rear element would reach behind the film "
                            "(its back focal distance is too short)",
                            m_fileName, float(distance));
}

namespace {

/// An axis-aligned box of points on the rear plane.
struct Box {
    Eigen::Vector2d min = Eigen::Vector2d::Constant(kInfinity);
    Eigen::Vector2d max = Eigen::Vector2d::Constant(-kInfinity);
    bool isEmpty() const { return (min.array() > max.array()).any(); }
    void expandBy(const Eigen::Vector2d &p) {
        min = min.cwiseMin(p);
        max = max.cwiseMax(p);
    }
};

} // namespace

ExitPupil::ExitPupil(const LensSystem &lens, double filmRadius, int intervals,
                     int samplesPerInterval)
    : m_regions(intervals), m_filmRadius(filmRadius), m_rearZ(lens.rearZ()) {
    // Candidate points on the rear plane: first a square 1.5 times the rear element's
    // radius (the pupil can look wider than the element from far off axis), with a
    // quarter of the rays; then that pass's box padded by two of its spacings, searched
    // again at a finer one. The film points lie on +x, where the pupil is symmetric about
    // y = 0: only y ≥ 0 is traced, each point standing for its mirror image too.
    const double extent = 1.5 * lens.rearApertureRadius();
    const int finePasses = std::max(1, samplesPerInterval);
    const int coarsePasses = std::max(1, samplesPerInterval / 4);
    parallelFor(0, intervals, [&](int interval) {
        const double r0 = filmRadius * interval / intervals;
        const double r1 = filmRadius * (interval + 1) / intervals;
        // `count` rays over the upper half of `region`: the box of the passing points and
        // their mirror images, and (if `passing`) the points; `spacing` receives the
        // distance between neighbouring candidates, about sqrt(area / count).
        auto search = [&](const Box &region, int count, double &spacing,
                          std::vector<Eigen::Vector2d> *passing) {
            Box half = region;
            half.min.y() = std::max(0.0, region.min.y());
            spacing = std::sqrt((half.max - half.min).prod() / count);
            Box found;
            for (int i = 0; i < count; ++i) {
                const Eigen::Vector3d film(r0 + (r1 - r0) * (i + 0.5) / count, 0.0, 0.0);
                const Eigen::Vector2d u(radicalInverse(2, i), radicalInverse(3, i));
                const Eigen::Vector2d rear = half.min + u.cwiseProduct(half.max - half.min);
                const Eigen::Vector3d target(rear.x(), rear.y(), m_rearZ);
                if (lens.traceFromFilm({film, (target - film).normalized()}, nullptr)) {
                    found.expandBy(rear);
                    found.expandBy(Eigen::Vector2d(rear.x(), -rear.y()));
                    if (passing)
                        passing->push_back(rear);
                }
            }
            return found;
        };
        Box square;
        square.min = Eigen::Vector2d::Constant(-extent);
        square.max = Eigen::Vector2d::Constant(extent);
        double coarseSpacing = 0.0, fineSpacing = 0.0;
        Box coarse = search(square, coarsePasses, coarseSpacing, nullptr);
        if (coarse.isEmpty())
            return; // no light reaches the film here: an empty region
        coarse.min = (coarse.min.array() - 2.0 * coarseSpacing).max(-extent);
        coarse.max = (coarse.max.array() + 2.0 * coarseSpacing).min(extent);
        std::vector<Eigen::Vector2d> points;
        const Box fine = search(coarse, finePasses, fineSpacing, &points);
        if (fine.isEmpty())
            return;
        // The smallest ellipse with the box's centre and aspect holding every passing
        // point (and so their mirror images), padded by 1.5 fine spacings: between
        // low-discrepancy points the pupil's edge lies about one spacing beyond the last
        // one inside.
        const Eigen::Vector2d center(0.5 * (fine.min.x() + fine.max.x()), 0.0);
        const Eigen::Vector2d halfExtent = (0.5 * (fine.max - fine.min)).cwiseMax(1e-9 * extent);
        double scale = 0.0;
        for (const Eigen::Vector2d &p : points)
            scale = std::max(scale, (p - center).cwiseQuotient(halfExtent).norm());
        m_regions[interval].center = center;
        m_regions[interval].semiAxes = scale * halfExtent.array() + 1.5 * fineSpacing;
    });
}

double ExitPupil::Region::area() const {
    return kPiDouble * semiAxes.x() * semiAxes.y();
}

bool ExitPupil::Region::contains(const Eigen::Vector2d &p) const {
    return area() > 0.0 && (p - center).cwiseQuotient(semiAxes).squaredNorm() <= 1.0;
}

const ExitPupil::Region &ExitPupil::regionAt(double filmRadius) const {
    const int count = static_cast<int>(m_regions.size());
    const int index = static_cast<int>(filmRadius / m_filmRadius * count);
    return m_regions[std::clamp(index, 0, count - 1)];
}

Eigen::Vector3d ExitPupil::sample(const Eigen::Vector2d &filmPoint, const Eigen::Vector2d &u,
                                  double *regionArea) const {
    const double radius = filmPoint.norm();
    const Region &region = regionAt(radius);
    *regionArea = region.area();
    // Uniform in the ellipse: the unit disk (concentric map) stretched by its semi-axes.
    const Point2f disk = Warp::squareToUniformDiskConcentric(Point2f(u.cast<float>()));
    const Eigen::Vector2d p =
        region.center + region.semiAxes.cwiseProduct(Eigen::Vector2d(disk.x(), disk.y()));
    // The regions were found on the +x axis; the lens is symmetric about its axis.
    const double cosPhi = radius > 0.0 ? filmPoint.x() / radius : 1.0;
    const double sinPhi = radius > 0.0 ? filmPoint.y() / radius : 0.0;
    return Eigen::Vector3d(cosPhi * p.x() - sinPhi * p.y(), sinPhi * p.x() + cosPhi * p.y(),
                           m_rearZ);
}

RayLoss measureRayLoss(const LensSystem &lens, const ExitPupil *pupil,
                       const Eigen::Vector2d &filmSize, int samples) {
    int traced = 0, blocked = 0, unlit = 0;
    for (int i = 0; i < samples; ++i) {
        const Eigen::Vector2d u(radicalInverse(2, i), radicalInverse(3, i));
        const Eigen::Vector2d v(radicalInverse(5, i), radicalInverse(7, i));
        const Eigen::Vector3d film((u.x() - 0.5) * filmSize.x(), (u.y() - 0.5) * filmSize.y(), 0.0);
        Eigen::Vector3d rear;
        if (pupil) {
            double area = 0.0;
            rear = pupil->sample(film.head<2>(), v, &area);
            if (area == 0.0) {
                ++unlit;
                continue;
            }
        } else {
            const Point2f disk = Warp::squareToUniformDisk(Point2f(v.cast<float>()));
            rear = Eigen::Vector3d(lens.rearApertureRadius() * disk.x(),
                                   lens.rearApertureRadius() * disk.y(), lens.rearZ());
        }
        ++traced;
        if (!lens.traceFromFilm({film, (rear - film).normalized()}, nullptr))
            ++blocked;
    }
    return {traced > 0 ? double(blocked) / traced : 0.0, double(unlit) / samples};
}

} // namespace nori
