// Environment maps: direction sampling under χ² for a constant map, a one-hot map, a
// small bright sun and the procedural sky (with a control whose pdf forgets sin θ), and
// the radiance a diffuse floor receives against closed forms.
#include "testutil.h"

#include "testing/agreementscenes.h"

#include <nori/chisquare.h>
#include <nori/emitter.h>
#include <nori/parser.h>
#include <nori/pcg32.h>
#include <nori/samplingroutines.h>
#include <nori/warp.h>

#include <catch2/catch.hpp>

using namespace nori;
using namespace nori::testing;

namespace {

/// Writes a width×height lat-long map whose texel (x, y) is value(x, y), as EXR.
template <typename F>
std::string writeMap(const TempDir &dir, const std::string &name, int width, int height, F value) {
    Bitmap image(Eigen::Vector2i(width, height));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            image(y, x) = value(x, y);
    std::string file = (dir.path() / name).string();
    image.saveEXR(file);
    return file;
}

std::shared_ptr<Emitter> loadEnvmap(const std::string &file, const std::string &extra = "") {
    auto emitter = std::dynamic_pointer_cast<Emitter>(loadFromXMLString(
        fmt::format(R"(<emitter type="envmap"><string name="filename" value="{}"/>{}</emitter>)",
                    file, extra)));
    REQUIRE(emitter);
    return emitter;
}

} // namespace

TEST_CASE("Environment map sampling: weights are eval/pdf and pdf matches sample()", "[envmap]") {
    TempDir dir;
    const std::string file = writeMap(dir, "ramp.exr", 16, 8, [](int x, int y) {
        return Color3f(0.1f + x * 0.05f, 0.2f + y * 0.1f, 0.3f);
    });
    auto envmap = loadEnvmap(
        file, R"(<transform name="toWorld"><rotate axis="1, 1, 0" angle="30"/></transform>)");
    PCG32 random(3, 4);
    for (int i = 0; i < 2000; ++i) {
        EmitterQueryRecord lRec(Point3f(0.2f, 0.1f, -0.3f));
        const float u = random.nextFloat();
        const Color3f weight = envmap->sample(lRec, Point2f(u, random.nextFloat()));
        if ((weight == 0.0f).all())
            continue;
        INFO("sample " << i << " toward " << lRec.wi.transpose());
        REQUIRE(envmap->pdf(lRec) == Approx(lRec.pdf).epsilon(1e-3));
        const Color3f expected = envmap->eval(lRec) / lRec.pdf;
        REQUIRE(weight.isApprox(expected, 1e-3f));
    }
}

TEST_CASE("A direction sampled in a texel reads back as that texel, edges and poles included",
          "[envmap]") {
    // One bright texel: every sample is drawn in it, so every sample must come back with
    // its radiance. Directions drawn at a texel's edge (primary samples 0 and 1 − 2⁻²⁴) or
    // beside a pole used to round into a black neighbour on their way back to (u, v): the
    // sample then weighed 0 (and a sky texel's sample beside a sun weighed the sun's
    // radiance over the sky's density).
    TempDir dir;
    const float edges[] = {0.0f, 0x1p-24f, 0.5f, 1.0f - 0x1p-24f};
    const std::pair<int, int> texels[] = {{5, 0}, {15, 3}, {0, 4}, {9, 7}};
    for (const std::pair<int, int> &texel : texels)
        for (const char *rotation :
             {"", R"(<transform name="toWorld"><rotate axis="1, 1, 0" angle="30"/></transform>)"}) {
            const int column = texel.first, row = texel.second;
            CAPTURE(column, row, rotation);
            const std::string file =
                writeMap(dir, fmt::format("texel{}{}.exr", column, row), 16, 8, [&](int x, int y) {
                    return Color3f(x == column && y == row ? 40.0f : 0.0f);
                });
            auto envmap = loadEnvmap(file, rotation);
            PCG32 random(5, 6);
            int lost = 0, drawn = 0;
            auto check = [&](const Point2f &sample) {
                EmitterQueryRecord lRec(Point3f(0.0f, 0.0f, 0.0f));
                const Color3f weight = envmap->sample(lRec, sample);
                ++drawn;
                // pdf() finds sin θ from the float direction, whose components a rotation
                // and a normalisation leave within 10⁻⁶ of the drawn one: near a pole (sin θ
                // of 10⁻⁵ in the edge samples) the two densities differ by that much over
                // sin θ, the drawn sin θ being p(u, v)/(2π² pdf) with p(u, v) = 16·8.
                const double sinTheta = 128.0 / (2.0 * kPi * kPi * lRec.pdf);
                const bool kept =
                    (weight * lRec.pdf).isApprox(Color3f(40.0f), 1e-4f) &&
                    std::abs(envmap->pdf(lRec) - lRec.pdf) <= (1e-4 + 1e-6 / sinTheta) * lRec.pdf;
                if (!kept && ++lost <= 3)
                    UNSCOPED_INFO("sample " << sample.transpose() << ": weight "
                                            << weight.transpose() << ", pdf " << lRec.pdf
                                            << ", pdf() " << envmap->pdf(lRec));
            };
            for (const float a : edges)
                for (const float b : edges)
                    check(Point2f(a, b));
            for (int i = 0; i < 200000; ++i) {
                // Half the samples within 10⁻⁵ of an edge of the texel in u or v.
                Point2f sample(random.nextFloat(), random.nextFloat());
                if (i % 2 == 1)
                    sample[i % 4 == 1 ? 0 : 1] =
                        i % 8 < 4 ? 1e-5f * sample.x()
                                  : std::min(1.0f - 1e-5f * sample.y(), 1.0f - 0x1p-24f);
                check(sample);
            }
            CHECK(lost == 0);
            CHECK(drawn > 200000);
        }
}

TEST_CASE("Environment map direction sampling passes chi-square, forgetting sin(theta) fails",
          "[envmap][chi2]") {
    TempDir dir;
    const std::vector<std::pair<std::string, std::string>> maps = {
        {"constant", writeMap(dir, "constant.exr", 32, 16, [](int, int) { return Color3f(1.0f); })},
        {"one-hot", writeMap(dir, "onehot.exr", 32, 16,
                             [](int x, int y) { return Color3f(x == 9 && y == 5 ? 1.0f : 0.0f); })},
        {"sun", writeMap(dir, "sun.exr", 128, 64,
                         [](int x, int y) {
                             const bool sun = std::abs(x - 40) <= 1 && std::abs(y - 20) <= 1;
                             return Color3f(sun ? 500.0f : 0.2f);
                         })},
        {"sky", std::string(NORI_SOURCE_DIR) + "/scenes/textured/textures/sky.exr"}};
    ChiSquareOptions options;
    options.sampleCount = 500000;
    options.significanceLevel = sidakCorrection(0.01, static_cast<int>(maps.size()));
    for (const auto &[name, file] : maps) {
        CAPTURE(name);
        auto envmap = loadEnvmap(
            file, R"(<transform name="toWorld"><rotate axis="0, 0, 1" angle="20"/></transform>)");
        options.seed += 1;
        const ChiSquareReport report =
            runChiSquareTest(emitterRoutine(*envmap, Point3f(0.0f, 0.0f, 0.0f)), options);
        INFO(report.result.message);
        CHECK(report.result.passed);
    }
    // The control: for the constant map p(u, v) = 1, so p(u, v)/(2π²), the density without
    // the 1/sin θ of the change of variables, is this constant.
    auto envmap = loadEnvmap(maps[0].second);
    SamplingRoutine wrong = emitterRoutine(*envmap, Point3f(0.0f, 0.0f, 0.0f));
    wrong.pdf = [](const Vector3f &) -> double { return 1.0 / (2.0 * kPi * kPi); };
    options.seed += 1;
    CHECK_FALSE(runChiSquareTest(wrong, options).result.passed);
}

namespace {

/// The floor under the environment map `file`.
std::shared_ptr<Scene> floorUnder(const std::string &file, const std::string &integrator,
                                  const std::string &emitterExtra = "",
                                  const std::string &sceneExtra = "") {
    return litFloor(integrator, fmt::format(R"(<emitter type="envmap"><string name="filename"
        value="{}"/>{}</emitter> {})",
                                            file, emitterExtra, sceneExtra));
}

void tTest(Scene &scene, double reference, size_t samples) {
    const PixelTTest test = tTestPixel(scene, reference, samples);
    INFO(test.summary());
    CHECK(test.result.passed);
}

const std::vector<std::string> kEnvironmentIntegrators = {"direct_mats", "direct_ems", "direct_mis",
                                                          "path_mats",   "path_ems",   "path_mis"};

} // namespace

TEST_CASE("A diffuse floor under a constant environment reflects albedo times L",
          "[envmap][ttest]") {
    TempDir dir;
    const std::string file =
        writeMap(dir, "constant.exr", 32, 16, [](int, int) { return Color3f(2.0f); });
    for (const std::string &integrator : kEnvironmentIntegrators) {
        CAPTURE(integrator);
        tTest(*floorUnder(file, integrator), 0.5 * 2.0, 20000);
    }
    // The `constant` environment is the same light.
    for (const std::string &integrator : kEnvironmentIntegrators) {
        CAPTURE(integrator);
        tTest(*litFloor(integrator,
                        R"(<emitter type="constant"><color name="radiance" value="2"/></emitter>)"),
              0.5 * 2.0, 20000);
    }
    // The same map as Radiance RGBE: 2.0 is stored exactly (mantissa 128, exponent 130).
    // BSDF sampling then weighs every sample albedo·L = 1 up to float rounding (decoded with
    // Ward's (m + 0.5), the map read 2.0078 and every sample 1.0039); the other strategies
    // agree within their noise.
    Bitmap constantMap(Eigen::Vector2i(32, 16));
    constantMap.setConstant(Color3f(2.0f));
    const std::string hdrFile = (dir.path() / "constant.hdr").string();
    constantMap.saveHDR(hdrFile);
    for (const char *integrator : {"direct_mats", "path_mats"}) {
        CAPTURE(integrator);
        const RunningMoments exact = estimatePixel(*floorUnder(hdrFile, integrator), 2000);
        CHECK(exact.mean == Approx(0.5 * 2.0).epsilon(1e-5));
        CHECK(exact.variance() < 1e-10);
    }
    for (const std::string &integrator : kEnvironmentIntegrators) {
        CAPTURE(integrator);
        tTest(*floorUnder(hdrFile, integrator), 0.5 * 2.0, 20000);
    }
    // The control: a reference 3% off is rejected.
    const RunningMoments moments = estimatePixel(*floorUnder(file, "path_mis"), 20000);
    CHECK_FALSE(studentTTest(moments.mean, moments.variance(), moments.count, 1.03, 0.01).passed);
}

TEST_CASE("Under a one-texel environment the floor gets L times the texel's projected solid "
          "angle",
          "[envmap][ttest]") {
    TempDir dir;
    // Texel (x, y) = (5, 3) of 16×8: θ from 3π/8 to 4π/8 above the floor (+y up).
    const std::string file = writeMap(dir, "texel.exr", 16, 8, [](int x, int y) {
        return Color3f(x == 5 && y == 3 ? 40.0f : 0.0f);
    });
    // E = L ∫∫ cos θ sin θ dθ dφ = L (2π/16) (sin²θ1 − sin²θ0)/2; radiance = albedo/π · E.
    const double theta0 = 3.0 * kPi / 8.0, theta1 = 4.0 * kPi / 8.0;
    const double irradiance = 40.0 * (2.0 * kPi / 16.0) *
                              (std::pow(std::sin(theta1), 2) - std::pow(std::sin(theta0), 2)) / 2.0;
    const double reference = 0.5 * kInvPi * irradiance;
    for (const char *integrator : {"direct_ems", "direct_mis", "path_ems", "path_mis"}) {
        CAPTURE(integrator);
        tTest(*floorUnder(file, integrator), reference, 20000);
    }
    // The control: the irradiance of the texel's centre direction times its solid angle
    // (the usual approximation, 2% off for this texel; its error grown by 1/√scale at
    // reduced test counts) is rejected.
    const double approximate = 0.5 * kInvPi * 40.0 * (2.0 * kPi / 16.0) *
                               (std::cos(theta0) - std::cos(theta1)) *
                               std::cos(0.5 * (theta0 + theta1));
    const PixelTTest wrong =
        tTestPixel(*floorUnder(file, "path_mis"),
                   reference * (1.0 + scaledPlantedBias(approximate / reference - 1.0)), 20000);
    INFO(wrong.summary());
    CHECK_FALSE(wrong.result.passed);
    // Rotated upside down by toWorld, the texel is below the floor: no light.
    const RunningMoments below = estimatePixel(
        *floorUnder(
            file, "path_mis",
            R"(<transform name="toWorld"><rotate axis="1, 0, 0" angle="180"/></transform>)"),
        2000);
    CHECK(below.mean == 0.0);
    // Rotated by 180° about the vertical, the same irradiance (the floor is symmetric).
    tTest(*floorUnder(
              file, "path_mis",
              R"(<transform name="toWorld"><rotate axis="0, 1, 0" angle="180"/></transform>)"),
          reference, 20000);
}

TEST_CASE("path_mats, path_ems and path_mis agree under a sky with a sun", "[envmap][ttest]") {
    // The matrix's sky: a sun of 3×3 texels of radiance 60 holds about three quarters of
    // the light on the floor, and BSDF sampling finds it about once in 1400 samples, so
    // path_mats takes 5·10⁶ samples (its standard error 0.33 %) against 1.5·10⁶ of path_mis
    // (0.08 %). Each pair is compared by Welch's z at 1 % over the three (Šidák), and must
    // have the power to see the 1.6 % that path_mats once lost under this sky (95 %); at
    // reduced test counts, 1/√scale times that, as the control's dimming.
    TempDir dir;
    const std::string map = (dir.path() / "sky.exr").string(),
                      dimmer = (dir.path() / "dimmer.exr").string();
    skyMap(60.0f)(map);
    skyMap(60.0f * static_cast<float>(1.0 - scaledPlantedBias(0.02)))(dimmer);
    const std::string sphere = R"(<mesh type="sphere"><point name="center" value="0.6, 0.5, -0.2"/>
        <float name="radius" value="0.5"/></mesh>)";
    const double level = sidakCorrection(0.01, 3);
    // The two-sided normal quantile of `level` (erfc(z/√2) = level, by bisection), and
    // the one-sided 95 % quantile for the power.
    double low = 0.0, high = 10.0;
    for (int i = 0; i < 100; ++i)
        (std::erfc(0.5 * (low + high) / std::sqrt(2.0)) > level ? low : high) = 0.5 * (low + high);
    const double critical = 0.5 * (low + high), power = 1.6448536;
    const auto compare = [&](const RunningMoments &a, const RunningMoments &b) {
        const double sigma =
            std::sqrt(a.variance() / double(a.count) + b.variance() / double(b.count));
        return std::pair{(a.mean - b.mean) / sigma, (critical + power) * sigma / b.mean};
    };
    const RunningMoments reference =
        estimatePixel(*floorUnder(map, "path_mis", "", sphere), 1500000);
    for (const auto &[integrator, samples] :
         {std::pair<const char *, size_t>{"path_mats", 5000000}, {"path_ems", 1000000}}) {
        const RunningMoments estimate =
            estimatePixel(*floorUnder(map, integrator, "", sphere), samples);
        const auto [z, detectable] = compare(estimate, reference);
        INFO(integrator << " " << estimate.mean << " against path_mis " << reference.mean
                        << ": z = " << z << " (critical " << critical
                        << "); smallest bias seen with 95 % power " << 100 * detectable << " %");
        CHECK(std::abs(z) < critical);
        CHECK(detectable < scaledPlantedBias(0.016));
    }
    // Negative control: under a sun 2 % dimmer (more at reduced counts), path_ems disagrees.
    const RunningMoments darker =
        estimatePixel(*floorUnder(dimmer, "path_ems", "", sphere), 1000000);
    const double z = compare(darker, reference).first;
    INFO("sun 2 % dimmer: z = " << z);
    CHECK(std::abs(z) > critical);
}

TEST_CASE("Camera rays see the environment filtered over their pixel footprint",
          "[envmap][differentials]") {
    TempDir dir;
    // A checkerboard of single texels (mean 0.5): unfiltered, a pixel covering many
    // texels sees 0 or 1; filtered, close to 0.5.
    const std::string map = writeMap(dir, "fine.exr", 1024, 512,
                                     [](int x, int y) { return Color3f(float((x + y) % 2)); });
    auto envmap = loadEnvmap(map);
    Ray3f ray(Point3f(0.0f, 0.0f, 0.0f), Vector3f(0.3f, 0.2f, -1.0f).normalized());
    ray.hasDifferentials = true;
    ray.rxOrigin = ray.ryOrigin = ray.o;
    // Each pixel step turns the direction by 0.05 rad: about 8 texels of the 1024-wide map.
    const Frame frame(ray.d);
    ray.rxDirection = (ray.d + 0.05f * frame.s).normalized();
    ray.ryDirection = (ray.d + 0.05f * frame.t).normalized();
    const float filtered = envmap->eval(EmitterQueryRecord(ray, true)).r();
    const float pointwise = envmap->eval(EmitterQueryRecord(ray, false)).r();
    CHECK(filtered == Approx(0.5f).margin(0.05f));
    CHECK((pointwise == 0.0f || pointwise == 1.0f));
}

TEST_CASE("The equal-area map round-trips, and square maps are sampled by luminance alone",
          "[envmap][chi2]") {
    // Clarberg's map and its inverse agree over the square, corners and diagonals included.
    PCG32 random(8, 1);
    for (int i = 0; i < 10000; ++i) {
        const Point2f p(random.nextFloat(), random.nextFloat());
        const Vector3f d = Warp::squareToEqualAreaSphere(p);
        REQUIRE(d.norm() == Approx(1.0f).margin(1e-5));
        const Point2f back = Warp::equalAreaSphereToSquare(d);
        INFO(p.transpose() << " -> " << d.transpose() << " -> " << back.transpose());
        REQUIRE((back - p).norm() < 2e-5f);
    }
    // Square maps: a gradient with a sun, a one-hot texel, and the map of the doc example.
    TempDir dir;
    const std::vector<std::string> maps = {
        writeMap(dir, "sun.exr", 64, 64,
                 [](int x, int y) {
                     const bool sun = std::abs(x - 40) <= 1 && std::abs(y - 12) <= 1;
                     return Color3f(sun ? 300.0f : 0.1f + 0.01f * float(x + y));
                 }),
        writeMap(dir, "onehot.exr", 16, 16,
                 [](int x, int y) { return Color3f(x == 3 && y == 11 ? 1.0f : 0.0f); }),
        std::string(NORI_SOURCE_DIR) + "/tests/data/envmaps/equalarea.pfm"};
    ChiSquareOptions options;
    options.sampleCount = 500000;
    options.significanceLevel = sidakCorrection(0.01, static_cast<int>(maps.size()));
    for (const std::string &file : maps) {
        CAPTURE(file);
        auto envmap = loadEnvmap(file, R"(<string name="mapping" value="equalarea"/>
            <transform name="toWorld"><rotate axis="1, 0, 0" angle="-90"/></transform>)");
        options.seed += 1;
        const ChiSquareReport report =
            runChiSquareTest(emitterRoutine(*envmap, Point3f(0.0f, 0.0f, 0.0f)), options);
        INFO(report.result.message);
        CHECK(report.result.passed);
        // Each texel covers 4π/(W·H): the constant part of a map integrates exactly.
        PCG32 directions(2, 2);
        for (int i = 0; i < 200; ++i) {
            EmitterQueryRecord lRec(Point3f(0.0f, 0.0f, 0.0f));
            const float u = directions.nextFloat();
            const Color3f weight = envmap->sample(lRec, Point2f(u, directions.nextFloat()));
            if ((weight == 0.0f).all())
                continue;
            REQUIRE(envmap->pdf(lRec) == Approx(lRec.pdf).epsilon(1e-3));
        }
    }
    // The control: a lat-long density (with 1/sin θ) for a square map.
    auto envmap = loadEnvmap(maps[0], R"(<string name="mapping" value="equalarea"/>)");
    SamplingRoutine wrong = emitterRoutine(*envmap, Point3f(0.0f, 0.0f, 0.0f));
    const SamplingRoutine right = wrong;
    wrong.pdf = [right](const Vector3f &w) -> double {
        const double sinTheta = std::sqrt(std::max(0.0, 1.0 - double(w.z()) * w.z()));
        return sinTheta > 0.0 ? right.pdf(w) * 2.0 / (kPiDouble * sinTheta) : 0.0;
    };
    options.seed += 1;
    CHECK_FALSE(runChiSquareTest(wrong, options).result.passed);
    CHECK_THAT(errorOf([&] {
                   loadEnvmap(
                       writeMap(dir, "wide.exr", 8, 4, [](int, int) { return Color3f(1.0f); }),
                       R"(<string name="mapping" value="equalarea"/>)");
               }),
               Catch::Contains("an equal-area map is square"));
}

TEST_CASE("A diffuse floor under a constant equal-area map reflects albedo times L",
          "[envmap][ttest]") {
    TempDir dir;
    const std::string white =
        writeMap(dir, "white.exr", 8, 8, [](int, int) { return Color3f(2.0f); });
    for (const std::string &integrator : kEnvironmentIntegrators)
        tTest(*floorUnder(white, integrator, R"(<string name="mapping" value="equalarea"/>)"),
              0.5 * 2.0, 4000);
}
