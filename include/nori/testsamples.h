// The one knob of the statistical tests' cost: NORI_TEST_SAMPLE_SCALE, a factor in (0, 1]
// by which every χ² test, t-test and agreement test multiplies its sample counts (unset:
// 1). scripts/sanitize.sh sets it, as the sanitizers run the renders ten times slower.
// Significance levels stay as they are, so a correct sampler still passes with the same
// probability; what drops is power: a test then sees only biases about 1/√scale times
// larger, and the agreement tests ask for that much less power (docs/testing.md).
#pragma once

#include <cstddef>
#include <string>

namespace nori {

/// NORI_TEST_SAMPLE_SCALE, read once; throws NoriException naming the variable when it is
/// not a number in (0, 1]. 1 while a FullTestSamples lives.
double testSampleScale();

/// While one lives, the statistical tests run at their full counts whatever the knob says:
/// for a test whose assertions need every sample (a negative control no longer rejected at
/// a tenth, estimates whose rare large values make them normal only at the full count).
/// Each use says which.
class FullTestSamples {
public:
    FullTestSamples();
    ~FullTestSamples();
    FullTestSamples(const FullTestSamples &) = delete;
    FullTestSamples &operator=(const FullTestSamples &) = delete;
};

/// `count` multiplied by testSampleScale(), rounded, and at least `minimum`.
size_t scaledTestSamples(size_t count, size_t minimum = 2);

/// A negative control's planted relative bias (0.02: 2 % too bright), grown by
/// 1/√testSampleScale(): the standard errors grow by that factor at reduced counts, so the
/// control stays as many standard errors away as at full counts and keeps its power.
double scaledPlantedBias(double bias);

/// A line saying that the statistical tests run at reduced counts, or "" at full counts
/// (the programs that run tests print it first, as their verdicts then have less power).
std::string testSampleScaleNotice();

} // namespace nori
