// The statistics toolkit: distribution functions against tables, quadrature, Pearson's
// test, and the χ² test of every warp and distribution — each with negative controls
// (wrong pdfs, missing Jacobians, biased samplers) that the test must reject.
#include <nori/dpdf.h>
#include <nori/pcg32.h>
#include <nori/samplingroutines.h>
#include <nori/warp.h>

#include "testutil.h"

#include <catch2/catch.hpp>

#include <iostream>

using namespace nori;
using Catch::Contains;
using nori::testing::errorOf;

namespace {

ChiSquareOptions testOptions(uint64_t seed = 1) {
    ChiSquareOptions options;
    options.seed = seed;
    options.sampleCount = 200000;
    return options;
}

/// Runs a negative control: the test must reject it. Prints the p-value for the record.
void expectRejected(const std::string &name, const SamplingRoutine &routine) {
    const ChiSquareReport report = runChiSquareTest(routine, testOptions(7));
    std::cout << fmt::format("negative control '{}': p-value {:.3g} ({})\n", name,
                             report.result.pValue, report.result.message);
    INFO(name << ": " << report.result.message);
    CHECK_FALSE(report.result.passed);
}

} // namespace

TEST_CASE("Distribution functions match published tables", "[statistics]") {
    // χ² quantiles (NIST/SEMATECH e-Handbook, table 1.3.6.7.4).
    CHECK(chiSquareCdf(3.841, 1) == Approx(0.95).margin(1e-4));
    CHECK(chiSquareCdf(18.307, 10) == Approx(0.95).margin(1e-4));
    CHECK(chiSquareCdf(124.342, 100) == Approx(0.95).margin(1e-4));
    CHECK(chiSquareCdf(0.0, 5) == 0.0);
    // Student-t quantiles (table 1.3.6.7.2): t_{0.975} for ν = 1, 10, 100.
    CHECK(studentTCdf(12.706, 1) == Approx(0.975).margin(1e-4));
    CHECK(studentTCdf(2.228, 10) == Approx(0.975).margin(1e-4));
    CHECK(studentTCdf(1.984, 100) == Approx(0.975).margin(1e-4));
    CHECK(studentTCdf(-2.228, 10) == Approx(0.025).margin(1e-4));
    CHECK(studentTCdf(0.0, 7) == Approx(0.5));
    // Closed forms: P(1, x) = 1 − e^{−x}; I_x(a, 1) = x^a.
    CHECK(incompleteGammaP(1.0, 2.5) == Approx(1.0 - std::exp(-2.5)).epsilon(1e-12));
    CHECK(incompleteGammaP(3.0, 40.0) == Approx(1.0).epsilon(1e-12));
    // Q(a, x) in the far tail: Q(1, x) = e^{−x}, which 1 − P would round to 0.
    CHECK(incompleteGammaQ(1.0, 800.0) == Approx(std::exp(-800.0)).epsilon(1e-9));
    CHECK(incompleteGammaQ(2.5, 1.0) == Approx(1.0 - incompleteGammaP(2.5, 1.0)).epsilon(1e-12));
    CHECK(incompleteBeta(2.5, 1.0, 0.3) == Approx(std::pow(0.3, 2.5)).epsilon(1e-12));
    CHECK(incompleteBeta(0.5, 0.5, 0.5) == Approx(0.5).epsilon(1e-12));
    // Šidák: 1 − (1 − α)^{1/n}.
    CHECK(sidakCorrection(0.01, 1) == Approx(0.01));
    CHECK(sidakCorrection(0.05, 10) == Approx(0.0051162).epsilon(1e-4));
}

TEST_CASE("Student's t-test computes Nori 2's statistic with its variance floor", "[statistics]") {
    // t = |mean − ref|·√(n / max(variance, 1e-5)).
    const StudentTResult noisy = studentTTest(0.51, 0.04, 400, 0.5, 0.01);
    CHECK(noisy.t == Approx(0.01 * std::sqrt(400 / 0.04)));
    CHECK(noisy.passed); // t = 1
    // A zero-variance estimate uses the floor: 0.0631777 vs the staff's 0.06317.
    const StudentTResult exact = studentTTest(0.0631777, 0.0, 100000, 0.06317, 0.01);
    CHECK(exact.t == Approx(7.7e-6 * std::sqrt(100000 / 1e-5)).epsilon(1e-3));
    CHECK(exact.passed);
    // Negative control: the same estimate against a reference 1e-4 away, t = 10.
    CHECK_FALSE(studentTTest(0.0631777, 0.0, 100000, 0.0630777, 0.01).passed);
    // p-value of t = 1.984 with 100 degrees of freedom, two-sided: 0.05.
    CHECK(studentTTest(1.0 + 1.984 / std::sqrt(101.0), 1.0, 101, 1.0, 0.01).pValue ==
          Approx(0.05).margin(1e-4));
}

TEST_CASE("Adaptive Simpson integrates smooth and kinked functions", "[statistics]") {
    CHECK(adaptiveSimpson2D([](double x, double y) { return x * y; }, 0, 0, 1, 1) ==
          Approx(0.25).epsilon(1e-10));
    CHECK(adaptiveSimpson2D([](double x, double y) { return std::sin(x) * std::cos(y); }, 0, 0,
                            kPiDouble, kPiDouble / 2) == Approx(2.0).epsilon(1e-6));
    // A kink inside the cell (|x − 0.3|) is handled by subdivision.
    CHECK(adaptiveSimpson2D([](double x, double) { return std::abs(x - 0.3); }, 0, 0, 1, 1) ==
          Approx(0.29).epsilon(1e-5));
}

TEST_CASE("Pearson's test pools sparse cells and rejects impossible samples", "[statistics]") {
    const std::vector<double> expected = {100, 100, 100, 2, 2, 2};
    const ChiSquareResult good = pearsonChiSquareTest({98, 105, 97, 3, 1, 2}, expected, 5, 0.01);
    CHECK(good.passed);
    CHECK(good.pooledCells == 3);
    CHECK(good.degreesOfFreedom == 3); // three cells plus one pool, minus one
    const ChiSquareResult bad = pearsonChiSquareTest({150, 60, 90, 2, 2, 2}, expected, 5, 0.01);
    CHECK_FALSE(bad.passed);
    const ChiSquareResult impossible = pearsonChiSquareTest({100, 100, 1}, {100, 101, 0}, 5, 0.01);
    CHECK_FALSE(impossible.passed);
    CHECK_THAT(impossible.message, Contains("pdf integrates to 0"));
}

TEST_CASE("Every warp draws from its pdf", "[statistics][warp]") {
    for (const NamedWarp &warp : namedWarps()) {
        std::vector<float> parameters = {warp.defaultParameter};
        if (warp.name == "beckmann" || warp.name == "ggx" || warp.name == "gtr1")
            parameters = {0.05f, 0.3f, 0.9f};
        if (warp.name == "hg")
            parameters = {-0.6f, 0.0f, 0.8f};
        if (warp.name == "sphere_cap")
            parameters = {-0.5f, 0.5f, 0.95f};
        if (warp.name == "cosine_power")
            parameters = {0.0f, 1.0f, 20.0f, 300.0f};
        for (float parameter : parameters) {
            const ChiSquareReport report = runChiSquareTest(warp.routine(parameter), testOptions());
            INFO(warp.name << " " << parameter << ": " << report.result.message);
            CHECK(report.result.passed);
            // The pdf is normalised: its integral over the domain is 1 (Simpson's error on
            // these smooth densities, with 200 bins, is below 1e-3).
            CHECK(report.pdfIntegral == Approx(1.0).margin(2e-3));
        }
    }
}

TEST_CASE("Negative controls: every warp's test rejects a pdf off by a factor 0.9",
          "[statistics][negative]") {
    for (const NamedWarp &warp : namedWarps()) {
        SamplingRoutine wrong = warp.routine(warp.defaultParameter);
        const auto pdf = wrong.pdf;
        wrong.pdf = [pdf](const Vector3f &p) { return 0.9 * pdf(p); };
        expectRejected(warp.name + " with its pdf scaled by 0.9", wrong);
    }
}

TEST_CASE("Negative controls: the χ² test rejects wrong warps", "[statistics][negative]") {
    SamplingRoutine missingJacobian;
    missingJacobian.domain = SampleDomain::CenteredSquare;
    missingJacobian.sample = [](const Point2f &u, Vector3f &p) {
        // r = u instead of √u: the polar map's Jacobian is missing.
        const float phi = 2.0f * kPi * u.y();
        p = Vector3f(u.x() * std::cos(phi), u.x() * std::sin(phi), 0.0f);
        return true;
    };
    missingJacobian.pdf = [](const Vector3f &p) {
        return Warp::squareToUniformDiskPdf(Point2f(p.x(), p.y()));
    };
    expectRejected("disk without the sqrt (missing Jacobian)", missingJacobian);

    SamplingRoutine scaledPdf = findWarp("cosine_hemisphere").routine(0.0f);
    scaledPdf.pdf = [](const Vector3f &v) { return 0.95 * Warp::squareToCosineHemispherePdf(v); };
    expectRejected("cosine hemisphere, pdf off by a factor 0.95", scaledPdf);

    SamplingRoutine overOne = findWarp("uniform_sphere").routine(0.0f);
    overOne.pdf = [](const Vector3f &v) { return 1.2 * Warp::squareToUniformSpherePdf(v); };
    expectRejected("uniform sphere, pdf integrating to 1.2", overOne);

    SamplingRoutine biasedBeckmann = findWarp("beckmann").routine(0.3f);
    biasedBeckmann.pdf = [](const Vector3f &m) { return Warp::squareToBeckmannPdf(m, 0.33f); };
    expectRejected("Beckmann sampled with alpha 0.3, pdf of 0.33", biasedBeckmann);

    SamplingRoutine flippedHG = findWarp("hg").routine(0.5f);
    flippedHG.pdf = [](const Vector3f &v) { return Warp::squareToHenyeyGreensteinPdf(v, -0.5f); };
    expectRejected("Henyey-Greenstein with the sign of g flipped in the pdf", flippedHG);

    SamplingRoutine uniformForCosine = findWarp("uniform_hemisphere").routine(0.0f);
    uniformForCosine.pdf = [](const Vector3f &v) { return Warp::squareToCosineHemispherePdf(v); };
    expectRejected("uniform hemisphere samples against the cosine pdf", uniformForCosine);

    SamplingRoutine phongNormalisation = findWarp("cosine_power").routine(20.0f);
    phongNormalisation.pdf = [](const Vector3f &v) {
        // The classic slip: (n + 2)/2π, the normalisation of the cos-weighted lobe.
        return Warp::squareToCosinePowerHemispherePdf(v, 20.0f) * 22.0f / 21.0f;
    };
    expectRejected("cosine power 20 with (n + 2)/2π for (n + 1)/2π", phongNormalisation);

    SamplingRoutine ggxAsBeckmann = findWarp("ggx").routine(0.3f);
    ggxAsBeckmann.pdf = [](const Vector3f &m) { return Warp::squareToBeckmannPdf(m, 0.3f); };
    expectRejected("GGX samples against the Beckmann pdf", ggxAsBeckmann);

    SamplingRoutine wrongTent = findWarp("tent").routine(0.0f);
    wrongTent.sample = [](const Point2f &u, Vector3f &p) {
        // A triangle-shaped density needs the inverse CDF; 2u − 1 is uniform instead.
        p = Vector3f(2.0f * u.x() - 1.0f, Warp::squareToTent(u).y(), 0.0f);
        return true;
    };
    expectRejected("tent sampled uniformly along x", wrongTent);

    SamplingRoutine capFullSphere = findWarp("sphere_cap").routine(0.5f);
    capFullSphere.pdf = [](const Vector3f &v) { return Warp::squareToUniformSpherePdf(v); };
    expectRejected("sphere cap against the full sphere's pdf", capFullSphere);

    SamplingRoutine gtr1AsGgx = findWarp("gtr1").routine(0.3f);
    gtr1AsGgx.pdf = [](const Vector3f &m) { return Warp::squareToGGXPdf(m, 0.3f); };
    expectRejected("GTR1 samples against the GGX pdf", gtr1AsGgx);

    SamplingRoutine outside = findWarp("square").routine(0.0f);
    outside.sample = [](const Point2f &u, Vector3f &p) {
        p = Vector3f(1.01f * u.x(), u.y(), 0.0f); // 1% of samples leave the square
        return true;
    };
    expectRejected("square warp that leaves the domain", outside);
}

TEST_CASE("DiscretePDF samples each entry with its probability", "[statistics][distribution]") {
    DiscretePDF pdf;
    const std::vector<float> weights = {1, 0, 3, 0.5f, 5, 0, 2.5f};
    for (float w : weights)
        pdf.append(w);
    CHECK(pdf.normalize() == Approx(12.0f));
    CHECK(pdf[2] == Approx(0.25f));
    CHECK(pdf[1] == 0.0f);

    PCG32 random(3, 4);
    const int n = 120000;
    std::vector<double> observed(weights.size(), 0.0), expected(weights.size());
    std::vector<double> reused(10, 0.0);
    for (int i = 0; i < n; ++i) {
        float u = random.nextFloat();
        const size_t index = pdf.sampleReuse(u);
        observed[index] += 1.0;
        // The rescaled u is again uniform on [0, 1).
        reused[std::min<size_t>(static_cast<size_t>(u * 10.0f), 9)] += 1.0;
    }
    for (size_t i = 0; i < weights.size(); ++i)
        expected[i] = n * pdf[i];
    CHECK(pearsonChiSquareTest(observed, expected, 5, 0.01).passed);
    CHECK(pearsonChiSquareTest(reused, std::vector<double>(10, n / 10.0), 5, 0.01).passed);

    // Negative control: the probabilities shifted by one entry.
    std::vector<double> shifted(weights.size());
    for (size_t i = 0; i < weights.size(); ++i)
        shifted[i] = n * pdf[(i + 1) % weights.size()];
    const ChiSquareResult wrong = pearsonChiSquareTest(observed, shifted, 5, 0.01);
    std::cout << fmt::format("negative control 'DiscretePDF with shifted pmf': p-value {:.3g}\n",
                             wrong.pValue);
    CHECK_FALSE(wrong.passed);

    // Zero weights after the last positive one are never drawn, not even by the largest u
    // below 1: w·(1/w) is 1 − 2⁻²⁴ for w = 1.85, and normalising by that product left the
    // trailing entries that sliver of probability.
    DiscretePDF trailing;
    for (float w : {0.0f, 1.85f, 0.0f, 0.0f})
        trailing.append(w);
    trailing.normalize();
    CHECK(trailing.sample(1.0f - 0x1p-24f) == 1);
    CHECK(trailing[1] == 1.0f);
    CHECK(trailing[3] == 0.0f);

    DiscretePDF empty;
    empty.append(0.0f);
    CHECK_THAT(errorOf([&] { empty.normalize(); }), Contains("cannot normalise"));
    CHECK_THAT(errorOf([&] { empty.append(-1.0f); }), Contains("negative"));
}

TEST_CASE("Distribution1D and Distribution2D sample their piecewise-constant densities",
          "[statistics][distribution]") {
    const Distribution1D line({0.5f, 2.0f, 0.0f, 1.0f, 4.0f});
    CHECK(line.integral() == Approx(7.5f / 5.0f));
    SamplingRoutine continuous;
    continuous.domain = SampleDomain::UnitSquare;
    continuous.sample = [&](const Point2f &u, Vector3f &p) {
        float pdf;
        size_t cell;
        p = Vector3f(line.sampleContinuous(u.x(), pdf, cell), u.y(), 0.0f);
        return pdf == line.pdf(p.x());
    };
    continuous.pdf = [&](const Vector3f &p) { return line.pdf(p.x()); };
    ChiSquareOptions options = testOptions();
    options.resolution = 20; // bins nest in the 5 cells
    CHECK(runChiSquareTest(continuous, options).result.passed);

    // Negative control: the pdf of other weights (two cells swapped).
    const Distribution1D swapped({0.5f, 1.0f, 0.0f, 2.0f, 4.0f});
    SamplingRoutine wrongLine = continuous;
    wrongLine.pdf = [&](const Vector3f &p) { return swapped.pdf(p.x()); };
    const ChiSquareReport wrong1D = runChiSquareTest(wrongLine, options);
    std::cout << fmt::format("negative control 'Distribution1D pdf with two cells swapped': "
                             "p-value {:.3g}\n",
                             wrong1D.result.pValue);
    CHECK_FALSE(wrong1D.result.passed);

    std::vector<float> image(8 * 6);
    for (size_t i = 0; i < image.size(); ++i)
        image[i] = static_cast<float>((i * 7) % 5);          // some cells are 0
    std::fill(image.begin() + 16, image.begin() + 24, 0.0f); // row 2 is black
    const Distribution2D plane(image, 8, 6);
    SamplingRoutine planar;
    planar.domain = SampleDomain::UnitSquare;
    planar.sample = [&](const Point2f &u, Vector3f &p) {
        float pdf;
        const Point2f q = plane.sampleContinuous(u, pdf);
        p = Vector3f(q.x(), q.y(), 0.0f);
        return std::abs(pdf - plane.pdf(q)) <= 1e-5f * pdf;
    };
    planar.pdf = [&](const Vector3f &p) { return plane.pdf(Point2f(p.x(), p.y())); };
    options.resolution = 24; // 3x4 bins per cell
    CHECK(runChiSquareTest(planar, options).result.passed);

    // Negative control: a pdf that forgets the conditional (uses the marginal only).
    SamplingRoutine marginalOnly = planar;
    std::vector<float> rows(6, 0.0f);
    for (size_t r = 0; r < 6; ++r)
        for (size_t c = 0; c < 8; ++c)
            rows[r] += image[r * 8 + c];
    const Distribution1D marginal(rows);
    marginalOnly.pdf = [&](const Vector3f &p) { return marginal.pdf(p.y()); };
    const ChiSquareReport wrong = runChiSquareTest(marginalOnly, options);
    std::cout << fmt::format("negative control 'Distribution2D pdf without the conditional': "
                             "p-value {:.3g}\n",
                             wrong.result.pValue);
    CHECK_FALSE(wrong.result.passed);
}
