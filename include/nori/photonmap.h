// Photon mapping (Jensen 2001): photons traced from the lights and stored where they land
// on diffuse surfaces, in a kd-tree, and the camera side that follows specular chains to
// the first diffuse hit and estimates the light reflected there from the photons around
// it. The photonmapper and progressivephotonmapper integrators are built from these.
#pragma once

#include <nori/color.h>
#include <nori/ray.h>
#include <nori/statestream.h>
#include <nori/vector.h>

#include <vector>

namespace nori {

class PropertyList;
class Sampler;
class Scene;

/// The parameters both photon mappers take.
struct PhotonMappingParameters {
    size_t photonCount = 1000000; ///< photons stored per map
    float photonRadius = 0.0f;    ///< the gathering radius; 0: automatic
    /// Camera paths follow every lobe of smooth glass (BSDF::discreteLobes) at their first
    /// splitBounces bounces instead of picking one.
    int splitBounces = 3;

    /// Reads `photonCount` (positive), `photonRadius` (finite, not negative) and
    /// `splitBounces` (0 to 8); errors name `plugin`.
    static PhotonMappingParameters read(const PropertyList &props, const std::string &plugin);
};

/// A photon where it landed.
struct Photon {
    Point3f position;
    Vector3f direction; ///< unit, toward where the photon came from
    Color3f power;      ///< the flux it carries (W), already divided by the photons emitted
};

/// A balanced kd-tree over photons, stored implicitly (Bentley 1975; Jensen 2001, §6.3):
/// the node covering photons [begin, end) is the median (begin + end)/2, split along the
/// widest axis of its range's bounds, m_axes[median].
class PhotonMap {
public:
    PhotonMap() = default;
    /// Builds the tree over `photons` (in parallel for large maps).
    explicit PhotonMap(std::vector<Photon> photons);

    size_t size() const { return m_photons.size(); }
    /// The memory the map holds (photons and split axes).
    size_t memoryBytes() const {
        return m_photons.capacity() * sizeof(Photon) + m_axes.capacity() * sizeof(uint8_t);
    }
    /// Calls visit(photon) for every photon within `radius` of `center` (boundary included).
    template <typename Visit>
    void forEachWithin(const Point3f &center, float radius, Visit &&visit) const;

private:
    void build(size_t begin, size_t end);

    std::vector<Photon> m_photons;
    std::vector<uint8_t> m_axes;
};

/// What tracing a photon map took.
struct PhotonTracingStatistics {
    size_t stored = 0;
    uint64_t emitted = 0; ///< photon paths started, the powers' divisor
    size_t bytes = 0;     ///< the map's memory
    double seconds = 0.0; ///< tracing and building
};

/// Traces photon paths until `photonCount` photons are stored (the course's convention):
/// each path starts at a light picked by power (Emitter::samplePhoton), stores a photon at
/// every hit on a diffuse BSDF (the first included) and continues by BSDF sampling with
/// Russian roulette; the powers are divided by the number of paths emitted. Path j draws
/// its random numbers from (seed, j) alone, and paths are kept in index order up to the
/// one that fills the map, so the map does not depend on the thread count. Stops early,
/// with what it has, after 100·photonCount paths (a scene whose light never reaches a
/// diffuse surface). Throws NoriException when the scene has no light.
PhotonMap tracePhotons(const Scene &scene, size_t photonCount, uint64_t seed,
                       PhotonTracingStatistics *statistics = nullptr);

/// The radiance arriving along a camera ray by photon mapping: the ray follows specular
/// reflections and refractions (BSDFs that are not diffuse), adds the emission it hits and,
/// at the first diffuse hit, the density estimate Σ f·Φ/(π r²) over the photons within
/// `radius` (Jensen 2001, eq. 7.6). At its first `splitBounces` bounces, a BSDF that lists
/// its Dirac lobes (smooth glass: reflection and refraction) is not sampled: the path
/// splits and follows each lobe, weighted by the lobe's probability, so the light seen in
/// glass comes without the noise of picking by Fresnel. `photonsFound` (if given)
/// receives the photons found, each estimate's count times its branch's probability: the
/// number a path that picked its lobes would find on average.
Color3f photonMappedRadiance(const Scene &scene, const PhotonMap &map, Sampler &sampler,
                             const Ray3f &cameraRay, float radius, int splitBounces,
                             float *photonsFound);

/// "1,000,000 photons stored from 1,234,567 paths, 36.0 MiB, in 1.23 s".
std::string describe(const PhotonTracingStatistics &statistics);

/// The gathering radius of `photonRadius` (0: automatic, the diagonal of the scene's
/// bounding box / 500, the course's rule).
float photonGatherRadius(const Scene &scene, float photonRadius);

/// Stochastic progressive photon mapping's statistics per pixel (Hachisuka & Jensen 2009,
/// §4): each pixel's radius R and photon count N, and what its camera samples found in the
/// pass under way. After a pass in which the pixel's samples found M photons each on
/// average, N ← N + αM and R² ← R²·(N + αM)/(N + M): the radius shrinks where photons are
/// dense, so bias and variance both vanish.
class ProgressiveRadii {
public:
    struct Pixel {
        float radiusSquared;
        float photons;        ///< N, the photons the radius is worth
        float passPhotons;    ///< photons found by this pass's samples
        uint32_t passSamples; ///< samples taken in this pass
    };

    ProgressiveRadii() = default;
    /// Every pixel of an image of `size` at `initialRadius`, with no photons.
    ProgressiveRadii(const Vector2i &size, float initialRadius);

    /// The statistics of pixel `p`; nullptr outside the image. During a pass only the
    /// thread rendering a pixel writes it (Integrator::beginPass).
    Pixel *pixel(const Point2i &p);
    /// R²'s factor for a pixel of N photons whose samples found M each: (N + αM)/(N + M).
    static float shrinkage(float photons, float found, float alpha) {
        return (photons + alpha * found) / (photons + found);
    }
    /// The update above, for every pixel that took samples in the pass (in parallel).
    void endPass(float alpha);

    float initialRadius() const { return m_initialRadius; }
    float smallestRadius() const;
    float largestRadius() const;
    size_t memoryBytes() const { return m_pixels.size() * sizeof(Pixel); }

    /// Every pixel's statistics, for a checkpoint, and back (same image size).
    void saveState(StateWriter &state) const;
    void loadState(StateReader &state);

private:
    int m_width = 0;
    float m_initialRadius = 0.0f;
    std::vector<Pixel> m_pixels;
};

template <typename Visit>
void PhotonMap::forEachWithin(const Point3f &center, float radius, Visit &&visit) const {
    const float radiusSquared = radius * radius;
    // Depth-first over [begin, end) ranges; a balanced tree of n photons is log₂ n deep.
    struct Range {
        size_t begin, end;
    };
    Range stack[64];
    int top = 0;
    stack[top++] = {0, m_photons.size()};
    while (top > 0) {
        const Range range = stack[--top];
        if (range.begin >= range.end)
            continue;
        const size_t median = range.begin + (range.end - range.begin) / 2;
        const Photon &photon = m_photons[median];
        if ((photon.position - center).squaredNorm() <= radiusSquared)
            visit(photon);
        const int axis = m_axes[median];
        const float offset = center[axis] - photon.position[axis];
        const Range below{range.begin, median}, above{median + 1, range.end};
        // The near side always, the far side only if the sphere reaches across the plane.
        const Range &near = offset < 0.0f ? below : above;
        const Range &far = offset < 0.0f ? above : below;
        if (offset * offset <= radiusSquared)
            stack[top++] = far;
        stack[top++] = near;
    }
}

} // namespace nori
