// Participating media: the phase functions under χ² (with negative controls), the
// transmittance estimators and free-flight sampling against exp(−σt·d) and its integrals,
// the grids (.vol against NanoVDB, the majorant grid's bounds and DDA), and volpath
// against closed forms: an absorbing slab, furnaces behind index-matched and dielectric
// boundaries, single scattering in a slab, and path_mis on a scene without media.
#include "testutil.h"

#include <nori/chisquare.h>
#include <nori/filesystem.h>
#include <nori/medium.h>
#include <nori/parser.h>
#include <nori/phase.h>
#include <nori/samplingroutines.h>
#include <nori/scene.h>
#include <nori/statistics.h>
#include <nori/volumegrid.h>
#include <nori/warp.h>

#include <catch2/catch.hpp>

#include <nanovdb/util/GridBuilder.h>
#include <nanovdb/util/IO.h>

#include <cstring>

using namespace nori;
using namespace nori::testing;

namespace {

const std::string kMediaDirectory = std::string(NORI_SOURCE_DIR) + "/scenes/media";

std::shared_ptr<Medium> loadMedium(const std::string &xml, const std::string &directory = ".") {
    auto medium = std::dynamic_pointer_cast<Medium>(loadFromXMLString(xml, directory));
    REQUIRE(medium);
    return medium;
}

std::shared_ptr<PhaseFunction> loadPhase(const std::string &xml) {
    auto phase = std::dynamic_pointer_cast<PhaseFunction>(loadFromXMLString(xml));
    REQUIRE(phase);
    return phase;
}

/// A grid of `resolution`³ voxels over [−1, 1]³ with value(x, y, z) at voxel centres.
template <typename F> VolumeGrid makeGrid(int resolution, F value) {
    std::vector<float> values;
    for (int z = 0; z < resolution; ++z)
        for (int y = 0; y < resolution; ++y)
            for (int x = 0; x < resolution; ++x)
                values.push_back(value(x, y, z));
    Eigen::Matrix4f unitToObject = Eigen::Matrix4f::Identity();
    unitToObject.topLeftCorner<3, 3>() *= 2.0f;
    unitToObject.topRightCorner<3, 1>() = Eigen::Vector3f::Constant(-1.0f);
    return VolumeGrid(Vector3i::Constant(resolution), 1, std::move(values), Transform(unitToObject),
                      "test grid");
}

/// Mean and variance, per channel, of `count` transmittance estimates along `ray`.
struct ChannelMoments {
    RunningMoments channel[3];
    void add(const Color3f &value) {
        for (int c = 0; c < 3; ++c)
            channel[c].add(value[c]);
    }
};

ChannelMoments transmittanceMoments(const Medium &medium, const Ray3f &ray,
                                    TransmittanceEstimator estimator, size_t count,
                                    float stepSize = 0.0f, uint64_t seed = 7) {
    PCG32 rng(seed, 1);
    ChannelMoments moments;
    for (size_t i = 0; i < count; ++i)
        moments.add(medium.transmittance(ray, rng, estimator, stepSize));
    return moments;
}

/// Whether `moments` estimate `expected` within 4.5 standard errors (a false alarm once
/// in ~150,000 runs), or within `absolute` when the estimator has no variance.
void checkMean(const RunningMoments &moments, double expected, const std::string &what,
               double absolute = 1e-5) {
    const double standardError = std::sqrt(moments.variance() / double(moments.count));
    INFO(what << ": mean " << moments.mean << " (standard error " << standardError << "), expected "
              << expected);
    CHECK(std::abs(moments.mean - expected) <= 4.5 * standardError + absolute);
}

/// Checks that two estimates agree, and (the negative control) that `reference` off by
/// the relative bias `controlBias` (−0.05: 5 % darker; more at reduced test counts) is told
/// apart from `estimate`.
void checkAgreement(const RunningMoments &estimate, const RunningMoments &reference,
                    double controlBias) {
    double t;
    INFO("estimate " << estimate.mean << ", reference " << reference.mean);
    CHECK(samplesAgree(estimate, reference, t));
    INFO("t = " << t);
    RunningMoments scaled = reference;
    scaled.mean *= 1.0 + scaledPlantedBias(controlBias);
    CHECK_FALSE(samplesAgree(estimate, scaled, t));
}

double luminance(const Color3f &c) {
    return c.getLuminance();
}

/// A scene of a 1×1 camera with a 1° field of view at (0, 0, 5) looking at the origin,
/// with `content`, rendered by volpath with `integratorProperties`.
std::shared_ptr<Scene> pinholeScene(const std::string &content,
                                    const std::string &integratorProperties = "") {
    return loadScene(fmt::format(R"(<scene>
        <integrator type="volpath">{}</integrator>
        <sampler type="independent"><integer name="sampleCount" value="1"/></sampler>
        <camera type="perspective"><float name="fov" value="1"/>
            <integer name="width" value="1"/><integer name="height" value="1"/>
            <transform name="toWorld"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
        </camera>{}</scene>)",
                                 integratorProperties, content),
                     kMediaDirectory);
}

} // namespace

TEST_CASE("Phase functions sample their pdf (chi-square, with negative controls)",
          "[media][chi2]") {
    const std::vector<std::string> phases = {
        R"(<phase type="isotropic"/>)",
        R"(<phase type="hg"><float name="g" value="-0.9"/></phase>)",
        R"(<phase type="hg"><float name="g" value="-0.3"/></phase>)",
        R"(<phase type="hg"><float name="g" value="0"/></phase>)",
        R"(<phase type="hg"><float name="g" value="0.5"/></phase>)",
        R"(<phase type="hg"><float name="g" value="0.95"/></phase>)"};
    const std::vector<Vector3f> incoming = {Vector3f(0.0f, 0.0f, 1.0f),
                                            Vector3f(0.6f, -0.48f, 0.64f)};
    const double level = sidakCorrection(0.01, int(phases.size() * incoming.size()));
    uint64_t seed = 11;
    for (const std::string &xml : phases) {
        const auto phase = loadPhase(xml);
        for (const Vector3f &wi : incoming) {
            const ChiSquareReport report = chiSquare(phaseRoutine(*phase, wi), seed++, level);
            INFO(phase->toString() << " wi = " << wi.transpose() << ": " << report.result.message);
            CHECK(report.result.passed);
            CHECK(report.pdfIntegral == Approx(1.0).epsilon(1e-3));
        }
    }

    // Negative controls: samples of one phase function against the pdf of another.
    auto rejected = [&](const std::string &sampled, const std::string &claimed) {
        const auto sampler = loadPhase(sampled), density = loadPhase(claimed);
        const Vector3f wi(0.0f, 0.0f, 1.0f);
        SamplingRoutine routine = phaseRoutine(*sampler, wi);
        routine.pdf = [&](const Vector3f &wo) {
            return density->pdf(PhaseFunctionQueryRecord(wi, wo, ESolidAngle));
        };
        const ChiSquareReport report = chiSquare(routine, 5, 0.01);
        INFO(sampled << " against " << claimed << ": " << report.result.message);
        CHECK_FALSE(report.result.passed);
    };
    rejected(R"(<phase type="isotropic"/>)",
             R"(<phase type="hg"><float name="g" value="0.1"/></phase>)");
    rejected(R"(<phase type="hg"><float name="g" value="0.95"/></phase>)",
             R"(<phase type="hg"><float name="g" value="0.9"/></phase>)");
    rejected(R"(<phase type="hg"><float name="g" value="0.5"/></phase>)",
             R"(<phase type="hg"><float name="g" value="-0.5"/></phase>)");
}

TEST_CASE("Transmittance estimators through a homogeneous slab equal exp(-sigma_t d)", "[media]") {
    const auto medium = loadMedium(R"(<medium type="homogeneous">
        <color name="sigmaT" value="0.2, 0.7, 1.5"/><color name="albedo" value="0.5"/></medium>)");
    const float distance = 2.0f;
    const Ray3f ray(Point3f(0.3f, -1.0f, 2.0f), Vector3f(0.6f, 0.0f, 0.8f), 0.5f, 0.5f + distance);
    const Color3f expected = (-Color3f(0.2f, 0.7f, 1.5f) * distance).exp();
    const size_t count = 40000;
    for (auto estimator : {TransmittanceEstimator::Delta, TransmittanceEstimator::Ratio}) {
        const ChannelMoments moments = transmittanceMoments(*medium, ray, estimator, count);
        for (int c = 0; c < 3; ++c)
            checkMean(moments.channel[c], expected[c],
                      fmt::format("estimator {}, channel {}", int(estimator), c));
    }
    // Ray marching is exact in a homogeneous medium, whatever the step.
    const ChannelMoments marched =
        transmittanceMoments(*medium, ray, TransmittanceEstimator::RayMarch, 100, 0.3f);
    for (int c = 0; c < 3; ++c) {
        CHECK(marched.channel[c].mean == Approx(expected[c]).epsilon(1e-5));
        CHECK(marched.channel[c].variance() < 1e-10);
    }
    // Negative control: the same estimates against a slab 10% thicker.
    const ChannelMoments delta =
        transmittanceMoments(*medium, ray, TransmittanceEstimator::Delta, count);
    const double standardError = std::sqrt(delta.channel[1].variance() / double(count));
    CHECK(std::abs(delta.channel[1].mean - std::exp(-0.7 * distance * 1.1)) > 4.5 * standardError);
}

TEST_CASE("Homogeneous free flights: collisions and passes weigh as the closed forms say "
          "(spectral MIS over coloured coefficients)",
          "[media]") {
    const Color3f sigmaS(0.3f, 0.9f, 0.1f), sigmaA(0.1f, 0.2f, 1.2f);
    const auto medium = loadMedium(
        fmt::format(R"(<medium type="homogeneous"><color name="sigmaS" value="{}, {}, {}"/>
        <color name="sigmaA" value="{}, {}, {}"/></medium>)",
                    sigmaS[0], sigmaS[1], sigmaS[2], sigmaA[0], sigmaA[1], sigmaA[2]));
    const Color3f sigmaT = sigmaS + sigmaA;
    const float distance = 1.5f;
    const Ray3f ray(Point3f(0.0f, 0.0f, 0.0f), Vector3f(0.0f, 1.0f, 0.0f), 0.0f, distance);
    // E[weight · 1{pass}] = T(d), E[weight · 1{collision}] = ∫ σs T(t) dt = σs (1 − T(d))/σt.
    const Color3f passed = (-sigmaT * distance).exp();
    const Color3f scattered = sigmaS * (Color3f(1.0f) - passed) / sigmaT;
    PCG32 rng(3, 1);
    ChannelMoments passMoments, scatterMoments;
    for (int i = 0; i < 100000; ++i) {
        const MediumSample mRec = medium->sampleFreeFlight(ray, rng);
        REQUIRE(mRec.weight.isValid());
        if (mRec.scattered)
            CHECK((mRec.t >= 0.0f && mRec.t <= distance));
        passMoments.add(mRec.scattered ? Color3f(0.0f) : mRec.weight);
        scatterMoments.add(mRec.scattered ? mRec.weight : Color3f(0.0f));
    }
    for (int c = 0; c < 3; ++c) {
        checkMean(passMoments.channel[c], passed[c], fmt::format("passing, channel {}", c));
        checkMean(scatterMoments.channel[c], scattered[c], fmt::format("collision, channel {}", c));
    }
}

TEST_CASE("A heterogeneous grid of constant density equals the homogeneous medium", "[media]") {
    TempDir dir;
    makeGrid(4, [](int, int, int) {
        return 1.0f;
    }).writeVol((dir.path() / "constant.vol").string());
    const auto heterogeneous = loadMedium(R"(<medium type="heterogeneous">
        <string name="filename" value="constant.vol"/><float name="scale" value="0.7"/>
        <color name="albedo" value="0.6"/><integer name="majorantResolution" value="4"/>
        <transform name="toWorld"><scale value="2"/></transform></medium>)",
                                          dir.path().string());
    // A chord of the cube [−2, 2]³ of length 3, inside it all along.
    const Ray3f ray(Point3f(-1.5f, -0.3f, 0.2f), Vector3f(1.0f, 0.0f, 0.0f), 0.0f, 3.0f);
    const double expected = std::exp(-0.7 * 3.0);
    for (auto estimator : {TransmittanceEstimator::Delta, TransmittanceEstimator::Ratio}) {
        const ChannelMoments moments = transmittanceMoments(*heterogeneous, ray, estimator, 40000);
        checkMean(moments.channel[0], expected, fmt::format("estimator {}", int(estimator)));
    }
    const ChannelMoments marched =
        transmittanceMoments(*heterogeneous, ray, TransmittanceEstimator::RayMarch, 10, 0.1f);
    CHECK(marched.channel[0].mean == Approx(expected).epsilon(1e-5));

    // Delta-tracked free flights: a collision within the chord with probability 1 − T,
    // of weight albedo; otherwise a pass of weight 1.
    PCG32 rng(9, 1);
    RunningMoments collided, weight;
    for (int i = 0; i < 40000; ++i) {
        const MediumSample mRec = heterogeneous->sampleFreeFlight(ray, rng);
        collided.add(mRec.scattered ? 1.0 : 0.0);
        weight.add(mRec.weight[0]);
        if (mRec.scattered)
            CHECK(mRec.weight[0] == Approx(0.6f));
    }
    checkMean(collided, 1.0 - expected, "collision probability");

    // An albedo grid (3 channels, a gradient along x) instead of the constant: a collision
    // weighs the albedo at its point.
    {
        std::vector<float> albedos;
        for (int z = 0; z < 2; ++z)
            for (int y = 0; y < 2; ++y)
                for (int x = 0; x < 2; ++x)
                    albedos.insert(albedos.end(), {0.2f, x == 0 ? 0.3f : 0.7f, 0.9f});
        Eigen::Matrix4f unitToObject = Eigen::Matrix4f::Identity();
        unitToObject.topLeftCorner<3, 3>() *= 2.0f;
        unitToObject.topRightCorner<3, 1>() = Eigen::Vector3f::Constant(-1.0f);
        VolumeGrid(Vector3i::Constant(2), 3, albedos, Transform(unitToObject), "albedo")
            .writeVol((dir.path() / "albedo.vol").string());
    }
    const auto coloured = loadMedium(R"(<medium type="heterogeneous">
        <string name="filename" value="constant.vol"/><float name="scale" value="0.7"/>
        <string name="albedoFilename" value="albedo.vol"/>
        <transform name="toWorld"><scale value="2"/></transform></medium>)",
                                     dir.path().string());
    for (int i = 0; i < 2000; ++i) {
        const MediumSample mRec = coloured->sampleFreeFlight(ray, rng);
        if (!mRec.scattered)
            continue;
        // Voxel centres at x = ±1 (world), linear between them, clamped outside.
        const float green = 0.5f + 0.2f * std::clamp(mRec.p.x(), -1.0f, 1.0f);
        CHECK(mRec.weight.isApprox(Color3f(0.2f, green, 0.9f), 1e-4f));
    }

    // Outside the grid's cube the medium is empty.
    const Ray3f outside(Point3f(-5.0f, 3.0f, 0.0f), Vector3f(1.0f, 0.0f, 0.0f), 0.0f, 10.0f);
    CHECK(transmittanceMoments(*heterogeneous, outside, TransmittanceEstimator::Delta, 100)
              .channel[0]
              .mean == 1.0);
}

TEST_CASE("The cloud reads the same from .vol and NanoVDB, and its majorant grid bounds it",
          "[media]") {
    const VolumeGrid vol = VolumeGrid::load(kMediaDirectory + "/cloud.vol");
    const VolumeGrid nvdb = VolumeGrid::load(kMediaDirectory + "/cloud.nvdb");
    // NanoVDB keeps the active voxels only (plus a border of background).
    CHECK((nvdb.resolution().array() < vol.resolution().array() + 2).all());
    // A dense copy above the limit is refused before it is allocated.
    const std::string nvdbBytes = readBinaryFile(kMediaDirectory + "/cloud.nvdb", "test");
    CHECK_THAT(errorOf([&] { VolumeGrid::parse(nvdbBytes, "cloud.nvdb", "", 1000); }),
               Catch::Contains("more than the 1000 values") && Catch::Contains("cloud.nvdb"));
    PCG32 rng(1, 1);
    for (int i = 0; i < 20000; ++i) {
        // Points of the object space [−1.2, 1.2]³, mapped into each grid's unit cube.
        const Point3f p(2.4f * rng.nextFloat() - 1.2f, 2.4f * rng.nextFloat() - 1.2f,
                        2.4f * rng.nextFloat() - 1.2f);
        const float a = vol.lookup(vol.unitToObject().inverse() * p);
        const float b = nvdb.lookup(nvdb.unitToObject().inverse() * p);
        INFO("at " << p.transpose());
        REQUIRE(a == Approx(b).margin(1e-4));
    }

    // The DDA's segments tile the ray's part inside the cube, in order, and no point of a
    // segment is denser than its bound.
    const MajorantGrid majorants(vol, 8, 3.0f);
    size_t segments = 0;
    for (int i = 0; i < 2000; ++i) {
        const Point3f o(1.6f * rng.nextFloat() - 0.3f, 1.6f * rng.nextFloat() - 0.3f,
                        1.6f * rng.nextFloat() - 0.3f);
        const Vector3f d = Warp::squareToUniformSphere(Point2f(rng.nextFloat(), rng.nextFloat()));
        MajorantIterator iterator(majorants, o, d, 0.0f, 4.0f);
        MajorantSegment segment;
        float previousEnd = -1.0f;
        while (iterator.next(segment)) {
            ++segments;
            REQUIRE(segment.tMin <= segment.tMax);
            if (previousEnd >= 0.0f)
                REQUIRE(segment.tMin == previousEnd);
            previousEnd = segment.tMax;
            for (int k = 0; k <= 8; ++k) {
                const float t = segment.tMin + (segment.tMax - segment.tMin) * float(k) / 8.0f;
                REQUIRE(3.0f * vol.lookup(o + t * d) <= segment.sigmaMajorant * (1.0f + 1e-5f));
            }
        }
    }
    CHECK(segments > 2000);
    // Thin regions get small bounds: the majorant grid's average is well under its maximum.
    double sum = 0.0;
    for (int z = 0; z < 8; ++z)
        for (int y = 0; y < 8; ++y)
            for (int x = 0; x < 8; ++x)
                sum += majorants.cell(x, y, z);
    CHECK(sum / 512.0 < 0.6 * majorants.maximum());
}

TEST_CASE("Grid values at voxel centres or at lattice corners (Mitsuba 0.6)", "[media]") {
    // Along x, values 0, 1, 2 over the unit cube.
    VolumeGrid grid = makeGrid(3, [](int x, int, int) { return float(x); });
    const auto at = [&](float u) { return grid.lookup(Point3f(u, 0.5f, 0.5f)); };
    // Centres: value i at (i + ½)/3, clamped to the edge values beyond the outer centres.
    CHECK(at(0.0f) == 0.0f);
    CHECK(at(1.0f / 6.0f) == 0.0f);
    CHECK(at(0.5f) == Approx(1.0f));
    CHECK(at(2.0f / 3.0f) == Approx(1.5f));
    CHECK(at(1.0f) == 2.0f);
    CHECK(grid.maximumOver(Point3f(0.0f, 0.0f, 0.0f), Point3f(0.1f, 1.0f, 1.0f)) == 0.0f);
    // Corners: value i at i/2, so linear across the whole cube.
    grid.setLayout(VoxelLayout::Corners);
    for (const float u : {0.0f, 0.1f, 0.25f, 0.5f, 0.8f, 1.0f})
        CHECK(at(u) == Approx(2.0f * u));
    CHECK(grid.maximumOver(Point3f(0.0f, 0.0f, 0.0f), Point3f(0.1f, 1.0f, 1.0f)) == 1.0f);
    CHECK(grid.maximumOver(Point3f(0.6f, 0.0f, 0.0f), Point3f(1.0f, 1.0f, 1.0f)) == 2.0f);
    // Outside the cube, nothing.
    CHECK(grid.lookup(Point3f(1.01f, 0.5f, 0.5f)) == 0.0f);
    // Corners need two values along every axis.
    VolumeGrid single = makeGrid(1, [](int, int, int) { return 1.0f; });
    CHECK_THAT(errorOf([&] { single.setLayout(VoxelLayout::Corners); }),
               Catch::Contains("at least 2"));
}

TEST_CASE("Ratio tracking has a lower variance than delta tracking through the cloud", "[media]") {
    const auto cloud = loadMedium(R"(<medium type="heterogeneous">
        <string name="filename" value="cloud.vol"/><float name="scale" value="3"/></medium>)",
                                  kMediaDirectory);
    double deltaVariance = 0.0, ratioVariance = 0.0;
    PCG32 directions(4, 1);
    for (int i = 0; i < 8; ++i) {
        const Vector3f d =
            Warp::squareToUniformSphere(Point2f(directions.nextFloat(), directions.nextFloat()));
        const Ray3f ray(Point3f(0.0f, 0.0f, 0.0f) - 2.0f * d, d, 0.0f, 4.0f);
        const ChannelMoments reference =
            transmittanceMoments(*cloud, ray, TransmittanceEstimator::RayMarch, 16, 0.002f);
        const ChannelMoments delta =
            transmittanceMoments(*cloud, ray, TransmittanceEstimator::Delta, 20000);
        const ChannelMoments ratio =
            transmittanceMoments(*cloud, ray, TransmittanceEstimator::Ratio, 20000);
        // The fine ray march as the reference, within its own bias (1e-3).
        checkMean(delta.channel[0], reference.channel[0].mean, "delta tracking", 1e-3);
        checkMean(ratio.channel[0], reference.channel[0].mean, "ratio tracking", 1e-3);
        deltaVariance += delta.channel[0].variance();
        ratioVariance += ratio.channel[0].variance();
    }
    WARN("variance of delta / ratio tracking through the cloud (8 rays): " << deltaVariance /
                                                                                  ratioVariance);
    CHECK(ratioVariance < deltaVariance);
}

TEST_CASE("volpath: an absorbing slab between camera and light gives Le exp(-sigma_t d)",
          "[media][ttest]") {
    // A slab 1 thick (z in [−0.5, 0.5]) of a coloured absorber in front of a light sphere.
    auto scene = pinholeScene(R"(
        <mesh type="obj"><string name="filename" value="box.obj"/>
            <transform name="toWorld"><scale value="3, 3, 0.5"/></transform>
            <medium type="homogeneous" name="interior"><color name="sigmaA" value="0.5, 1, 2"/></medium>
        </mesh>
        <mesh type="sphere"><point name="center" value="0, 0, -4"/><float name="radius" value="1"/>
            <emitter type="area"><color name="radiance" value="2, 3, 4"/></emitter></mesh>)");
    const double reference =
        luminance(Color3f(2.0f, 3.0f, 4.0f) * (-Color3f(0.5f, 1.0f, 2.0f)).exp());
    const PixelTTest test = tTestPixel(*scene, reference, 20000);
    INFO(test.summary());
    CHECK(test.result.passed);
    // Negative control: the light seen through a slab 5 % thicker (more at reduced counts).
    const auto thickness = static_cast<float>(1.0 + scaledPlantedBias(0.05));
    const double thicker =
        luminance(Color3f(2.0f, 3.0f, 4.0f) * (-Color3f(0.5f, 1.0f, 2.0f) * thickness).exp());
    CHECK_FALSE(
        studentTTest(test.moments.mean, test.moments.variance(), test.moments.count, thicker, 0.01)
            .passed);
}

TEST_CASE("volpath: rays track their medium across nested boundaries", "[media][ttest]") {
    // Through an absorbing sphere (r = 1.5, σa = 0.3) holding a denser one (r = 0.7,
    // σa = 1, its exterior the outer medium): chords of 3 and 1.4 through the centres.
    auto scene = pinholeScene(R"(
        <medium type="homogeneous" id="outer"><color name="sigmaA" value="0.3"/></medium>
        <mesh type="sphere"><float name="radius" value="1.5"/><ref id="outer" name="interior"/></mesh>
        <mesh type="sphere"><float name="radius" value="0.7"/><ref id="outer" name="exterior"/>
            <medium type="homogeneous" name="interior"><color name="sigmaA" value="1"/></medium></mesh>
        <mesh type="sphere"><point name="center" value="0, 0, -4"/><float name="radius" value="1"/>
            <emitter type="area"><color name="radiance" value="2"/></emitter></mesh>)");
    const double reference = 2.0 * std::exp(-0.3 * (3.0 - 1.4) - 1.0 * 1.4);
    const PixelTTest test = tTestPixel(*scene, reference, 20000);
    INFO(test.summary());
    CHECK(test.result.passed);
    // Negative control: leaving the inner sphere into vacuum instead of the outer medium.
    const double lost = 2.0 * std::exp(-0.3 * 0.8 - 1.0 * 1.4);
    CHECK_FALSE(
        studentTTest(test.moments.mean, test.moments.variance(), test.moments.count, lost, 0.01)
            .passed);
}

TEST_CASE("volpath: white furnaces of albedo-1 media behind index-matched and dielectric "
          "boundaries see 1",
          "[media][ttest]") {
    const std::string environment =
        R"(<emitter type="constant"><color name="radiance" value="1"/></emitter>)";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"index-matched sphere, homogeneous hg 0.5", R"(
            <mesh type="sphere"><float name="radius" value="1"/>
                <medium type="homogeneous" name="interior"><color name="sigmaT" value="3"/>
                    <color name="albedo" value="1"/><phase type="hg"><float name="g" value="0.5"/></phase>
                </medium></mesh>)"},
        {"dielectric sphere, homogeneous isotropic", R"(
            <mesh type="sphere"><float name="radius" value="1"/>
                <bsdf type="dielectric"><float name="intIOR" value="1.5"/></bsdf>
                <medium type="homogeneous" name="interior"><color name="sigmaT" value="2"/>
                    <color name="albedo" value="1"/></medium></mesh>)"},
        {"index-matched cube, the cloud (delta tracking)", R"(
            <mesh type="obj"><string name="filename" value="box.obj"/>
                <medium type="heterogeneous" name="interior"><string name="filename" value="cloud.nvdb"/>
                    <float name="scale" value="10"/><color name="albedo" value="1"/>
                    <phase type="hg"><float name="g" value="-0.3"/></phase></medium></mesh>)"},
        {"nested boundaries: a dense sphere in a thin one, the inner one's exterior the outer "
         "medium",
         R"(
            <medium type="homogeneous" id="outer"><color name="sigmaT" value="0.8"/>
                <color name="albedo" value="1"/></medium>
            <mesh type="sphere"><float name="radius" value="1.5"/><ref id="outer" name="interior"/></mesh>
            <mesh type="sphere"><float name="radius" value="0.7"/><ref id="outer" name="exterior"/>
                <medium type="homogeneous" name="interior"><color name="sigmaT" value="6"/>
                    <color name="albedo" value="1"/><phase type="hg"><float name="g" value="0.8"/></phase>
                </medium></mesh>)"},
        {"camera inside a homogeneous fog, in an index-matched sphere", R"(
            <mesh type="sphere"><float name="radius" value="8"/><ref id="fog" name="interior"/></mesh>)"}};
    for (const auto &[name, content] : cases) {
        const bool cameraInside = name.rfind("camera inside", 0) == 0;
        std::string xml = environment + content;
        auto scene = cameraInside ? loadScene(fmt::format(R"(<scene><integrator type="volpath"/>
                    <medium type="homogeneous" id="fog"><color name="sigmaT" value="0.3"/>
                        <color name="albedo" value="1"/></medium>
                    <sampler type="independent"><integer name="sampleCount" value="1"/></sampler>
                    <camera type="perspective"><float name="fov" value="1"/>
                        <integer name="width" value="1"/><integer name="height" value="1"/>
                        <transform name="toWorld"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
                        <ref id="fog"/>
                    </camera>{}</scene>)",
                                                          xml),
                                              kMediaDirectory)
                                  : pinholeScene(xml);
        // 20,000 samples: a path that total internal reflection keeps in the dielectric
        // sphere passes hundreds of roulette events at q = 0.99, each multiplying its weight
        // by 1/0.99, so rare samples are worth tens and the sample variance ranges from 0.3
        // to 0.95 with the seed; at 8,000 samples the control's 3 % were 2.4 standard errors
        // there, short of the 2.58 of significance 0.01 (found when the roulette changed).
        const PixelTTest test = tTestPixel(*scene, 1.0, 20000);
        INFO(name << ": " << test.summary());
        CHECK(test.result.passed);
        // Negative control: a medium losing 3 % of the light (more at reduced counts) would
        // be told apart.
        CHECK_FALSE(studentTTest(test.moments.mean, test.moments.variance(), test.moments.count,
                                 1.0 - scaledPlantedBias(0.03), 0.01)
                        .passed);
    }
}

TEST_CASE("volpath: single scattering in a slab matches its closed form", "[media][ttest]") {
    // A slab z in [−1, 0] (σs = 0.4, σa = 0.1, hg g = 0.3) lit by a directional light of
    // irradiance E from 60° off the normal, seen along −z. Single scattering at depth s:
    // σs p E exp(−σt s) exp(−σt s/cos θ), so L = σs p E (1 − e^{−σt d k})/(σt k) with
    // k = 1 + 1/cos θ; p at the angle between the propagation −z and the light direction.
    const float sigmaS = 0.4f, sigmaT = 0.5f, g = 0.3f, irradiance = 10.0f, depth = 1.0f;
    const float cosLight = 0.5f, sinLight = std::sqrt(1.0f - cosLight * cosLight);
    // Our convention: wi = +z toward the camera, wo toward the light; cos = −wi·wo.
    const float mu = -cosLight;
    const double phase = (1.0 - g * g) / (4.0 * kPi * std::pow(1.0 + g * g - 2.0 * g * mu, 1.5));
    const double k = 1.0 + 1.0 / cosLight;
    const double radiance =
        sigmaS * phase * irradiance * (1.0 - std::exp(-sigmaT * depth * k)) / (sigmaT * k);
    auto scene =
        pinholeScene(fmt::format(R"(
        <mesh type="obj"><string name="filename" value="box.obj"/>
            <transform name="toWorld"><scale value="50, 50, 0.5"/><translate value="0, 0, -0.5"/></transform>
            <medium type="homogeneous" name="interior"><color name="sigmaS" value="{}"/>
                <color name="sigmaA" value="{}"/><phase type="hg"><float name="g" value="{}"/></phase></medium>
        </mesh>
        <emitter type="directional"><vector name="direction" value="{}, 0, {}"/>
            <color name="irradiance" value="{}"/></emitter>)",
                                 sigmaS, sigmaT - sigmaS, g, -sinLight, -cosLight, irradiance),
                     R"(<boolean name="singleScatter" value="true"/>)");
    const PixelTTest test = tTestPixel(*scene, radiance, 20000);
    INFO(test.summary());
    CHECK(test.result.passed);
    // Negative control: the phase function evaluated at the mirrored angle (+cos θ).
    const double mirrored = radiance * std::pow((1.0 + g * g - 2.0 * g * mu), 1.5) /
                            std::pow((1.0 + g * g + 2.0 * g * mu), 1.5);
    CHECK_FALSE(
        studentTTest(test.moments.mean, test.moments.variance(), test.moments.count, mirrored, 0.01)
            .passed);
}

TEST_CASE("volpath: a slab 10^4 wide scatters light as one 100 wide", "[media][ttest]") {
    // Multiple scattering in a slab z in [−1, 0] lit by a directional light 60° off its
    // normal, seen along −z: light that travels 50 sideways is exp(−25) of it, so the box's
    // width must not matter. Paths scattering within 1 of a 10⁴-unit face in a grazing
    // direction missed it 8 % of the time (the triangle test's t > 0 bound grows with the
    // triangle) and stayed in the medium: this slab read 1.4 % darker before hits near t = 0
    // were re-tested in double.
    auto slab = [](float halfWidth) {
        return pinholeScene(fmt::format(R"(
            <mesh type="obj"><string name="filename" value="box.obj"/>
                <transform name="toWorld"><scale value="{0}, {0}, 0.5"/><translate value="0, 0, -0.5"/></transform>
                <medium type="homogeneous" name="interior"><color name="sigmaS" value="0.9"/>
                    <color name="sigmaA" value="0.1"/><phase type="hg"><float name="g" value="0.3"/></phase></medium>
            </mesh>
            <emitter type="directional"><vector name="direction" value="-0.866, 0, -0.5"/>
                <color name="irradiance" value="10"/></emitter>)",
                                        halfWidth));
    };
    const RunningMoments narrow = estimatePixel(*slab(50.0f), 2000000);
    const RunningMoments wide = estimatePixel(*slab(5000.0f), 2000000);
    // Negative control: a wide slab 1 % brighter (more at reduced counts) is told apart.
    checkAgreement(narrow, wide, 0.01);
}

TEST_CASE("volpath equals path_mis on a scene without media", "[media][ttest]") {
    const std::string content = R"(
        <mesh type="sphere"><point name="center" value="0, 3, 0"/><float name="radius" value="0.5"/>
            <emitter type="area"><color name="radiance" value="5"/></emitter></mesh>
        <emitter type="constant"><color name="radiance" value="0.3"/></emitter>
        <mesh type="sphere"><point name="center" value="0.15, 1, 0.5"/><float name="radius" value="0.3"/>
            <bsdf type="dielectric"/></mesh>
        <mesh type="sphere"><point name="center" value="-0.5, 0.4, 0"/><float name="radius" value="0.4"/>
            <bsdf type="roughconductor"><float name="alpha" value="0.2"/></bsdf></mesh>)";
    const RunningMoments volpath = estimatePixel(*litFloor("volpath", content), 100000);
    const RunningMoments pathMIS = estimatePixel(*litFloor("path_mis", content), 100000);
    // Negative control: path_mis 5 % darker (more at reduced counts) is told apart.
    checkAgreement(volpath, pathMIS, -0.05);
}

TEST_CASE("Media refuse bad input with clear errors", "[media][errors]") {
    TempDir dir;
    const std::string directory = dir.path().string();
    auto heterogeneous = [&](const std::string &file) {
        return errorOf([&] {
            loadMedium(
                fmt::format(
                    R"(<medium type="heterogeneous"><string name="filename" value="{}"/></medium>)",
                    file),
                directory);
        });
    };
    // .vol files: truncated, wrong version, NaN and negative densities.
    makeGrid(3, [](int, int, int) { return 0.5f; }).writeVol(directory + "/good.vol");
    std::string bytes = readBinaryFile(directory + "/good.vol", "test");
    writeBinaryFile(directory + "/truncated.vol", bytes.substr(0, bytes.size() - 5), "test");
    CHECK_THAT(heterogeneous("truncated.vol"),
               Catch::Contains("truncated") && Catch::Contains("truncated.vol"));
    std::string version = bytes;
    version[3] = 2;
    writeBinaryFile(directory + "/version.vol", version, "test");
    CHECK_THAT(heterogeneous("version.vol"), Catch::Contains("version 2"));
    std::string header = bytes.substr(0, 20);
    CHECK_THAT(errorOf([&] { VolumeGrid::parseVol(header, "short.vol"); }),
               Catch::Contains("short.vol") && Catch::Contains("header"));
    CHECK_THAT(errorOf([] {
                   makeGrid(3, [](int x, int y, int z) {
                       return x == 1 && y == 2 && z == 0 ? std::numeric_limits<float>::quiet_NaN()
                                                         : 0.5f;
                   });
               }),
               Catch::Contains("nan") && Catch::Contains("(1, 2, 0)"));
    std::string negative = bytes;
    const float minusOne = -1.0f;
    std::memcpy(&negative[48 + 4 * 13], &minusOne, 4);
    writeBinaryFile(directory + "/negative.vol", negative, "test");
    CHECK_THAT(heterogeneous("negative.vol"), Catch::Contains("-1") &&
                                                  Catch::Contains("(1, 1, 1)") &&
                                                  Catch::Contains("negative.vol"));
    CHECK_THAT(heterogeneous("missing.vol"), Catch::Contains("missing.vol"));

    // NanoVDB files: the wrong grid type, a damaged grid, a truncated file.
    {
        nanovdb::GridBuilder<int32_t> builder(0);
        builder([](const nanovdb::Coord &) { return 3; },
                nanovdb::CoordBBox(nanovdb::Coord(0), nanovdb::Coord(3)));
        nanovdb::io::writeGrid(directory + "/int.nvdb",
                               builder.getHandle(1.0, nanovdb::Vec3d(0.0), "ints"));
    }
    CHECK_THAT(heterogeneous("int.nvdb"), Catch::Contains("int32") && Catch::Contains("ints") &&
                                              Catch::Contains("float grid"));
    makeGrid(4, [](int x, int, int) {
        return 0.1f * float(x);
    }).writeNanoVDB(directory + "/good.nvdb", "density");
    CHECK_NOTHROW(heterogeneous("good.nvdb").empty());
    CHECK_THAT(errorOf([&] {
                   loadMedium(
                       R"(<medium type="heterogeneous"><string name="filename" value="good.nvdb"/>
                       <string name="gridName" value="smoke"/></medium>)",
                       directory);
               }),
               Catch::Contains("no grid named 'smoke'"));
    const std::string nvdb = readBinaryFile(directory + "/good.nvdb", "test");
    writeBinaryFile(directory + "/short.nvdb", nvdb.substr(0, nvdb.size() / 2), "test");
    CHECK_THAT(heterogeneous("short.nvdb"), Catch::Contains("truncated"));
    std::string damaged = nvdb;
    damaged[damaged.size() - 100] ^= 0x5a;
    writeBinaryFile(directory + "/damaged.nvdb", damaged, "test");
    CHECK_THAT(heterogeneous("damaged.nvdb"), Catch::Contains("damaged"));
    makeGrid(2, [](int, int, int) { return 0.3f; }).writeVol(directory + "/density.vol");
    writeBinaryFile(directory + "/noise.nvdb", std::string(300, 'x'), "test");
    CHECK_THAT(heterogeneous("noise.nvdb"), Catch::Contains("not a NanoVDB file"));

    // Parameters.
    CHECK_THAT(errorOf([] {
                   loadMedium(
                       R"(<medium type="homogeneous"><color name="sigmaA" value="-1"/></medium>)");
               }),
               Catch::Contains("sigmaA") && Catch::Contains("non-negative"));
    CHECK_THAT(errorOf([] {
                   loadMedium(R"(<medium type="homogeneous"><color name="sigmaS" value="1"/>
                       <color name="albedo" value="0.5"/></medium>)");
               }),
               Catch::Contains("not a mix"));
    CHECK_THAT(errorOf([] {
                   loadMedium(R"(<medium type="homogeneous"><color name="sigmaT" value="1"/>
                       <color name="albedo" value="1.5"/></medium>)");
               }),
               Catch::Contains("albedo"));
    CHECK_THAT(
        errorOf([] {
            loadScene(
                R"(<scene><integrator type="volpath"><string name="transmittance" value="raymarch"/></integrator>
                       <camera type="perspective"/></scene>)");
        }),
        Catch::Contains("stepSize"));
    CHECK_THAT(
        errorOf([] {
            loadScene(
                R"(<scene><integrator type="volpath"><string name="transmittance" value="ratios"/></integrator>
                       <camera type="perspective"/></scene>)");
        }),
        Catch::Contains("'ratios'"));
    CHECK_THAT(errorOf([] {
                   loadScene(R"(<scene><integrator type="volpath"/><camera type="perspective"/>
                       <mesh type="sphere"><medium type="homogeneous" name="inside"/></mesh></scene>)");
               }),
               Catch::Contains("\"inside\"") && Catch::Contains("interior"));
    CHECK_THAT(errorOf([] {
                   loadScene(R"(<scene><integrator type="volpath"/><camera type="perspective"/>
                       <mesh type="sphere"><medium type="homogeneous" name="interior"/>
                       <medium type="homogeneous" name="interior"/></mesh></scene>)");
               }),
               Catch::Contains("only one medium"));
}

TEST_CASE("A medium inside an open mesh is warned about", "[media][errors]") {
    TempDir dir;
    dir.write("quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n");
    const std::string scene = dir.write("open.xml", R"(<scene>
        <integrator type="volpath"/>
        <sampler type="independent"><integer name="sampleCount" value="1"/></sampler>
        <camera type="perspective"><integer name="width" value="4"/><integer name="height" value="4"/></camera>
        <mesh type="obj"><string name="filename" value="quad.obj"/>
            <medium type="homogeneous" name="interior"/></mesh>
        <mesh type="obj"><string name="filename" value=")" +
                                                        kMediaDirectory + R"(/box.obj"/>
            <medium type="homogeneous" name="interior"/></mesh></scene>)");
    const ProcessResult result = runNori({scene, "-o", (dir.path() / "open.exr").string()});
    CHECK(result.exitCode == 0);
    CHECK_THAT(result.output, Catch::Contains("Warning") && Catch::Contains("quad.obj") &&
                                  Catch::Contains("not closed"));
    // The closed box is not warned about.
    size_t warnings = 0;
    for (size_t at = result.output.find("not closed"); at != std::string::npos;
         at = result.output.find("not closed", at + 1))
        ++warnings;
    CHECK(warnings == 1);
}

TEST_CASE("nori-make-cloud reproduces the committed cloud byte for byte", "[media]") {
    TempDir dir;
    const ProcessResult result = runCommand(MAKE_CLOUD_EXECUTABLE, {dir.path().string()});
    REQUIRE(result.exitCode == 0);
    for (const char *file : {"cloud.vol", "cloud.nvdb"})
        CHECK(readBinaryFile((dir.path() / file).string(), "generated") ==
              readBinaryFile(kMediaDirectory + "/" + file, "committed"));
}
