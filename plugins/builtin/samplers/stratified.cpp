/*
 * stratified — jittered stratified samples, padded per dimension (PBR 4th ed. §8.5):
 * each next1D() or next2D() call of a sample is its own dimension, and the sampleCount
 * samples of a pixel fall one in each stratum of it, in an order shuffled independently
 * per pixel and dimension so that dimensions do not correlate. 1D dimensions have
 * sampleCount strata; 2D dimensions a grid of nx × ny = sampleCount cells, nx the
 * largest divisor of sampleCount at most its square root (a square count gives a square
 * grid, a power of two a 1:2 grid, a prime count strips). Samples past sampleCount (a
 * longer render) start another, independently shuffled round of strata.
 *
 * No parameters of its own: it takes those of every sampler, sampleCount, seed,
 * maxTolerance and minSamples (adaptive sampling; see docs/plugins.md).
 *
 *   <sampler type="stratified">
 *       <integer name="sampleCount" value="64"/>
 *   </sampler>
 */
#include <nori/hash.h>
#include <nori/lowdiscrepancy.h>
#include <nori/sampler.h>

namespace nori {
namespace {

class Stratified : public Sampler {
public:
    explicit Stratified(const PropertyList &props) { (void)props; }

    std::unique_ptr<Sampler> clone() const override { return std::make_unique<Stratified>(*this); }

    float next1D() override {
        const uint32_t count = strataCount();
        const uint64_t hash = dimensionHash();
        const uint32_t stratum =
            permutationElement(m_sampleIndex % count, count, static_cast<uint32_t>(hash));
        return (static_cast<float>(stratum) + jitter(hash, 0)) / static_cast<float>(count);
    }

    Point2f next2D() override {
        const uint32_t count = strataCount();
        const uint64_t hash = dimensionHash();
        const uint32_t columns = gridColumns(count);
        const uint32_t rows = count / columns;
        const uint32_t cell =
            permutationElement(m_sampleIndex % count, count, static_cast<uint32_t>(hash));
        const uint32_t column = cell % columns, row = cell / columns;
        return Point2f((static_cast<float>(column) + jitter(hash, 0)) / static_cast<float>(columns),
                       (static_cast<float>(row) + jitter(hash, 1)) / static_cast<float>(rows));
    }

    std::string toString() const override {
        return fmt::format("Stratified[{}]", commonPropertiesString());
    }

private:
    uint32_t strataCount() const {
        return static_cast<uint32_t>(std::min<size_t>(m_sampleCount, UINT32_MAX));
    }

    /// Columns of the 2D grid of `count` cells: the largest divisor of count at most
    /// √count (found once per count).
    uint32_t gridColumns(uint32_t count) {
        if (count != m_gridCount) {
            m_gridCount = count;
            m_gridColumns = static_cast<uint32_t>(std::sqrt(static_cast<double>(count)));
            while (count % m_gridColumns != 0)
                --m_gridColumns;
        }
        return m_gridColumns;
    }

    /// The shuffle of this dimension and round of strata in this pixel; advances the
    /// dimension.
    uint64_t dimensionHash() {
        const uint32_t round = m_sampleIndex / strataCount();
        return hashValues(m_seed, m_pixel.x(), m_pixel.y(), m_dimension++, round);
    }

    /// The position inside the stratum of the current sample: coordinate `axis`.
    float jitter(uint64_t dimensionHash, int axis) const {
        const uint64_t bits = hashValues(dimensionHash, m_sampleIndex, axis);
        return fractionToFloat(static_cast<uint32_t>(bits >> 32));
    }

    uint32_t m_gridCount = 0, m_gridColumns = 1;
};

NORI_REGISTER_CLASS(Stratified, "stratified");

} // namespace
} // namespace nori
