/*
 * photonmapper — photon mapping as the course's assignment defines it (Jensen 2001):
 * before rendering, photon paths are traced from the lights (picked by power) until
 * photonCount photons are stored, one at every diffuse hit, the first included, so that
 * direct light too comes from the map; their powers are divided by the number of paths
 * emitted. Camera paths follow specular reflection and refraction, add the emission they
 * hit and, at the first diffuse hit, sum f·Φ/(π r²) over the photons within photonRadius.
 * At their first splitBounces bounces they follow both the reflection and the refraction
 * of smooth glass, each weighted by its Fresnel probability, rather than pick one
 * (Whitted-style; Jensen 2001, ch. 9): light reflected in glass comes without speckles.
 * Biased (the radius blurs the light) but consistent as photonCount grows and the radius
 * shrinks; caustics through glass come out clean where a path tracer shows fireflies.
 * The map is traced with the sampler's seed and does not depend on the thread count.
 *
 * Parameters:
 *   photonCount   integer  1000000  photons stored in the map
 *   photonRadius  float    0        gathering radius; 0: the diagonal of the scene's
 *                                   bounding box / 500
 *   splitBounces  integer  3        bounces at which glass splits camera paths (0 to 8;
 *                                   0: pick by Fresnel)
 *
 *   <integrator type="photonmapper">
 *       <integer name="photonCount" value="1000000"/>
 *       <float name="photonRadius" value="0"/>
 *   </integrator>
 */
#include <nori/integrator.h>
#include <nori/photonmap.h>
#include <nori/sampler.h>
#include <nori/scene.h>

namespace nori {
namespace {

class PhotonMapper : public Integrator {
public:
    explicit PhotonMapper(const PropertyList &props)
        : m_parameters(PhotonMappingParameters::read(props, "photonmapper")) {}

    void preprocess(const Scene *scene) override {
        m_radius = photonGatherRadius(*scene, m_parameters.photonRadius);
        m_map = tracePhotons(*scene, m_parameters.photonCount, scene->getSampler()->getSeed(),
                             &m_statistics);
    }

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        return photonMappedRadiance(*scene, m_map, *sampler, ray, m_radius,
                                    m_parameters.splitBounces, nullptr);
    }

    std::string renderSummary() const override {
        return fmt::format("Photon map: {}; radius {:.4g}", describe(m_statistics), m_radius);
    }

    std::string toString() const override {
        return fmt::format("PhotonMapper[photonCount={}, photonRadius={}, splitBounces={}]",
                           m_parameters.photonCount, m_parameters.photonRadius,
                           m_parameters.splitBounces);
    }

private:
    PhotonMappingParameters m_parameters;
    float m_radius = 0.0f;
    PhotonMap m_map;
    PhotonTracingStatistics m_statistics;
};

NORI_REGISTER_CLASS(PhotonMapper, "photonmapper");

} // namespace
} // namespace nori
