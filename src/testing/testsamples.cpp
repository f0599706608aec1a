#include <nori/testsamples.h>

#include <nori/common.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>

namespace nori {

namespace {

/// FullTestSamples alive (tests run one at a time; their loops may read it from any thread).
std::atomic<int> g_fullSampleScopes{0};

double readTestSampleScale() {
    const char *text = std::getenv("NORI_TEST_SAMPLE_SCALE");
    if (text == nullptr || *text == '\0')
        return 1.0;
    char *end = nullptr;
    const double scale = std::strtod(text, &end);
    if (*end != '\0' || !(scale > 0.0 && scale <= 1.0))
        throw NoriException("NORI_TEST_SAMPLE_SCALE must be a number in (0, 1], got '{}'", text);
    return scale;
}

} // namespace

double testSampleScale() {
    // The environment is read once (a C++11 static is initialised once, thread-safely); a
    // bad value throws on every call, as the static is then never initialised.
    static const double scale = readTestSampleScale();
    return g_fullSampleScopes > 0 ? 1.0 : scale;
}

FullTestSamples::FullTestSamples() {
    ++g_fullSampleScopes;
}

FullTestSamples::~FullTestSamples() {
    --g_fullSampleScopes;
}

size_t scaledTestSamples(size_t count, size_t minimum) {
    const double scaled = std::round(testSampleScale() * static_cast<double>(count));
    return std::max(minimum, static_cast<size_t>(scaled));
}

double scaledPlantedBias(double bias) {
    return bias / std::sqrt(testSampleScale());
}

std::string testSampleScaleNotice() {
    if (testSampleScale() == 1.0)
        return {};
    return fmt::format("statistical tests at NORI_TEST_SAMPLE_SCALE={:g} of their samples (less "
                       "power: docs/testing.md)\n",
                       testSampleScale());
}

} // namespace nori
