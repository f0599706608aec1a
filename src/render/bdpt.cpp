#include <nori/bdpt.h>
#include <nori/bsdf.h>
#include <nori/camera.h>
#include <nori/emitter.h>
#include <nori/raydifferential.h>
#include <nori/sampler.h>
#include <nori/scene.h>

#include <limits>

namespace nori {

bool PathVertex::isDeltaLight() const {
    return kind == Kind::Light && emitter != nullptr && emitter->isDelta();
}

Vector3f directionBetween(const PathVertex &from, const PathVertex &to) {
    if (to.atInfinity)
        return -to.travel;
    if (from.atInfinity)
        return from.travel;
    return (to.p - from.p).normalized();
}

namespace {

/// A density per unit solid angle at `from` as a density per unit area at `next`:
/// |cos θ_next|/d² (PBR 3rd ed. §16.3.1, eq. 16.17). Light at infinity keeps it per solid
/// angle.
float toAreaDensity(float pdf, const PathVertex &from, const PathVertex &next) {
    if (next.atInfinity)
        return pdf;
    const Vector3f w = next.p - from.p;
    const float distanceSquared = w.squaredNorm();
    if (distanceSquared == 0.0f)
        return 0.0f;
    if (next.onSurface())
        pdf *= std::abs(next.n.dot(w)) / std::sqrt(distanceSquared);
    return pdf / distanceSquared;
}

/// Densities that are zero mark delta events; the ratios of the MIS weights skip them
/// (PBR 3rd ed. §16.3.4).
float remapZero(float pdf) {
    return pdf != 0.0f ? pdf : 1.0f;
}

/// The probability of choosing `emitter`: by power, as light subpaths start, or, given the
/// surface vertex `receiver`, as next-event estimation chooses a light for it (the scene's
/// light sampler: the light tree's importance there, by default).
float choiceProbability(const Scene &scene, const Emitter *emitter, const PathVertex *receiver) {
    return receiver ? scene.emitterPmf(receiver->p, receiver->its.shFrame.n, emitter)
                    : scene.emitterPmf(emitter);
}

/// The density of a light vertex `light` leaving along `travel`: its light chosen as
/// choiceProbability(receiver) says, times its position density.
float originDensity(const Scene &scene, const PathVertex &light, const Vector3f &travel,
                    const PathVertex *receiver = nullptr) {
    if (light.atInfinity) {
        // A direction at infinity could come from any light at infinity: their densities
        // add (PBR 3rd ed. §16.3.4, InfiniteLightDensity).
        EmitterQueryRecord lRec;
        lRec.wi = -travel;
        float density = 0.0f;
        for (const Emitter *emitter : scene.getInfiniteEmitters())
            density += choiceProbability(scene, emitter, receiver) * emitter->pdf(lRec);
        return density;
    }
    return choiceProbability(scene, light.emitter, receiver) *
           light.emitter->emissionDensity(light.p, light.n, travel).position;
}

/// The emitter whose emission densities a light vertex has: its own, or for a camera ray
/// that left the scene, any light at infinity (they share the scene's disk).
const Emitter &emitterOf(const Scene &scene, const PathVertex &light) {
    return light.emitter ? *light.emitter : *scene.getInfiniteEmitters().front();
}

} // namespace

bool BidirectionalPaths::allowed(int s, int t) const {
    const int events = s + t - 2;
    if (events < 0 || (s == 1 && t == 1))
        return false;
    return m_depth.maxDepth < 0 || events <= m_depth.maxDepth;
}

void BidirectionalPaths::validate(const Scene &scene, const std::string &plugin) {
    requireLightPathScene(scene, plugin, "bidirectional path tracing");
    // Lights whose plugin gives no emission densities say so by name (Emitter's default).
    for (const auto &emitter : scene.getEmitters())
        (void)emitter->emissionDensity(Point3f(0.0f, 0.0f, 0.0f), Normal3f(0.0f, 0.0f, 1.0f),
                                       Vector3f(0.0f, 0.0f, 1.0f));
}

float BidirectionalPaths::pdfLightOrigin(const Scene &scene, const PathVertex &light,
                                         const PathVertex &next) {
    return originDensity(scene, light, directionBetween(light, next));
}

float BidirectionalPaths::nextEventChoiceRatio(const Scene &scene, const PathVertex &light,
                                               const PathVertex &receiver) {
    if (receiver.kind != PathVertex::Kind::Surface)
        return 1.0f;
    const Vector3f travel = directionBetween(light, receiver);
    const float byPower = originDensity(scene, light, travel);
    return byPower > 0.0f ? originDensity(scene, light, travel, &receiver) / byPower : 1.0f;
}

float BidirectionalPaths::pdfLight(const Scene &scene, const PathVertex &light,
                                   const PathVertex &next) {
    const Vector3f w = directionBetween(light, next);
    const EmissionDensity density = emitterOf(scene, light).emissionDensity(light.p, light.n, w);
    if (light.atInfinity) {
        // Photons cross the scene's disk uniformly: per unit area of a surface at `next`,
        // the disk's density times the cosine there.
        return density.position * (next.onSurface() ? std::abs(next.n.dot(w)) : 1.0f);
    }
    return toAreaDensity(density.direction, light, next);
}

float BidirectionalPaths::pdfThroughDelta(const PathVertex &from, const PathVertex &next) {
    return toAreaDensity(std::abs(from.n.dot(directionBetween(from, next))), from, next);
}

float BidirectionalPaths::pdfToward(const Scene &scene, const PathVertex &from,
                                    const PathVertex *previous, const PathVertex &next) {
    if (from.kind == PathVertex::Kind::Light)
        return pdfLight(scene, from, next);
    const Vector3f toNext = directionBetween(from, next);
    float pdf = 0.0f;
    if (from.kind == PathVertex::Kind::Camera) {
        pdf = scene.getCamera()->pdfDirection(from.p, toNext);
    } else {
        if (!previous)
            return 0.0f;
        const Intersection &its = from.its;
        const BSDFQueryRecord query(its, its.toLocal(directionBetween(from, *previous)),
                                    its.toLocal(toNext), ESolidAngle);
        pdf = its.shape->getBSDF()->pdf(query);
    }
    return toAreaDensity(pdf, from, next);
}

void BidirectionalPaths::traceCameraSubpath(const Scene &scene, Sampler &sampler, const Ray3f &ray,
                                            std::vector<PathVertex> &path) const {
    path.clear();
    PathVertex lens;
    lens.kind = PathVertex::Kind::Camera;
    lens.p = ray.o;
    lens.throughput = Color3f(1.0f);
    path.push_back(lens);
    randomWalk(scene, sampler, ray, Color3f(1.0f), true, path);
}

void BidirectionalPaths::traceLightSubpath(const Scene &scene, Sampler &sampler,
                                           std::vector<PathVertex> &path) const {
    path.clear();
    const float emitterSample = sampler.next1D();
    const Point2f positionSample = sampler.next2D();
    const Point2f directionSample = sampler.next2D();
    EmissionSample emission;
    const Emitter *emitter = nullptr;
    float pmf = 0.0f;
    const Color3f flux = sampleLightPath(scene, emitterSample, positionSample, directionSample,
                                         emission, emitter, pmf);
    if ((flux == 0.0f).all() || emission.density.position == 0.0f ||
        emission.density.direction == 0.0f)
        return;
    PathVertex light;
    light.kind = PathVertex::Kind::Light;
    light.emitter = emitter;
    light.p = emission.p;
    light.n = emission.n;
    light.atInfinity = emitter->liesAtInfinity();
    light.travel = light.atInfinity ? emission.ray.d.normalized() : Vector3f::Zero();
    light.pdfForward = originDensity(
        scene, light, light.travel.isZero() ? Vector3f(emission.ray.d.normalized()) : light.travel);
    path.push_back(light);
    randomWalk(scene, sampler, emission.ray, flux, false, path);
    if (path.size() > 1)
        path[0].nextEventRatio = nextEventChoiceRatio(scene, path[0], path[1]);
}

namespace {

/// Sets the densities that the newest vertex of `path` settles (PBR 3rd ed. §16.3.2): its
/// own, as the vertex before it sampled it, and the reverse one of the vertex before that,
/// as seen from the newest. Both from the vertices' positions, as every strategy computes
/// them, so that all strategies weigh a path with the same densities.
void linkDensities(const Scene &scene, std::vector<PathVertex> &path) {
    PathVertex &newest = path.back();
    const size_t current = path.size() - 2;
    if (current == 0) {
        newest.pdfForward = BidirectionalPaths::pdfToward(scene, path[0], nullptr, newest);
        return;
    }
    PathVertex &before = path[current - 1];
    if (path[current].delta) {
        newest.pdfForward = BidirectionalPaths::pdfThroughDelta(path[current], newest);
        before.pdfReverse = BidirectionalPaths::pdfThroughDelta(path[current], before);
        return;
    }
    newest.pdfForward = BidirectionalPaths::pdfToward(scene, path[current], &before, newest);
    before.pdfReverse = BidirectionalPaths::pdfToward(scene, path[current], &newest, before);
}

} // namespace

void BidirectionalPaths::randomWalk(const Scene &scene, Sampler &sampler, Ray3f ray,
                                    const Color3f &throughput, bool radiance,
                                    std::vector<PathVertex> &path) const {
    // A camera subpath holds the lens, maxDepth scattering vertices and the vertex its last
    // ray finds; a light subpath the light and maxDepth scattering vertices.
    const size_t maxVertices = m_depth.maxDepth < 0
                                   ? std::numeric_limits<size_t>::max()
                                   : static_cast<size_t>(m_depth.maxDepth) + (radiance ? 2 : 1);
    // The throughput relative to the subpath's start decides the roulette.
    Color3f relative(1.0f);
    while (path.size() < maxVertices) {
        // The same dimensions in the same order at every vertex, used or not.
        const float emitterSample = sampler.next1D();
        const Point2f connectionSample = sampler.next2D();
        const Point2f bsdfSample = sampler.next2D();
        const float rouletteSample = sampler.next1D();

        PathVertex vertex;
        vertex.throughput = throughput * relative;
        vertex.emitterSample = emitterSample;
        vertex.connectionSample = connectionSample;
        Intersection &its = vertex.its;
        if (!scene.rayIntersect(ray, its)) {
            // A camera ray that leaves the scene ends on the lights at infinity (s = 0).
            if (radiance && !scene.getInfiniteEmitters().empty()) {
                vertex.kind = PathVertex::Kind::Light;
                vertex.atInfinity = true;
                vertex.travel = -ray.d.normalized();
                vertex.p = ray.o;
                vertex.emitted = lightAtInfinity(scene, ray);
                vertex.nextEventRatio = nextEventChoiceRatio(scene, vertex, path.back());
                path.push_back(vertex);
                linkDensities(scene, path);
            }
            return;
        }
        const Vector3f toPrevious = -ray.d.normalized();
        // Light arriving from a direction on which the shading and geometric surfaces
        // disagree is dropped, as the light tracer and photon mappers drop it.
        if (!radiance && !its.sidesAgree(toPrevious))
            return;
        vertex.kind = PathVertex::Kind::Surface;
        vertex.p = its.p;
        vertex.n = its.geoFrame.n;
        vertex.emitter = its.shape->getEmitter();
        if (radiance && vertex.emitter) {
            vertex.emitted = vertex.emitter->eval(EmitterQueryRecord(ray.o, its));
            vertex.nextEventRatio = nextEventChoiceRatio(scene, vertex, path.back());
        }
        path.push_back(vertex);
        linkDensities(scene, path);
        if (path.size() >= maxVertices)
            return;

        // Scatter: a BSDF sample, weighted for radiance or (adjoint) for flux.
        PathVertex &current = path.back();
        const BSDF &bsdf = *current.its.shape->getBSDF();
        BSDFQueryRecord bRec(current.its, current.its.toLocal(toPrevious));
        const Color3f weight = bsdf.sample(bRec, bsdfSample);
        if ((weight == 0.0f).all())
            return;
        const Vector3f wo = current.its.toWorld(bRec.wo);
        float factor = 1.0f;
        if (radiance) {
            if (!current.its.sidesAgree(wo))
                return;
        } else {
            factor = adjointSampleFactor(current.its, toPrevious, wo, bRec);
            if (factor == 0.0f)
                return;
        }
        current.delta = bRec.measure == EDiscrete;
        relative *= weight * factor;
        // Events so far on this subpath: every vertex after its start scattered once.
        if (!russianRoulette(static_cast<int>(path.size()) - 1, m_depth.rrDepth, relative,
                             rouletteSample))
            return;
        ray = radiance ? spawnScatteredRay(current.its, ray, bRec) : current.its.spawnRay(wo);
    }
}

StrategySample BidirectionalPaths::connect(const Scene &scene, const std::vector<PathVertex> &light,
                                           int s, const std::vector<PathVertex> &camera, int t,
                                           PathVertex &sampled, CameraLink &link) const {
    StrategySample result;
    result.s = s;
    result.t = t;
    const PathVertex &pt = camera[t - 1];
    // A camera subpath that left the scene joins no light subpath.
    if (t > 1 && s != 0 && pt.kind == PathVertex::Kind::Light)
        return result;
    if (s == 0) {
        // The camera subpath found a light (Veach's s = 0).
        if (pt.isLight())
            result.unweighted = pt.throughput * pt.emitted;
        return result;
    }
    if (t == 1) {
        // Light tracing: the light subpath's last vertex seen by the camera.
        const PathVertex &qs = light[s - 1];
        if (qs.kind != PathVertex::Kind::Surface)
            return result;
        const Color3f response = connectToCamera(scene, qs.its, directionBetween(qs, light[s - 2]),
                                                 qs.connectionSample, link);
        if ((response == 0.0f).all())
            return result;
        sampled = PathVertex();
        sampled.kind = PathVertex::Kind::Camera;
        sampled.p = link.camera.lensPoint;
        result.unweighted = qs.throughput * response;
        result.splat = true;
        result.position = link.camera.filmPosition;
        return result;
    }
    if (pt.kind != PathVertex::Kind::Surface)
        return result;
    const Intersection &its = pt.its;
    const Vector3f toCamera = directionBetween(pt, camera[t - 2]);
    if (s == 1) {
        // Next-event estimation: a new light vertex, its light chosen for `pt` as the path
        // tracers choose it (by the light tree's importance at pt, by default), and a
        // point on that light as the light samples it for `pt`.
        float emitterSample = pt.emitterSample, pmf = 0.0f;
        const Emitter *emitter = scene.sampleEmitter(its.p, its.shFrame.n, emitterSample, pmf);
        if (!emitter || pmf == 0.0f)
            return result;
        EmitterQueryRecord lRec(its.p);
        const Color3f radianceOverPdf = emitter->sample(lRec, pt.connectionSample);
        if ((radianceOverPdf == 0.0f).all() || !its.sidesAgree(lRec.wi))
            return result;
        const BSDFQueryRecord query(its, its.toLocal(toCamera), its.toLocal(lRec.wi), ESolidAngle);
        const Color3f f = its.shape->getBSDF()->eval(query);
        if ((f == 0.0f).all() || scene.rayIntersect(its.spawnRayTo(lRec.p)))
            return result;
        result.unweighted =
            pt.throughput * f * radianceOverPdf * (std::abs(Frame::cosTheta(query.wo)) / pmf);
        result.light = emitter;
        result.lightPmf = pmf;
        sampled = PathVertex();
        sampled.kind = PathVertex::Kind::Light;
        sampled.emitter = emitter;
        sampled.p = lRec.p;
        sampled.atInfinity = emitter->liesAtInfinity();
        sampled.travel = sampled.atInfinity ? Vector3f(-lRec.wi) : Vector3f::Zero();
        if (emitter->getShape())
            sampled.n = lRec.n;
        sampled.pdfForward = pdfLightOrigin(scene, sampled, pt);
        // The tree's pmf is at hand; a light at infinity shares its directions with the
        // others there, whose pmfs are not.
        const float byPower = scene.emitterPmf(emitter);
        sampled.nextEventRatio = sampled.atInfinity ? nextEventChoiceRatio(scene, sampled, pt)
                                 : byPower > 0.0f   ? pmf / byPower
                                                    : 1.0f;
        return result;
    }
    // Both subpaths end on surfaces: join them with a segment (Veach 1997, eq. 10.8), the
    // light arriving at pt along `joint` from qs.
    const PathVertex &qs = light[s - 1];
    if (qs.kind != PathVertex::Kind::Surface)
        return result;
    Vector3f joint = qs.p - pt.p;
    const float distanceSquared = joint.squaredNorm();
    if (distanceSquared == 0.0f)
        return result;
    joint /= std::sqrt(distanceSquared);
    if (!its.sidesAgree(joint))
        return result;
    const Vector3f toLight = directionBetween(qs, light[s - 2]);
    const Color3f fCamera = its.shape->getBSDF()->eval(
        BSDFQueryRecord(its, its.toLocal(toCamera), its.toLocal(joint), ESolidAngle));
    const Color3f fLight = qs.its.shape->getBSDF()->eval(
        BSDFQueryRecord(qs.its, qs.its.toLocal(-joint), qs.its.toLocal(toLight), ESolidAngle));
    const float cosLightGeometric = std::abs(qs.n.dot(toLight));
    if ((fCamera == 0.0f).all() || (fLight == 0.0f).all() || cosLightGeometric == 0.0f)
        return result;
    // The flux at qs as radiance (Veach 1997, §5.3: |ωL·ns|/|ωL·ng|), the geometry term with
    // the shading cosine at pt, which receives, and the geometric one at qs.
    const Color3f value =
        pt.throughput * fCamera * fLight * qs.throughput *
        (std::abs(its.shFrame.n.dot(joint)) * std::abs(qs.n.dot(joint)) / distanceSquared) *
        (std::abs(qs.its.shFrame.n.dot(toLight)) / cosLightGeometric);
    if ((value == 0.0f).all() || scene.rayIntersect(its.spawnRayTo(qs.p)))
        return result;
    result.unweighted = value;
    return result;
}

float BidirectionalPaths::misWeight(const Scene &scene, const std::vector<PathVertex> &light, int s,
                                    const std::vector<PathVertex> &camera, int t,
                                    const PathVertex &sampled, const CameraLink &link) const {
    if (s + t == 2)
        return 1.0f;
    // The path as strategy (s, t) made it: light vertices 0..s−1 and camera vertices
    // 0..t−1, with the vertex connect() sampled in place of light[0] (s = 1) or camera[0]
    // (t = 1). Where a t = 1 connection shaded qs as the camera ray does, so does this.
    auto lightVertex = [&](int i) -> const PathVertex & {
        return s == 1 && i == 0 ? sampled : light[i];
    };
    auto cameraVertex = [&](int i) -> const PathVertex & {
        return t == 1 && i == 0 ? sampled : camera[i];
    };
    PathVertex shadedQs;
    const PathVertex *qs = s > 0 ? &lightVertex(s - 1) : nullptr;
    if (qs && t == 1 && link.traced) {
        shadedQs = *qs;
        shadedQs.its = link.seen;
        qs = &shadedQs;
    }
    const PathVertex *pt = &cameraVertex(t - 1);
    const PathVertex *qsMinus = s > 1 ? &lightVertex(s - 2) : nullptr;
    const PathVertex *ptMinus = t > 1 ? &cameraVertex(t - 2) : nullptr;

    // The reverse densities the connection changes (PBR 3rd ed. §16.3.4): of pt and qs as
    // the other side would sample them now that the two are joined, and of their
    // predecessors, whose scattering directions changed.
    const float ptReverse =
        qs ? pdfToward(scene, *qs, qsMinus, *pt) : pdfLightOrigin(scene, *pt, *ptMinus);
    const float ptMinusReverse = !ptMinus ? 0.0f
                                 : qs     ? pdfToward(scene, *pt, qs, *ptMinus)
                                          : pdfLight(scene, *pt, *ptMinus);
    const float qsReverse = qs ? pdfToward(scene, *pt, ptMinus, *qs) : 0.0f;
    const float qsMinusReverse = qsMinus ? pdfToward(scene, *qs, pt, *qsMinus) : 0.0f;

    auto cameraReverse = [&](int i) {
        return i == t - 1 ? ptReverse : i == t - 2 ? ptMinusReverse : cameraVertex(i).pdfReverse;
    };
    auto lightReverse = [&](int i) {
        return i == s - 1 ? qsReverse : i == s - 2 ? qsMinusReverse : lightVertex(i).pdfReverse;
    };
    // The connected vertices scattered by evaluation, not by a delta lobe.
    auto cameraDelta = [&](int i) { return i != t - 1 && cameraVertex(i).delta; };
    auto lightDelta = [&](int i) { return i != s - 1 && lightVertex(i).delta; };
    auto heuristic = [&](float ratio) {
        return m_heuristic == MISHeuristic::Power ? ratio * ratio : ratio;
    };
    // The ratios below take the path's light vertex x₀ as a light subpath starts it, its
    // light chosen by power. Strategy s = 1 chooses it at x₁ instead (next-event
    // estimation): its density is r = x₀.nextEventRatio times that, so its term is scaled
    // by r, and for s = 1 itself every other term by 1/r. (x₁ of s = 2 and t = 1 is shaded
    // anew, in shadedQs: its r too.)
    const PathVertex &x0 = s > 0 ? lightVertex(0) : *pt;
    const float choiceRatio =
        s == 2 && qs == &shadedQs ? nextEventChoiceRatio(scene, x0, *qs) : x0.nextEventRatio;

    // Σ over the other strategies of (p_i/p_s)^β, each ratio from the previous one by one
    // vertex changing sides (Veach 1997, eq. 10.9); strategies that would join at a delta
    // vertex, or hit a delta light, cannot make this path.
    const float own = s == 1 && choiceRatio > 0.0f ? 1.0f / choiceRatio : 1.0f;
    auto term = [&](int other, float ratio) {
        return heuristic(ratio * own * (other == 1 ? choiceRatio : 1.0f));
    };
    float sum = 0.0f, ratio = 1.0f;
    for (int i = t - 1; i > 0; --i) {
        ratio *= remapZero(cameraReverse(i)) / remapZero(cameraVertex(i).pdfForward);
        if (!cameraDelta(i) && !cameraDelta(i - 1))
            sum += term(s + t - i, ratio);
    }
    ratio = 1.0f;
    for (int i = s - 1; i >= 0; --i) {
        ratio *= remapZero(lightReverse(i)) / remapZero(lightVertex(i).pdfForward);
        const bool previousDelta = i > 0 ? lightDelta(i - 1) : lightVertex(0).isDeltaLight();
        if (!lightDelta(i) && !previousDelta)
            sum += term(i, ratio);
    }
    return 1.0f / (1.0f + sum);
}

Color3f
BidirectionalPaths::estimate(const Scene &scene, Sampler &sampler, const Ray3f &ray,
                             std::vector<Splat> &splats,
                             const std::function<void(const StrategySample &)> &visit) const {
    thread_local std::vector<PathVertex> camera, light;
    traceCameraSubpath(scene, sampler, ray, camera);
    traceLightSubpath(scene, sampler, light);
    Color3f radiance(0.0f);
    for (int t = 1; t <= static_cast<int>(camera.size()); ++t) {
        for (int s = 0; s <= static_cast<int>(light.size()); ++s) {
            if (!allowed(s, t))
                continue;
            PathVertex sampled;
            CameraLink link;
            StrategySample strategy = connect(scene, light, s, camera, t, sampled, link);
            if (!(strategy.unweighted == 0.0f).all())
                strategy.weight = misWeight(scene, light, s, camera, t, sampled, link);
            if (visit)
                visit(strategy);
            const Color3f value = strategy.unweighted * strategy.weight;
            if (strategy.weight == 0.0f || !value.isValid())
                continue;
            if (strategy.splat)
                splats.push_back({strategy.position, value});
            else
                radiance += value;
        }
    }
    return radiance;
}

} // namespace nori
