#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/hash.h>
#include <nori/parallel.h>
#include <nori/pathtracing.h>
#include <nori/pcg32.h>
#include <nori/photonmap.h>
#include <nori/proplist.h>
#include <nori/raydifferential.h>
#include <nori/sampler.h>
#include <nori/scene.h>

#include <algorithm>
#include <chrono>

namespace nori {

namespace {

/// Ranges at least this large are split in parallel while building.
constexpr size_t kParallelBuildSize = 1 << 15;
/// Photon paths traced per task.
constexpr size_t kPathsPerChunk = 4096;
/// A path ends after this many bounces even if Russian roulette has not ended it.
constexpr int kMaxPhotonBounces = 1024;
/// Camera paths: Russian roulette from this bounce on, and a hard limit.
constexpr int kCameraRouletteDepth = 3;
constexpr int kMaxCameraBounces = 1024;
/// Splitting at most this many bounces deep: up to 2^8 density estimates per sample.
constexpr int kMaxSplitBounces = 8;
/// Paths traced at most per photon wanted, before giving up on filling the map.
constexpr uint64_t kMaxPathsPerPhoton = 100;

/// The photons the paths of one chunk stored, and after each path how many so far.
struct ChunkPhotons {
    std::vector<Photon> photons;
    std::vector<uint32_t> storedAfterPath;
};

/// Traces photon path `index`, appending the photons it stores.
void tracePhotonPath(const Scene &scene, uint64_t seed, uint64_t index,
                     std::vector<Photon> &stored) {
    PCG32 random(hashValues(seed, index), 0x70686f746f6eULL); // stream "photon"
    const float emitterSample = random.nextFloat();
    const Point2f positionSample(random.nextFloat(), random.nextFloat());
    const Point2f directionSample(random.nextFloat(), random.nextFloat());
    EmissionSample emission;
    const Emitter *emitter = nullptr;
    float pmf = 0.0f;
    Color3f power = sampleLightPath(scene, emitterSample, positionSample, directionSample, emission,
                                    emitter, pmf);
    if ((power == 0.0f).all())
        return;
    Ray3f ray = emission.ray;
    Color3f throughput(1.0f); // power relative to the emitted power, for the roulette
    for (int bounce = 0; bounce < kMaxPhotonBounces; ++bounce) {
        Intersection its;
        if (!scene.rayIntersect(ray, its))
            return;
        const BSDF *bsdf = its.shape->getBSDF();
        const Vector3f wi = -ray.d.normalized();
        if (bsdf->isDiffuse())
            stored.push_back({its.p, wi, power});

        BSDFQueryRecord bRec(its, its.toLocal(wi));
        Color3f weight = bsdf->sample(bRec, Point2f(random.nextFloat(), random.nextFloat()));
        const Vector3f wo = its.toWorld(bRec.wo);
        if ((weight == 0.0f).all() || !its.sidesAgree(wo))
            return;
        // Photons carry flux: the adjoint of the BSDF's radiance weight.
        const float adjoint = adjointSampleFactor(its, wi, wo, bRec);
        if (adjoint == 0.0f)
            return;
        weight *= adjoint;
        power *= weight;
        throughput *= weight;
        // Russian roulette: continue with probability q, and divide by it.
        const float q = std::min(0.99f, throughput.maxCoeff());
        if (!(random.nextFloat() < q))
            return;
        power /= q;
        throughput /= q;
        ray = its.spawnRay(wo);
    }
}

ChunkPhotons traceChunk(const Scene &scene, uint64_t seed, uint64_t firstPath, size_t pathCount) {
    ChunkPhotons chunk;
    chunk.storedAfterPath.reserve(pathCount);
    for (size_t i = 0; i < pathCount; ++i) {
        tracePhotonPath(scene, seed, firstPath + i, chunk.photons);
        chunk.storedAfterPath.push_back(static_cast<uint32_t>(chunk.photons.size()));
    }
    return chunk;
}

} // namespace

PhotonMap::PhotonMap(std::vector<Photon> photons)
    : m_photons(std::move(photons)), m_axes(m_photons.size(), 0) {
    build(0, m_photons.size());
}

void PhotonMap::build(size_t begin, size_t end) {
    if (end - begin <= 1)
        return;
    Point3f lower = m_photons[begin].position, upper = lower;
    for (size_t i = begin + 1; i < end; ++i) {
        lower = lower.cwiseMin(m_photons[i].position);
        upper = upper.cwiseMax(m_photons[i].position);
    }
    int axis;
    (upper - lower).maxCoeff(&axis);
    const size_t median = begin + (end - begin) / 2;
    std::nth_element(
        m_photons.begin() + static_cast<ptrdiff_t>(begin),
        m_photons.begin() + static_cast<ptrdiff_t>(median),
        m_photons.begin() + static_cast<ptrdiff_t>(end),
        [axis](const Photon &a, const Photon &b) { return a.position[axis] < b.position[axis]; });
    m_axes[median] = static_cast<uint8_t>(axis);
    if (end - begin >= kParallelBuildSize)
        parallelInvoke([&] { build(begin, median); }, [&] { build(median + 1, end); });
    else {
        build(begin, median);
        build(median + 1, end);
    }
}

PhotonMap tracePhotons(const Scene &scene, size_t photonCount, uint64_t seed,
                       PhotonTracingStatistics *statistics) {
    const auto start = std::chrono::steady_clock::now();
    if (scene.getEmitters().empty())
        throw NoriException("photon mapping needs a light, and the scene has none");
    std::vector<Photon> photons;
    photons.reserve(photonCount);
    const uint64_t maxPaths = kMaxPathsPerPhoton * std::max<uint64_t>(photonCount, 1);
    uint64_t emitted = 0;
    // Rounds of chunks in parallel, merged in path order until the map is full. The first
    // round traces an eighth of photonCount paths; later ones what the stored/emitted
    // ratio so far says is missing, with 10% to spare.
    uint64_t roundPaths = std::max<uint64_t>(photonCount / 8, 1);
    while (photons.size() < photonCount && emitted < maxPaths) {
        const size_t chunkCount =
            static_cast<size_t>((roundPaths + kPathsPerChunk - 1) / kPathsPerChunk);
        std::vector<ChunkPhotons> chunks(chunkCount);
        const uint64_t roundStart = emitted;
        parallelFor(size_t(0), chunkCount, [&](size_t c) {
            chunks[c] = traceChunk(scene, seed, roundStart + c * kPathsPerChunk, kPathsPerChunk);
        });
        for (const ChunkPhotons &chunk : chunks) {
            for (size_t path = 0; path < chunk.storedAfterPath.size(); ++path) {
                const uint32_t from = path == 0 ? 0 : chunk.storedAfterPath[path - 1];
                photons.insert(photons.end(), chunk.photons.begin() + from,
                               chunk.photons.begin() + chunk.storedAfterPath[path]);
                ++emitted;
                if (photons.size() >= photonCount || emitted >= maxPaths)
                    break;
            }
            if (photons.size() >= photonCount || emitted >= maxPaths)
                break;
        }
        const double storedPerPath =
            photons.empty() ? 0.0 : static_cast<double>(photons.size()) / emitted;
        const double missing =
            static_cast<double>(photonCount - std::min(photons.size(), photonCount));
        roundPaths = storedPerPath > 0.0 ? static_cast<uint64_t>(1.1 * missing / storedPerPath) + 1
                                         : 8 * roundPaths;
        roundPaths = std::min(roundPaths, maxPaths - std::min(maxPaths, emitted));
    }
    // The map holds flux per emitted path.
    if (emitted > 0) {
        const float perPath = 1.0f / static_cast<float>(emitted);
        parallelFor(size_t(0), photons.size(), [&](size_t i) { photons[i].power *= perPath; });
    }
    photons.shrink_to_fit();
    PhotonMap map(std::move(photons));
    if (statistics) {
        statistics->stored = map.size();
        statistics->emitted = emitted;
        statistics->bytes = map.memoryBytes();
        statistics->seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    }
    return map;
}

namespace {

/// What the camera paths of one sample gathered, each branch of a split weighted by its
/// probability (the product of the probabilities of the lobes it followed).
struct CameraGather {
    Color3f radiance{0.0f};
    float photons = 0.0f; ///< photons found: each density estimate's count times its probability
};

/// The scene, map and settings one camera sample's paths share.
struct CameraPathContext {
    const Scene &scene;
    const PhotonMap &map;
    Sampler &sampler;
    float radius;
    int splitBounces;
};

/// Follows a camera path from `ray` (the bounce-th ray of the path) to its first diffuse
/// hit and adds what it gathers times `probability`. `throughput` is the path's weight as
/// if every lobe had been picked by sampling (split lobes: weight/probability), so that
/// Russian roulette sees the same numbers with and without splitting.
void followCameraPath(const CameraPathContext &context, Ray3f ray, Color3f throughput,
                      float probability, int bounce, CameraGather &gather) {
    Point3f previous = ray.o;
    for (; bounce < kMaxCameraBounces; ++bounce) {
        Intersection its;
        if (!context.scene.rayIntersect(ray, its)) {
            // Only specular chains reach here: a filtered lookup of the environment.
            gather.radiance += probability * throughput * lightAtInfinity(context.scene, ray);
            return;
        }
        if (const Emitter *emitter = its.shape->getEmitter())
            gather.radiance +=
                probability * throughput * emitter->eval(EmitterQueryRecord(previous, its));

        const BSDF *bsdf = its.shape->getBSDF();
        const Vector3f wiLocal = its.toLocal(-ray.d.normalized());
        if (bsdf->isDiffuse()) {
            Color3f reflected(0.0f);
            size_t found = 0;
            context.map.forEachWithin(its.p, context.radius, [&](const Photon &photon) {
                ++found;
                const BSDFQueryRecord bRec(its, wiLocal, its.toLocal(photon.direction),
                                           ESolidAngle);
                reflected += bsdf->eval(bRec) * photon.power;
            });
            gather.radiance +=
                probability * throughput * reflected / (kPi * context.radius * context.radius);
            gather.photons += probability * static_cast<float>(found);
            return;
        }

        BSDFQueryRecord bRec(its, wiLocal);
        if (bounce < context.splitBounces) {
            DiscreteLobe lobes[BSDF::kMaxDiscreteLobes];
            const int lobeCount = bsdf->discreteLobes(bRec, lobes);
            if (lobeCount > 1) {
                // Follow every lobe, each weighted by its probability of being picked.
                for (int i = 0; i < lobeCount; ++i) {
                    const DiscreteLobe &lobe = lobes[i];
                    const Vector3f wo = its.toWorld(lobe.wo);
                    if (!(lobe.probability > 0.0f) || !its.sidesAgree(wo))
                        continue;
                    bRec.wo = lobe.wo;
                    bRec.eta = lobe.eta;
                    bRec.measure = EDiscrete;
                    followCameraPath(context, spawnScatteredRay(its, ray, bRec),
                                     throughput * lobe.weight / lobe.probability,
                                     probability * lobe.probability, bounce + 1, gather);
                }
                return;
            }
        }

        // The same dimensions at every bounce, used or not.
        const Point2f bsdfSample = context.sampler.next2D();
        const float rouletteSample = context.sampler.next1D();
        const Color3f weight = bsdf->sample(bRec, bsdfSample);
        if ((weight == 0.0f).all() || !its.sidesAgree(its.toWorld(bRec.wo)))
            return;
        throughput *= weight;
        previous = its.p;
        ray = spawnScatteredRay(its, ray, bRec);
        if (!russianRoulette(bounce + 1, kCameraRouletteDepth, throughput, rouletteSample))
            return;
    }
}

} // namespace

Color3f photonMappedRadiance(const Scene &scene, const PhotonMap &map, Sampler &sampler,
                             const Ray3f &cameraRay, float radius, int splitBounces,
                             float *photonsFound) {
    CameraGather gather;
    followCameraPath({scene, map, sampler, radius, splitBounces}, cameraRay, Color3f(1.0f), 1.0f, 0,
                     gather);
    if (photonsFound)
        *photonsFound = gather.photons;
    return gather.radiance;
}

PhotonMappingParameters PhotonMappingParameters::read(const PropertyList &props,
                                                      const std::string &plugin) {
    PhotonMappingParameters parameters;
    const int count = props.getInteger("photonCount", 1000000);
    if (count <= 0)
        throw NoriException("{}: 'photonCount' must be positive, got {}", plugin, count);
    parameters.photonCount = static_cast<size_t>(count);
    parameters.photonRadius = props.getFloat("photonRadius", 0.0f);
    parameters.splitBounces = props.getInteger("splitBounces", parameters.splitBounces);
    if (parameters.splitBounces < 0 || parameters.splitBounces > kMaxSplitBounces)
        throw NoriException("{}: 'splitBounces' must be in [0, {}], got {}", plugin,
                            kMaxSplitBounces, parameters.splitBounces);
    if (!(parameters.photonRadius >= 0.0f) || !std::isfinite(parameters.photonRadius))
        throw NoriException("{}: 'photonRadius' must be finite and not negative (0: automatic), "
                            "got {}",
                            plugin, parameters.photonRadius);
    return parameters;
}

std::string describe(const PhotonTracingStatistics &statistics) {
    return fmt::format("{} photons stored from {} paths, {:.1f} MiB, in {:.2f} s",
                       statistics.stored, statistics.emitted,
                       static_cast<double>(statistics.bytes) / (1024.0 * 1024.0),
                       statistics.seconds);
}

float photonGatherRadius(const Scene &scene, float photonRadius) {
    if (photonRadius > 0.0f)
        return photonRadius;
    const BoundingBox3f &bounds = scene.getBoundingBox();
    const float diagonal = bounds.isValid() ? (bounds.max - bounds.min).norm() : 0.0f;
    return diagonal > 0.0f ? diagonal / 500.0f : 1e-3f;
}

ProgressiveRadii::ProgressiveRadii(const Vector2i &size, float initialRadius)
    : m_width(size.x()), m_initialRadius(initialRadius),
      m_pixels(static_cast<size_t>(size.prod()),
               Pixel{initialRadius * initialRadius, 0.0f, 0.0f, 0}) {}

ProgressiveRadii::Pixel *ProgressiveRadii::pixel(const Point2i &p) {
    if (p.x() < 0 || p.y() < 0 || p.x() >= m_width)
        return nullptr;
    const size_t index = static_cast<size_t>(p.y()) * m_width + p.x();
    return index < m_pixels.size() ? &m_pixels[index] : nullptr;
}

void ProgressiveRadii::saveState(StateWriter &state) const {
    state.write<uint64_t>(m_pixels.size());
    for (const Pixel &pixel : m_pixels) {
        state.write(pixel.radiusSquared);
        state.write(pixel.photons);
        state.write(pixel.passPhotons);
        state.write(pixel.passSamples);
    }
}

void ProgressiveRadii::loadState(StateReader &state) {
    if (state.read<uint64_t>() != m_pixels.size())
        throw NoriException("{} does not fit this render: another image size", state.what());
    for (Pixel &pixel : m_pixels) {
        pixel.radiusSquared = state.read<float>();
        pixel.photons = state.read<float>();
        pixel.passPhotons = state.read<float>();
        pixel.passSamples = state.read<uint32_t>();
    }
}

void ProgressiveRadii::endPass(float alpha) {
    parallelFor(size_t(0), m_pixels.size(), [&](size_t i) {
        Pixel &pixel = m_pixels[i];
        if (pixel.passSamples > 0 && pixel.passPhotons > 0.0f) {
            const float found = pixel.passPhotons / static_cast<float>(pixel.passSamples);
            pixel.radiusSquared *= shrinkage(pixel.photons, found, alpha);
            pixel.photons += alpha * found;
        }
        pixel.passPhotons = 0.0f;
        pixel.passSamples = 0;
    });
}

float ProgressiveRadii::smallestRadius() const {
    float smallest = m_initialRadius * m_initialRadius;
    for (const Pixel &pixel : m_pixels)
        smallest = std::min(smallest, pixel.radiusSquared);
    return std::sqrt(smallest);
}

float ProgressiveRadii::largestRadius() const {
    float largest = 0.0f;
    for (const Pixel &pixel : m_pixels)
        largest = std::max(largest, pixel.radiusSquared);
    return std::sqrt(largest);
}

} // namespace nori
