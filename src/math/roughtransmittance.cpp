#include <nori/fresnel.h>
#include <nori/parallel.h>
#include <nori/roughtransmittance.h>

#include <map>
#include <memory>
#include <mutex>

namespace nori {

namespace {

constexpr int kCosines = 64, kRoughnesses = 32, kSamples = 1024;

/// The weight of one visible normal m drawn for wi: the BTDF's ∫ f_t |cos θo| dωo over
/// normals is ∫ (1 − F(wi·m)) G(wi, wt, m) D(m) (wi·m)/cos θi dm, and the density of m is
/// pdfNormal(wi, m) (G1(wi, m) (wi·m) D(m)/cos θi for GGX's visible normals).
float transmittedWeight(const MicrofacetDistribution &distribution, float eta, const Vector3f &wi,
                        const Point2f &u) {
    const Vector3f m = distribution.sampleNormal(wi, u);
    const float cosIM = wi.dot(m);
    const float density = distribution.pdfNormal(wi, m);
    if (cosIM <= 0.0f || !(density > 0.0f))
        return 0.0f;
    Vector3f wt;
    if (!refract(wi, m, eta, wt))
        return 0.0f; // total internal reflection at this microfacet
    if (wt.z() >= 0.0f)
        return 0.0f; // refracted back above the macro-surface: no transmission
    const float value = (1.0f - fresnelDielectric(cosIM, 1.0f, eta)) * distribution.G(wi, wt, m) *
                        distribution.D(m) * cosIM / wi.z();
    return value / density;
}

} // namespace

RoughTransmittance::RoughTransmittance(MicrofacetDistribution::Type type, float eta)
    : m_table(kCosines, kRoughnesses, kSamples,
              [type, eta](const Vector3f &wi, float p, const Point2f &u) {
                  const float alpha = std::max(p * kMaxAlpha, 1e-4f);
                  return transmittedWeight(MicrofacetDistribution(type, alpha), eta, wi, u);
              }) {
    // 2 ∫ T(μ) μ dμ by the midpoint rule on the interpolated table, per roughness node.
    constexpr int kSteps = 512;
    m_diffuse.resize(kRoughnesses);
    for (int j = 0; j < kRoughnesses; ++j) {
        const float p = static_cast<float>(j) / (kRoughnesses - 1);
        double sum = 0.0;
        for (int i = 0; i < kSteps; ++i) {
            const float mu = (static_cast<float>(i) + 0.5f) / kSteps;
            sum += m_table(mu, p) * mu;
        }
        m_diffuse[static_cast<size_t>(j)] = static_cast<float>(2.0 * sum / kSteps);
    }
}

float RoughTransmittance::diffuse(float alpha) const {
    const float position =
        std::clamp(alpha / kMaxAlpha, 0.0f, 1.0f) * static_cast<float>(kRoughnesses - 1);
    const int lower = std::min(static_cast<int>(position), kRoughnesses - 2);
    const float t = position - static_cast<float>(lower);
    return (1.0f - t) * m_diffuse[static_cast<size_t>(lower)] +
           t * m_diffuse[static_cast<size_t>(lower) + 1];
}

const RoughTransmittance &RoughTransmittance::get(MicrofacetDistribution::Type type, float eta) {
    static std::mutex mutex;
    static std::map<std::pair<int, float>, std::unique_ptr<RoughTransmittance>> tables;
    const std::lock_guard<std::mutex> lock(mutex);
    auto &table = tables[{static_cast<int>(type), eta}];
    // Isolated: while the table's parallel loop runs, this thread must not pick up another
    // task that could call get() and wait for the lock it holds.
    if (!table)
        runIsolated([&] { table = std::make_unique<RoughTransmittance>(type, eta); });
    return *table;
}

} // namespace nori
