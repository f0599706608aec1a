/*
 * progressivephotonmapper — stochastic progressive photon mapping (Hachisuka & Jensen
 * 2009): the render goes in passes of one sample per pixel, each with a new map of
 * photonCount photons (traced as photonmapper does, seeded by the pass's sample index).
 * Every pixel keeps its own radius R and photon count N (ProgressiveRadii): after a pass
 * in which its camera sample found M photons, N ← N + αM and R² ← R²(N + αM)/(N + M), so
 * the radius shrinks where photons are dense and the estimate converges to the right
 * answer (bias and variance both vanish). The published estimate τ/(π R² · passes · emitted) equals the
 * mean over passes of each pass's Σ f·Φ/(π R_pass²) (τ's rescaling by R²_new/R²_old
 * cancels), so each camera sample returns its pass's estimate and the film averages them:
 * the image is deterministic for a fixed seed, whatever the thread count, and it works with
 * --time, adaptive sampling and split renders (each part shrinks its radii from the
 * start, so parts are each consistent but carry more bias than one render of all passes).
 *
 * Parameters:
 *   photonCount   integer  1000000  photons stored per pass
 *   photonRadius  float    0        initial radius of every pixel; 0: the diagonal of
 *                                   the scene's bounding box / 500
 *   alpha         float    0.7      fraction of new photons kept per pass, in (0, 1)
 *   splitBounces  integer  3        bounces at which camera paths follow both the
 *                                   reflection and the refraction of smooth glass, each
 *                                   weighted by its Fresnel probability (photonmapper);
 *                                   0: pick one by Fresnel
 *
 *   <integrator type="progressivephotonmapper">
 *       <integer name="photonCount" value="100000"/>
 *       <float name="alpha" value="0.7"/>
 *   </integrator>
 */
#include <nori/camera.h>
#include <nori/hash.h>
#include <nori/integrator.h>
#include <nori/photonmap.h>
#include <nori/proplist.h>
#include <nori/sampler.h>
#include <nori/scene.h>

namespace nori {
namespace {

class ProgressivePhotonMapper : public Integrator {
public:
    explicit ProgressivePhotonMapper(const PropertyList &props)
        : m_parameters(PhotonMappingParameters::read(props, "progressivephotonmapper")) {
        m_alpha = props.getFloat("alpha", 0.7f);
        if (!(m_alpha > 0.0f && m_alpha < 1.0f))
            throw NoriException("progressivephotonmapper: 'alpha' must be in (0, 1), got {}",
                                m_alpha);
    }

    void preprocess(const Scene *scene) override {
        m_radii = ProgressiveRadii(scene->getCamera()->getOutputSize(),
                                   photonGatherRadius(*scene, m_parameters.photonRadius));
        m_passes = 0;
        m_totalEmitted = 0;
        m_photonSeconds = 0.0;
        m_peakBytes = 0;
        traceMap(*scene, 0); // so that Li works outside the render loop, as pass 0
    }

    void beginPass(const Scene *scene, uint32_t firstSample, uint32_t) override {
        if (firstSample != m_mapSample)
            traceMap(*scene, firstSample);
    }

    /// The SPPM update of every pixel that took samples in the pass.
    void endPass(const Scene *) override {
        m_radii.endPass(m_alpha);
        ++m_passes;
        m_mapSample = kNoMap; // the next pass traces its own
    }

    size_t maxSamplesPerPass() const override { return 1; }

    void saveState(StateWriter &state) const override {
        m_radii.saveState(state);
        state.write<uint64_t>(m_passes);
        state.write(m_totalEmitted);
        state.write(m_photonSeconds);
        state.write<uint64_t>(m_peakBytes);
    }
    void loadState(StateReader &state) override {
        m_radii.loadState(state);
        m_passes = state.read<uint64_t>();
        m_totalEmitted = state.read<uint64_t>();
        m_photonSeconds = state.read<double>();
        m_peakBytes = state.read<uint64_t>();
        m_mapSample = kNoMap; // the next pass traces its own map
    }

    Color3f Li(const Scene *scene, Sampler *sampler, const Ray3f &ray) const override {
        ProgressiveRadii::Pixel *pixel = m_radii.pixel(sampler->pixel());
        const float radius = pixel ? std::sqrt(pixel->radiusSquared) : m_radii.initialRadius();
        float found = 0.0f;
        Color3f radiance = photonMappedRadiance(*scene, m_map, *sampler, ray, radius,
                                                m_parameters.splitBounces, &found);
        if (pixel) { // only this pixel's thread writes it during a pass (Integrator::beginPass)
            pixel->passPhotons += found;
            ++pixel->passSamples;
        }
        return radiance;
    }

    std::string renderSummary() const override {
        return fmt::format("Progressive photon mapping: {} passes of {} photons ({:.0f} paths each "
                           "on average), {:.2f} s tracing photons, map {:.1f} MiB at most, pixel "
                           "state {:.1f} MiB; radius {:.4g} at first, now {:.4g} to {:.4g}",
                           m_passes, m_parameters.photonCount,
                           m_passes > 0 ? static_cast<double>(m_totalEmitted) / m_passes : 0.0,
                           m_photonSeconds, static_cast<double>(m_peakBytes) / (1024.0 * 1024.0),
                           static_cast<double>(m_radii.memoryBytes()) / (1024.0 * 1024.0),
                           m_radii.initialRadius(), m_radii.smallestRadius(),
                           m_radii.largestRadius());
    }

    std::string toString() const override {
        return fmt::format(
            "ProgressivePhotonMapper[photonCount={}, photonRadius={}, alpha={}, splitBounces={}]",
            m_parameters.photonCount, m_parameters.photonRadius, m_alpha,
            m_parameters.splitBounces);
    }

private:
    static constexpr uint32_t kNoMap = UINT32_MAX;

    void traceMap(const Scene &scene, uint32_t firstSample) {
        m_map = PhotonMap(); // free the last pass's map before tracing the next
        PhotonTracingStatistics statistics;
        m_map = tracePhotons(scene, m_parameters.photonCount,
                             hashValues(scene.getSampler()->getSeed(), firstSample), &statistics);
        m_mapSample = firstSample;
        m_totalEmitted += statistics.emitted;
        m_photonSeconds += statistics.seconds;
        m_peakBytes = std::max(m_peakBytes, statistics.bytes);
    }

    PhotonMappingParameters m_parameters;
    float m_alpha;
    mutable ProgressiveRadii m_radii;
    PhotonMap m_map;
    uint32_t m_mapSample = kNoMap; ///< the first sample index of the pass m_map is for
    size_t m_passes = 0;
    uint64_t m_totalEmitted = 0;
    double m_photonSeconds = 0.0;
    size_t m_peakBytes = 0;
};

NORI_REGISTER_CLASS(ProgressivePhotonMapper, "progressivephotonmapper");

} // namespace
} // namespace nori
