// Bidirectional path tracing (Veach 1997, ch. 10; PBR 3rd ed. §16.3, whose vertex
// bookkeeping this follows): a subpath from the camera and one from a light, and every
// way (s, t) of joining s vertices of the light subpath to t of the camera subpath into a
// whole path, each weighted by multiple importance sampling. The bdpt integrator
// (plugins/builtin/integrators/bdpt.cpp) is built from this; the tests reach the pieces.
#pragma once

#include <nori/color.h>
#include <nori/integrator.h>
#include <nori/pathtracing.h>
#include <nori/shape.h>

#include <functional>
#include <vector>

namespace nori {

class Emitter;
class Sampler;
class Scene;

/// A vertex of a light or camera subpath. Densities are per unit area at the vertex (per
/// unit solid angle for a vertex at infinity), so that the probability density of a
/// whole path under any strategy is a product of them (Veach 1997, §10.2).
struct PathVertex {
    enum class Kind { Camera, Light, Surface };
    Kind kind = Kind::Surface;
    Point3f p = Point3f(0.0f, 0.0f, 0.0f); ///< position (on the disk, for light at infinity)
    /// The geometric normal; zero where there is no surface (a point light, the lens).
    Normal3f n = Normal3f(0.0f, 0.0f, 0.0f);
    Intersection its;                 ///< surfaces: the hit, with its BSDF and shading frame
    const Emitter *emitter = nullptr; ///< light vertices, and surfaces that emit
    /// Light at infinity: the unit direction the light travels (into the scene).
    Vector3f travel = Vector3f::Zero();
    /// The path's weight up to this vertex, f/p of its vertices before it: importance for
    /// camera subpaths, flux for light subpaths (Veach 1997, §5.2), surfaces excluded.
    Color3f throughput = Color3f(0.0f);
    /// Light a camera subpath found here: an emitting surface or light at infinity.
    Color3f emitted = Color3f(0.0f);
    float pdfForward = 0.0f; ///< density of this vertex as its own subpath sampled it
    float pdfReverse = 0.0f; ///< density of it as the other subpath would sample it
    /// A light vertex x₀: nextEventChoiceRatio of it and the vertex x₁ next to it on its
    /// path, kept so that each path's MIS weights evaluate the light tree once.
    float nextEventRatio = 1.0f;
    bool delta = false;      ///< left by a delta BSDF lobe: no strategy can join here
    bool atInfinity = false; ///< a light at infinity (an environment, a directional light)
    /// Drawn with the subpath for its s = 1 (camera) or t = 1 (light) connection, so that
    /// every vertex uses the same sampler dimensions in the same order.
    float emitterSample = 0.0f;
    Point2f connectionSample = Point2f(0.0f, 0.0f);

    bool onSurface() const { return !n.isZero(); }
    /// A light vertex that no ray can hit: a point or spot light, a directional light.
    bool isDeltaLight() const;
    /// Whether light leaves this vertex toward others as from a light (a light vertex or
    /// an emitting surface the camera subpath ended at, for s = 0).
    bool isLight() const { return kind == Kind::Light || emitter != nullptr; }
};

/// The unit direction from vertex `from` to vertex `to` (at infinity: its travel reversed).
Vector3f directionBetween(const PathVertex &from, const PathVertex &to);

/// Which heuristic weighs the strategies (Veach 1997, §9.2.2 and §9.2.4).
enum class MISHeuristic { Power, Balance };

/// One strategy's part of a sample: its contribution before the MIS weight, and where it
/// lands (t = 1 strategies anywhere on the film: a splat).
struct StrategySample {
    int s = 0, t = 0;
    Color3f unweighted = Color3f(0.0f);
    float weight = 0.0f;
    bool splat = false;
    Point2f position = Point2f(0.0f, 0.0f);
    /// s = 1: the light next-event estimation chose and the probability it chose it with.
    const Emitter *light = nullptr;
    float lightPmf = 0.0f;
};

/// The bidirectional estimator for one camera ray: subpaths, connections, MIS weights.
class BidirectionalPaths {
public:
    BidirectionalPaths(PathDepth depth, MISHeuristic heuristic)
        : m_depth(depth), m_heuristic(heuristic) {}

    /// Checks that the scene can be rendered: a camera that connect() supports, no media,
    /// lights that emit photons. Throws NoriException naming what is wrong; `plugin` names
    /// the integrator.
    static void validate(const Scene &scene, const std::string &plugin);

    /// Estimates the radiance along the camera ray: returns the contributions that land
    /// on its own pixel and appends those of t = 1 to `splats`. `visit`, if set, sees
    /// every strategy (the strategies debug view).
    Color3f estimate(const Scene &scene, Sampler &sampler, const Ray3f &ray,
                     std::vector<Splat> &splats,
                     const std::function<void(const StrategySample &)> &visit = {}) const;

    /// The camera subpath: vertex 0 on the lens (ray.o), then what the ray finds.
    void traceCameraSubpath(const Scene &scene, Sampler &sampler, const Ray3f &ray,
                            std::vector<PathVertex> &path) const;
    /// The light subpath: vertex 0 on a light picked by power, then what its photon finds.
    void traceLightSubpath(const Scene &scene, Sampler &sampler,
                           std::vector<PathVertex> &path) const;

    /// Joins the first s vertices of `light` and t of `camera`: the contribution without
    /// its MIS weight. For s = 1 and t = 1, `sampled` receives the new light or camera
    /// vertex; for t = 1, `link` the camera connection (and result.position where it lands).
    StrategySample connect(const Scene &scene, const std::vector<PathVertex> &light, int s,
                           const std::vector<PathVertex> &camera, int t, PathVertex &sampled,
                           CameraLink &link) const;
    /// The MIS weight of strategy (s, t) for the path it sampled, by the recursive ratios
    /// of Veach 1997, §10.2.1 (PBR 3rd ed. §16.3.4): every other strategy's density
    /// relative to this one's, from each vertex's forward and reverse densities, with the
    /// few that the connection changes computed anew. `sampled` and `link` are connect()'s.
    float misWeight(const Scene &scene, const std::vector<PathVertex> &light, int s,
                    const std::vector<PathVertex> &camera, int t, const PathVertex &sampled,
                    const CameraLink &link) const;

    /// Whether strategy (s, t) makes a path the depth limit allows.
    bool allowed(int s, int t) const;

    /// The density (at `next`) with which vertex `from` samples `next`, having been
    /// reached from `previous` (nullptr at a subpath's start): a BSDF, the camera, or a
    /// light emitting.
    static float pdfToward(const Scene &scene, const PathVertex &from, const PathVertex *previous,
                           const PathVertex &next);
    /// The density at `next` of a delta lobe at `from` sampling it, without the lobe's
    /// Dirac factor: a unit density per projected solid angle, so the geometry term
    /// G(from, next) = |cos θ_from||cos θ_next|/d². Strategies that cross a delta vertex in
    /// either direction share its Dirac factor, so it cancels from their weights, and the
    /// geometry terms of its two edges stay (Veach 1997, §10.3.5: densities per projected
    /// solid angle). Dropping them too, as PBR 3rd ed. §16.3.4 does, weighs caustics seen
    /// through glass towards the camera subpath that hits the light by chance.
    static float pdfThroughDelta(const PathVertex &from, const PathVertex &next);
    /// The density with which a light subpath starts at the light vertex `light`, emitting
    /// toward `next`: the light's pmf times its position density (for light at infinity,
    /// the density of the direction, summed over the lights at infinity).
    static float pdfLightOrigin(const Scene &scene, const PathVertex &light,
                                const PathVertex &next);
    /// How much likelier next-event estimation (s = 1) at the surface vertex `receiver`
    /// is to choose the light of the light vertex `light` than a light subpath is: the
    /// scene's light sampler's pmf there (the light tree's) over the pmf by power, summed
    /// over the lights at infinity as pdfLightOrigin sums them. 1 where `receiver` is no
    /// surface. Strategy s = 1's density of a path is pdfLightOrigin's times this.
    static float nextEventChoiceRatio(const Scene &scene, const PathVertex &light,
                                      const PathVertex &receiver);
    /// The density at `next` of light leaving the light vertex `light` toward it.
    static float pdfLight(const Scene &scene, const PathVertex &light, const PathVertex &next);

    const PathDepth &depth() const { return m_depth; }
    MISHeuristic heuristic() const { return m_heuristic; }

private:
    /// Extends `path` from its last vertex along `ray` (Veach's random walk, PBR 3rd ed.
    /// §16.3.2): surfaces found, densities both ways, the throughput updated by BSDF
    /// samples (for radiance on camera subpaths; adjoint, for flux, on light subpaths).
    void randomWalk(const Scene &scene, Sampler &sampler, Ray3f ray, const Color3f &throughput,
                    bool radiance, std::vector<PathVertex> &path) const;

    PathDepth m_depth;
    MISHeuristic m_heuristic;
};

} // namespace nori
