// Analytic shapes: the sphere's uv parameterisation as the courses define it (EPFL's and
// ETH's), and its derivatives.
#include <nori/parser.h>
#include <nori/pcg32.h>
#include <nori/shape.h>
#include <nori/warp.h>

#include <catch2/catch.hpp>

using namespace nori;

namespace {

/// The hit of a sphere (one primitive) by a ray from outside toward `target`, a point of
/// its surface whose outward normal is n.
Intersection hitFromOutside(const Shape &sphere, const Point3f &target, const Vector3f &n) {
    const Ray3f ray(target + 3.0f * n, Vector3f(-n));
    Intersection its;
    Point2f coords;
    REQUIRE(sphere.rayIntersect(0, ray, its.t, coords));
    sphere.setHitInformation(0, ray, coords, its);
    return its;
}

/// The hit's dp/du and dp/dv against central differences of the sphere's p(u, v), within
/// 10⁻³ of their lengths' scales 2πr and πr.
template <typename Position>
void checkSphereDerivatives(const Intersection &its, Position &&position, double radius) {
    const double h = 1e-4, u = its.uv.x(), v = its.uv.y();
    const Eigen::Vector3d dpdu = (position(u + h, v) - position(u - h, v)) / (2 * h);
    const Eigen::Vector3d dpdv = (position(u, v + h) - position(u, v - h)) / (2 * h);
    CHECK((its.dpdu.cast<double>() - dpdu).norm() < 1e-3 * radius * 2 * kPiDouble);
    CHECK((its.dpdv.cast<double>() - dpdv).norm() < 1e-3 * radius * kPiDouble);
}

} // namespace

TEST_CASE("Sphere uv: u = ½ + φ/2π (EPFL) or φ/2π (ETH), v = 1 − θ/π", "[shape]") {
    const Point3f center(0.5f, -1.0f, 2.0f);
    const float radius = 1.5f;
    // The convention by the sphere's own parameter (none: EPFL), and ETH's by --convention.
    const auto [parameter, commandLine, offset] =
        GENERATE(table<std::string, std::string, double>({{"", "", 0.5},
                                                          {"epfl", "", 0.5},
                                                          {"eth", "", 0.0},
                                                          {"", "eth", 0.0},
                                                          {"epfl", "eth", 0.5}}));
    INFO("convention parameter '" << parameter << "', --convention '" << commandLine << "'");
    LoadOptions options;
    options.convention = commandLine;
    const std::string xml = fmt::format(
        R"(<mesh type="sphere"><point name="center" value="0.5, -1, 2"/>
           <float name="radius" value="1.5"/>{}</mesh>)",
        parameter.empty() ? ""
                          : fmt::format(R"(<string name="convention" value="{}"/>)", parameter));
    auto sphere = std::dynamic_pointer_cast<Shape>(loadFromXMLString(xml, ".", options));
    REQUIRE(sphere);
    PCG32 random(3, 4);
    for (int i = 0; i < 200; ++i) {
        const float u1 = random.nextFloat();
        const Vector3f n = Warp::squareToUniformSphere(Point2f(u1, random.nextFloat()));
        const Intersection its = hitFromOutside(*sphere, center + radius * n, n);
        INFO("n = " << n.transpose());
        CHECK(its.uv.x() ==
              Approx(offset + std::atan2(n.y(), n.x()) / (2 * kPiDouble)).margin(1e-5));
        CHECK(its.uv.y() == Approx(1.0 - std::acos(n.z()) / kPiDouble).margin(1e-4));
        // dp/du and dp/dv by central differences of p(u, v).
        auto position = [&, offset = offset](double u, double v) -> Eigen::Vector3d {
            const double phi = 2 * kPiDouble * (u - offset), beta = kPiDouble * (v - 0.5);
            return Eigen::Vector3d(std::cos(beta) * std::cos(phi), std::cos(beta) * std::sin(phi),
                                   std::sin(beta)) *
                   radius;
        };
        checkSphereDerivatives(its, position, radius);
        // The frame is right-handed with its normal outward and s along dp/du.
        CHECK(its.geoFrame.n.dot(n) == Approx(1.0f).margin(1e-5));
        if (std::abs(n.z()) < 0.99f)
            CHECK(its.geoFrame.s.dot(its.dpdu.normalized()) == Approx(1.0f).margin(1e-4));
        CHECK(its.dpdu.cross(its.dpdv).dot(n) >= 0.0f);
    }
}

TEST_CASE("Sphere uv as Mitsuba defines them: u = φ/2π from 0 up to 1, v = θ/π",
          "[shape][mitsuba]") {
    const Point3f center(0.5f, -1.0f, 2.0f);
    const float radius = 1.5f;
    auto sphere = std::dynamic_pointer_cast<Shape>(loadFromXMLString(
        R"(<mesh type="sphere"><point name="center" value="0.5, -1, 2"/>
           <float name="radius" value="1.5"/><string name="convention" value="mitsuba"/></mesh>)"));
    REQUIRE(sphere);
    PCG32 random(5, 6);
    for (int i = 0; i < 200; ++i) {
        const float u1 = random.nextFloat();
        const Vector3f n = Warp::squareToUniformSphere(Point2f(u1, random.nextFloat()));
        const Intersection its = hitFromOutside(*sphere, center + radius * n, n);
        INFO("n = " << n.transpose());
        double phi = std::atan2(n.y(), n.x());
        if (phi < 0.0)
            phi += 2 * kPiDouble;
        CHECK(its.uv.x() == Approx(phi / (2 * kPiDouble)).margin(1e-5));
        CHECK(its.uv.y() == Approx(std::acos(n.z()) / kPiDouble).margin(1e-4));
        // dp/du and dp/dv of p(u, v) = c + r (sin θ cos φ, sin θ sin φ, cos θ), θ = πv.
        auto position = [&](double u, double v) -> Eigen::Vector3d {
            const double p = 2 * kPiDouble * u, t = kPiDouble * v;
            return Eigen::Vector3d(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p),
                                   std::cos(t)) *
                   radius;
        };
        checkSphereDerivatives(its, position, radius);
    }
}

TEST_CASE("Cube uv as Mitsuba lays them out, face by face", "[shape][mitsuba]") {
    auto cube = std::dynamic_pointer_cast<Shape>(loadFromXMLString(
        R"(<mesh type="cube"><string name="convention" value="mitsuba"/></mesh>)"));
    REQUIRE(cube);
    // One corner of each face and its uv, from Mitsuba's cube (0.6 and 3, shapes/cube.cpp):
    // the face's normal, the corner, its uv, and a second corner with its uv.
    struct FaceCorners {
        Vector3f normal;
        Point3f a;
        Point2f uvA;
        Point3f b;
        Point2f uvB;
    };
    const FaceCorners faces[] = {
        {{0, -1, 0}, {1, -1, -1}, {0, 1}, {-1, -1, 1}, {1, 0}},
        {{0, 1, 0}, {1, 1, -1}, {0, 1}, {-1, 1, 1}, {1, 0}},
        {{1, 0, 0}, {1, -1, -1}, {0, 1}, {1, 1, 1}, {1, 0}},
        {{0, 0, 1}, {1, -1, 1}, {0, 1}, {-1, 1, 1}, {1, 0}},
        {{-1, 0, 0}, {-1, -1, 1}, {0, 1}, {-1, 1, -1}, {1, 0}},
        {{0, 0, -1}, {1, 1, -1}, {0, 1}, {-1, -1, -1}, {1, 0}},
    };
    for (const FaceCorners &face : faces) {
        INFO("face " << face.normal.transpose());
        // uv are affine on a face: points between the two opposite corners.
        for (const float t : {0.1f, 0.5f, 0.8f}) {
            const Point3f target = (1.0f - t) * face.a + t * face.b;
            const Ray3f ray(target + 2.0f * face.normal, -face.normal);
            // The nearest of the cube's triangles along the ray.
            Intersection its;
            its.t = kInfinity;
            bool hit = false;
            for (uint32_t index = 0; index < cube->getPrimitiveCount(); ++index) {
                float t = 0.0f;
                Point2f coords;
                if (cube->rayIntersect(index, ray, t, coords) && t < its.t) {
                    its.t = t;
                    cube->setHitInformation(index, ray, coords, its);
                    hit = true;
                }
            }
            REQUIRE(hit);
            const Point2f expected = (1.0f - t) * face.uvA + t * face.uvB;
            CHECK(its.uv.x() == Approx(expected.x()).margin(1e-5));
            CHECK(its.uv.y() == Approx(expected.y()).margin(1e-5));
        }
    }
}
