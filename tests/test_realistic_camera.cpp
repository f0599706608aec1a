// The realistic camera: lens files, the traced optics against paraxial theory, focusing,
// exit-pupil sampling (its waste and its bias) and vignetting.
#include <nori/bitmap.h>
#include <nori/camera.h>
#include <nori/lenssystem.h>
#include <nori/parser.h>
#include <nori/pcg32.h>

#include "testutil.h"

#include <catch2/catch.hpp>

#include <cmath>

using namespace nori;
using Catch::Contains;
using nori::testing::distanceToRay;
using nori::testing::errorOf;
using nori::testing::runNori;
using nori::testing::TempDir;

namespace {

std::string lensPath(const std::string &name) {
    return std::string(NORI_SOURCE_DIR) + "/scenes/lenses/" + name;
}

/// Effective focal length and back focal distance (rear vertex to focal point) of a
/// prescription by the paraxial ray trace y' = y + t·u, n'u' = nu − y(n' − n)/R (Hecht,
/// Optics §6.2; Smith, Modern Optical Engineering §3.2), independent of the exact tracer.
std::pair<double, double> paraxialFocalLengths(const std::vector<LensInterfaceRow> &rows) {
    const double height = 1.0; // paraxial: any height, the equations are linear
    double y = height, nu = 0.0, n = 1.0;
    for (size_t i = 0; i < rows.size(); ++i) {
        const double nNext = rows[i].eta;
        if (rows[i].curvatureRadius != 0.0)
            nu -= y * (nNext - n) / rows[i].curvatureRadius;
        n = nNext;
        if (i + 1 < rows.size())
            y += rows[i].thickness * nu / n;
    }
    const double u = nu / n;
    return {-height / u, -y / u};
}

std::shared_ptr<Camera> makeRealistic(const std::string &parameters, int width = 600,
                                      int height = 400) {
    auto camera = std::dynamic_pointer_cast<Camera>(loadFromXMLString(fmt::format(
        R"(<camera type="realistic"><integer name="width" value="{}"/><integer name="height" value="{}"/>
            <string name="lensFile" value="{}"/>{}</camera>)",
        width, height, lensPath("dgauss.50mm.dat"), parameters)));
    REQUIRE(camera);
    return camera;
}

/// The width of the 35 mm-diagonal 3:2 film of the tests' 600×400 images: 29.1 mm.
const double kFilmWidth = filmExtent(35.0e-3, 600, 400).x();

/// The double-Gauss lens focused at `distance`, as the camera of makeRealistic has it.
LensSystem focusedDoubleGauss(double distance) {
    LensSystem lens(readLensFile(lensPath("dgauss.50mm.dat")), 0.0, "dgauss");
    lens.focusAt(distance);
    return lens;
}

/// Two independent Monte Carlo means agree when they differ by less than four standard
/// errors (a false alarm once in 16 000 comparisons; the seeds are fixed).
bool meansAgree(const RunningMoments &a, const RunningMoments &b) {
    const double standardError = std::sqrt(a.variance() / a.count + b.variance() / b.count);
    return std::abs(a.mean - b.mean) < 4.0 * standardError;
}

} // namespace

TEST_CASE("A paraxial ray through the double-Gauss lens meets the focal point of its "
          "prescription",
          "[camera][realistic]") {
    const std::vector<LensInterfaceRow> rows = readLensFile(lensPath("dgauss.50mm.dat"));
    const LensSystem lens(rows, 0.0, "dgauss");
    const LensSystem::CardinalPoints points = lens.cardinalPoints();
    const auto [paraxialFocal, paraxialBack] = paraxialFocalLengths(rows);
    const double traced = 1e3 * points.effectiveFocalLength();
    const double tracedBack = 1e3 * (lens.rearZ() - points.rearFocalZ);
    INFO("traced f = " << traced << " mm, back focal distance " << tracedBack << " mm; paraxial "
                       << paraxialFocal << " mm, " << paraxialBack << " mm");
    // The exact tracer at a paraxial height (1e-3 of the smallest aperture) agrees with
    // first-order optics to its (h/R)² ~ 1e-6 error.
    CHECK(traced == Approx(paraxialFocal).epsilon(1e-4));
    CHECK(tracedBack == Approx(paraxialBack).epsilon(1e-4));
    // The prescription is a 50 mm lens (the rounding of its radii to 0.005 mm moves f).
    CHECK(traced == Approx(50.0).epsilon(0.01));
    // The front focal length equals the rear one: air on both sides.
    CHECK(1e3 * (points.frontFocalZ - points.frontPrincipalZ) == Approx(traced).epsilon(1e-4));

    // The other shipped lenses are what their files say they are.
    for (const auto &[file, focalLength] :
         {std::pair<const char *, double>{"wide.22mm.dat", 22.0}, {"fisheye.10mm.dat", 10.0}}) {
        const LensSystem other(readLensFile(lensPath(file)), 0.0, file);
        INFO(file);
        CHECK(1e3 * other.cardinalPoints().effectiveFocalLength() ==
              Approx(focalLength).epsilon(0.01));
    }

    // The control: one index mistyped (1.67 for 1.57 in the first element) is caught.
    std::vector<LensInterfaceRow> mistyped = rows;
    mistyped[0].eta = 1.57;
    CHECK(1e3 * LensSystem(mistyped, 0.0, "mistyped").cardinalPoints().effectiveFocalLength() !=
          Approx(50.0).epsilon(0.01));
}

TEST_CASE("A point at the focus distance is imaged smaller than a pixel", "[camera][realistic]") {
    // 600 pixels across the 29.1 mm width of a 35 mm-diagonal 3:2 film: 48.5 µm pixels,
    // whose footprint at distance D is pixel·D/f' (f' the image distance, about f). At
    // f/4: wide open (f/2) the lens's spherical aberration alone spreads 1.6 pixels, and
    // focusing by the paraxial thick lens is not the best focus of the marginal rays.
    const double focus = 2.0;
    auto camera = makeRealistic(R"(<float name="focusDistance" value="2"/>
        <float name="apertureDiameter" value="8.5"/>)");
    const double pixel = kFilmWidth / 600.0;
    const double footprint = pixel * focus / 0.0514; // 1/s + 1/s' = 1/f: s' = 51.4 mm
    PCG32 random(3, 5);
    // On the axis (the film centre) and 60% of the way to the image's right edge.
    for (const Point2f &film : {Point2f(300.0f, 200.0f), Point2f(480.0f, 200.0f)}) {
        Ray3f chief;
        REQUIRE(camera->sampleRay(chief, film, Point2f(0.5f, 0.5f))[0] > 0.0f);
        // The point of the chief ray at the focus distance (the film is the plane z = 0).
        auto pointAt = [&](double distance) {
            const double t = (distance - chief.o.z()) / chief.d.z();
            return Point3f((chief.o.cast<double>() + t * chief.d.cast<double>()).cast<float>());
        };
        double inFocus = 0.0, defocused = 0.0;
        int passed = 0;
        for (int i = 0; i < 2000; ++i) {
            Ray3f ray;
            if (camera->sampleRay(ray, film, Point2f(random.nextFloat(), random.nextFloat()))[0] ==
                0.0f)
                continue;
            ++passed;
            inFocus = std::max(inFocus, double(distanceToRay(pointAt(focus), ray)));
            defocused = std::max(defocused, double(distanceToRay(pointAt(2.0 * focus), ray)));
        }
        INFO("film position " << film.transpose() << ": " << passed << " rays; the widest passes "
                              << inFocus * 1e3 << " mm from the point in focus, footprint "
                              << footprint * 1e3 << " mm");
        REQUIRE(passed > 1000);
        // Every ray passes within half a pixel's footprint: the spot is under a pixel.
        CHECK(2.0 * inFocus < footprint);
        // The control: a point twice as far is blurred over several pixels.
        CHECK(2.0 * defocused > 3.0 * footprint);
    }
}

TEST_CASE("Wide open, the root-mean-square spot of a point in focus is under a pixel",
          "[camera][realistic]") {
    // At f/2 the marginal rays of the double Gauss stray (spherical aberration: its
    // widest rays miss by 1.6 pixels); the spot's RMS diameter, the size that an image
    // shows, stays under the 48.5 µm pixel. Rays from the axial point at 2 m to the film.
    const LensSystem lens = focusedDoubleGauss(2.0);
    const double frontRadius = 0.5 * 25.2e-3;
    PCG32 random(4, 6);
    RunningMoments squaredRadius;
    for (int i = 0; i < 20000; ++i) {
        const Eigen::Vector3d object(0.0, 0.0, 2.0);
        const Eigen::Vector3d target(frontRadius * (2.0 * random.nextFloat() - 1.0),
                                     frontRadius * (2.0 * random.nextFloat() - 1.0), lens.frontZ());
        LensRay out;
        if (!lens.traceFromScene({object, (target - object).normalized()}, &out))
            continue;
        squaredRadius.add(out.at(-out.o.z() / out.d.z()).head<2>().squaredNorm());
    }
    const double rmsDiameter = 2.0 * std::sqrt(squaredRadius.mean);
    INFO(squaredRadius.count << " rays; RMS spot diameter " << rmsDiameter * 1e6 << " µm");
    REQUIRE(squaredRadius.count > 10000);
    CHECK(rmsDiameter < kFilmWidth / 600.0);
    // The control: the lens focused at 1 m (the film 1.3 mm off) spreads it over pixels.
    LensSystem defocused = focusedDoubleGauss(2.0);
    defocused.focusAt(1.0);
    RunningMoments blurred;
    for (int i = 0; i < 2000; ++i) {
        const Eigen::Vector3d object(0.0, 0.0, 2.0);
        const Eigen::Vector3d target(frontRadius * (2.0 * random.nextFloat() - 1.0),
                                     frontRadius * (2.0 * random.nextFloat() - 1.0),
                                     defocused.frontZ());
        LensRay out;
        if (defocused.traceFromScene({object, (target - object).normalized()}, &out))
            blurred.add(out.at(-out.o.z() / out.d.z()).head<2>().squaredNorm());
    }
    CHECK(2.0 * std::sqrt(blurred.mean) > 3.0 * kFilmWidth / 600.0);
}

TEST_CASE("Exit-pupil sampling loses far fewer rays than sampling the rear element",
          "[camera][realistic]") {
    // The fisheye loses more toward its exit pupil (17.8 %) than the others: off axis its
    // pupil narrows to a cat's eye (1.4 × 5.5 mm at 13 mm off axis, against 6 mm across on
    // axis), which the tabulated ellipse bounds loosely. That is the ellipse's fit to the
    // pupil's shape, not the tabulation's resolution: 1024 radii of 32768 rays each,
    // instead of 64 of 8192, still lose 13.5 % (measured with ExitPupil's own arguments).
    // Its bound is the comparison with sampling the rear element, which it meets.
    const Eigen::Vector2d film(kFilmWidth, kFilmWidth * 2.0 / 3.0);
    for (const char *file : {"dgauss.50mm.dat", "wide.22mm.dat", "fisheye.10mm.dat"}) {
        const bool fisheye = std::string(file) == "fisheye.10mm.dat";
        LensSystem lens(readLensFile(lensPath(file)), 0.0, file);
        lens.focusAt(4.0);
        const ExitPupil pupil(lens, 0.5 * film.norm());
        const RayLoss withPupil = measureRayLoss(lens, &pupil, film, 1 << 16);
        const RayLoss without = measureRayLoss(lens, nullptr, film, 1 << 16);
        INFO(file << ": " << 100.0 * withPupil.blocked << "% blocked with the exit pupil, "
                  << 100.0 * without.blocked << "% without");
        if (!fisheye)
            CHECK(withPupil.blocked < 0.15);
        CHECK(withPupil.blocked < without.blocked / 3.0);
        // The double Gauss and the wide angle cover the film; the fisheye's image circle
        // leaves its corners dark.
        if (fisheye)
            CHECK(withPupil.unlit > 0.1);
        else
            CHECK(withPupil.unlit == 0.0);
    }
}

TEST_CASE("Exit-pupil sampling is unbiased: the camera's weights match the film irradiance",
          "[camera][realistic]") {
    // The camera's mean weight at a film point is its irradiance relative to the centre's;
    // estimated independently by sampling the square the pupil search starts from
    // (1.5 rear radii), weight cos⁴θ·A/z² where the ray passes.
    const double focus = 3.0;
    auto camera = makeRealistic(R"(<float name="focusDistance" value="3"/>)");
    const LensSystem lens = focusedDoubleGauss(focus);
    const ExitPupil pupil(lens, 0.5 * 35e-3);
    const double extent = 1.5 * lens.rearApertureRadius(), z = lens.rearZ();

    PCG32 random(7, 11);
    auto irradiance = [&](const Eigen::Vector3d &film, const Eigen::Vector3d &rear, double area) {
        const Eigen::Vector3d d = (rear - film).normalized();
        return lens.traceFromFilm({film, d}, nullptr) ? std::pow(d.z(), 4) * area / (z * z) : 0.0;
    };
    auto bruteForce = [&](const Eigen::Vector3d &film) {
        RunningMoments moments;
        for (int i = 0; i < 200000; ++i) {
            const Eigen::Vector3d rear(extent * (2.0 * random.nextFloat() - 1.0),
                                       extent * (2.0 * random.nextFloat() - 1.0), z);
            moments.add(irradiance(film, rear, 4.0 * extent * extent));
        }
        return moments;
    };
    const RunningMoments centre = bruteForce(Eigen::Vector3d::Zero());
    for (const float u : {0.5f, 0.7f, 0.85f, 0.999f}) {
        // Pixel column u·600 of the middle row; the film point of the same radius.
        const Eigen::Vector3d film((u - 0.5) * kFilmWidth, 0.0, 0.0);
        RunningMoments reference = bruteForce(film);
        reference.mean /= centre.mean;
        reference.m2 /= centre.mean * centre.mean;
        RunningMoments weights, axialPupil;
        for (int i = 0; i < 200000; ++i) {
            Ray3f ray;
            const Point2f aperture(random.nextFloat(), random.nextFloat());
            weights.add(camera->sampleRay(ray, Point2f(u * 600.0f, 200.0f), aperture)[0]);
            // The control: the pupil of the film's centre used at every film point.
            double area = 0.0;
            const Eigen::Vector3d rear =
                pupil.sample(Eigen::Vector2d::Zero(), aperture.cast<double>(), &area);
            axialPupil.add(irradiance(film, rear, area) / centre.mean);
        }
        INFO("film x = " << film.x() * 1e3 << " mm: camera weight " << weights.mean
                         << ", irradiance ratio " << reference.mean << ", with the axial pupil "
                         << axialPupil.mean);
        CHECK(meansAgree(weights, reference));
        if (u > 0.8f) // far off axis, where the pupil has moved
            CHECK_FALSE(meansAgree(axialPupil, reference));
    }
}

TEST_CASE("A uniformly bright scene renders at its radiance in the centre and vignettes "
          "toward the corners",
          "[camera][realistic][cli]") {
    TempDir dir;
    const std::string scene = dir.write("scene.xml", fmt::format(R"(<scene>
        <integrator type="path_mis"/>
        <sampler type="independent"><integer name="sampleCount" value="256"/></sampler>
        <camera type="realistic"><string name="lensFile" value="{}"/>
            <integer name="width" value="30"/><integer name="height" value="20"/>
            <float name="focusDistance" value="5"/>
            <rfilter type="box"/>
        </camera>
        <emitter type="constant"><color name="radiance" value="1, 1, 1"/></emitter>
    </scene>)",
                                                                 lensPath("dgauss.50mm.dat")));
    auto result = runNori({"--no-progress", "-o", (dir.path() / "out").string(), scene});
    INFO(result.output);
    REQUIRE(result.exitCode == 0);
    const Bitmap image = Bitmap::load((dir.path() / "out.exr").string());
    // The four pixels around the centre: 1024 samples of weights whose spread is ~0.3.
    const float centre =
        (image(9, 14) + image(9, 15) + image(10, 14) + image(10, 15)).mean() / 4.0f;
    const float corner = image(0, 0).mean();
    INFO("centre " << centre << ", corner " << corner);
    CHECK(centre == Approx(1.0f).epsilon(0.04));
    CHECK(corner < 0.6f * centre);
    CHECK(corner > 0.05f);
    for (int y = 0; y < image.height(); ++y)
        for (int x = 0; x < image.width(); ++x)
            REQUIRE(image(y, x).isValid());
}

TEST_CASE("Ray differentials of the realistic camera span one pixel", "[camera][realistic]") {
    auto camera = makeRealistic(R"(<float name="focusDistance" value="4"/>)");
    const double pixelAngle = kFilmWidth / 600.0 / 0.0506;
    PCG32 random(2, 9);
    for (int i = 0; i < 100; ++i) {
        const Point2f film(100.0f + 400.0f * random.nextFloat(),
                           50.0f + 300.0f * random.nextFloat());
        Ray3f ray;
        if (camera->sampleRayDifferential(
                ray, film, Point2f(random.nextFloat(), random.nextFloat()))[0] == 0.0f)
            continue;
        REQUIRE(ray.hasDifferentials);
        const double dx = (ray.rxDirection - ray.d).norm(), dy = (ray.ryDirection - ray.d).norm();
        INFO("film " << film.transpose() << ": " << dx << ", " << dy << " against " << pixelAngle);
        CHECK(dx == Approx(pixelAngle).epsilon(0.1));
        CHECK(dy == Approx(pixelAngle).epsilon(0.1));
    }
}

TEST_CASE("A cropped realistic camera traces the full image's rays", "[camera][realistic][crop]") {
    auto full = makeRealistic(R"(<float name="focusDistance" value="4"/>)");
    auto cropped = makeRealistic(R"(<float name="focusDistance" value="4"/>
        <integer name="cropOffsetX" value="150"/><integer name="cropOffsetY" value="40"/>
        <integer name="cropWidth" value="200"/><integer name="cropHeight" value="100"/>)");
    CHECK(cropped->getOutputSize() == Vector2i(200, 100));
    PCG32 random(8, 1);
    int traced = 0;
    for (int i = 0; i < 200; ++i) {
        const Point2f film(200.0f * random.nextFloat(), 100.0f * random.nextFloat());
        const Point2f aperture(random.nextFloat(), random.nextFloat());
        Ray3f a, b;
        const Color3f weightA = cropped->sampleRay(a, film, aperture);
        const Color3f weightB =
            full->sampleRay(b, Point2f(film + Point2f(150.0f, 40.0f)), aperture);
        REQUIRE(weightA[0] == Approx(weightB[0]).epsilon(1e-6));
        if (weightA[0] == 0.0f)
            continue;
        ++traced;
        CHECK(a.o.isApprox(b.o, 1e-6f));
        CHECK(a.d.isApprox(b.d, 1e-6f));
    }
    CHECK(traced > 100);
}

TEST_CASE("Lens files and realistic-camera parameters: clear errors", "[camera][realistic]") {
    auto parse = [](const std::string &text) { return parseLensPrescription(text, "lens.dat"); };
    CHECK_THAT(errorOf([&] { parse("# a comment\n29.475 3.76 1.67\n"); }),
               Contains("lens.dat:2: a lens row holds 4 numbers") && Contains("got 3"));
    CHECK_THAT(errorOf([&] { parse("29.475 3.76 1.67 25.2\n84.83 0.12 glass 25.2\n"); }),
               Contains("lens.dat:2: the index of refraction 'glass' is not a finite number"));
    CHECK_THAT(errorOf([&] { parse("29.475 3.76 1.67 25.2\n0 4.5 0 0\n"); }),
               Contains("lens.dat:2: the aperture diameter must be positive, got 0 mm"));
    CHECK_THAT(errorOf([&] { parse("29.475 3.76 1.67 -3\n"); }),
               Contains("lens.dat:1: the aperture diameter must be positive"));
    CHECK_THAT(errorOf([&] { parse("29.475 -1 1.67 25\n"); }),
               Contains("lens.dat:1: the thickness must not be negative"));
    CHECK_THAT(errorOf([&] { parse("29.475 1 0.5 25\n"); }),
               Contains("lens.dat:1: the index of refraction must be 0 (air) or at least 1"));
    CHECK_THAT(
        errorOf([&] { parse("10 1 1.5 25\n"); }),
        Contains("lens.dat:1: a sphere of radius 10 mm cannot hold an aperture of diameter 25"));
    CHECK_THAT(errorOf([&] { parse("29.475 1 1.5 25\n0 1 0 20\n"); }),
               Contains("lens.dat:2: an aperture stop (radius 0) lies between two media"));
    CHECK_THAT(errorOf([&] { parse("# nothing\n\n"); }),
               Contains("lens.dat: the lens file holds no rows"));
    CHECK_THAT(errorOf([&] { parse("0 5 0 10\n"); }), Contains("no refracting surface"));
    CHECK_THAT(errorOf([&] { parse("29.475 3.76 nan 25.2\n"); }),
               Contains("is not a finite number"));
    // A biconcave lens spreads light: no image.
    CHECK_THAT(errorOf([&] {
                   LensSystem(parse("-50 2 1.5 20\n50 40 0 20\n"), 0.0, "lens.dat").focusAt(1.0);
               }),
               Contains("lens.dat: the lens diverges light"));

    // Through the camera (the parser adds the XML location).
    CHECK_THAT(
        errorOf([] { makeRealistic(R"(<float name="focusDistance" value="0.1"/>)"); }),
        Contains("'focusDistance' 0.1 is closer than this lens can focus: the nearest is 0.19"));
    CHECK_THAT(errorOf([] { makeRealistic(R"(<float name="apertureDiameter" value="0"/>)"); }),
               Contains("'apertureDiameter' must be positive, got 0 mm"));
    CHECK_THAT(errorOf([] { makeRealistic(R"(<float name="apertureDiameter" value="30"/>)"); }),
               Contains("'apertureDiameter' 30 mm is wider than the aperture stop") &&
                   Contains("(line 11), which opens to 17.1 mm"));
    CHECK_NOTHROW(makeRealistic(R"(<float name="apertureDiameter" value="17.1"/>)"));
    CHECK_THAT(errorOf([] { makeRealistic(R"(<float name="filmDiagonal" value="-35"/>)"); }),
               Contains("'filmDiagonal' must be positive"));
    CHECK_THAT(
        errorOf([] {
            loadFromXMLString(
                R"(<camera type="realistic"><string name="lensFile" value="missing.dat"/></camera>)");
        }),
        Contains("lens file") && Contains("missing.dat"));
}

TEST_CASE("The realistic camera frames the scene as a pinhole of its field of view",
          "[camera][realistic]") {
    // Chief rays (through the pupil's centre) leave the lens at the angle their film point
    // makes at the rear principal plane: tan θ = h / s' (Hecht, Optics §6.1). A
    // perspective camera of that field of view, same convention, looks the same way, up
    // to the lens's distortion (under 1% for a double Gauss).
    const double focus = 1000.0;
    auto realistic = makeRealistic(R"(<float name="focusDistance" value="1000"/>)");
    const double imageDistance = focusedDoubleGauss(focus).cardinalPoints().rearPrincipalZ;
    const double fov = 2.0 * std::atan(0.5 * kFilmWidth / imageDistance) * 180.0 / kPiDouble;
    auto pinhole = std::dynamic_pointer_cast<Camera>(loadFromXMLString(fmt::format(
        R"(<camera type="perspective"><integer name="width" value="600"/><integer name="height" value="400"/>
            <float name="fov" value="{}"/></camera>)",
        fov)));
    REQUIRE(pinhole);
    double worst = 0.0;
    for (const Point2f &film :
         {Point2f(300.5f, 200.5f), Point2f(450.0f, 200.0f), Point2f(590.0f, 200.0f),
          Point2f(100.0f, 300.0f), Point2f(10.0f, 10.0f), Point2f(590.0f, 390.0f)}) {
        Ray3f lensRay, pinholeRay;
        REQUIRE(realistic->sampleRay(lensRay, film, Point2f(0.5f, 0.5f))[0] > 0.0f);
        pinhole->sampleRay(pinholeRay, film, Point2f(0.5f, 0.5f));
        const Vector3f d = pinholeRay.d.normalized();
        // Distortion: the relative error of the image height tan θ.
        const double tanLens = std::hypot(lensRay.d.x(), lensRay.d.y()) / lensRay.d.z();
        const double tanPinhole = std::hypot(d.x(), d.y()) / d.z();
        INFO("pixel " << film.transpose() << ": lens " << lensRay.d.transpose() << ", pinhole "
                      << d.transpose());
        // Same side (the convention) and nearly the same direction.
        CHECK(lensRay.d.x() * d.x() >= 0.0f);
        CHECK(lensRay.d.y() * d.y() >= 0.0f);
        if (tanPinhole > 0.05)
            worst = std::max(worst, std::abs(tanLens / tanPinhole - 1.0));
        CHECK(lensRay.d.dot(d) > std::cos(0.01 * fov * kPiDouble / 180.0));
    }
    INFO("largest distortion " << 100.0 * worst << "%");
    CHECK(worst < 0.01);
    CHECK(worst > 0.0); // a real lens, not a pinhole in disguise
}
