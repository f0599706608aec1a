// Nori 2's plugin-facing API, as course code uses it (include/nori/common.h, second half,
// and the Nori 2 spellings of the other headers): each piece does what Nori 2's does.
#include <nori/bbox.h>
#include <nori/common.h>
#include <nori/frame.h>
#include <nori/fresnel.h>
#include <nori/mesh.h>
#include <nori/scene.h>
#include <nori/timer.h>
#include <nori/warp.h>

#include <filesystem/resolver.h>

#include "testutil.h"

#include <catch2/catch.hpp>

using namespace nori;
using nori::testing::errorOf;
using nori::testing::loadScene;

TEST_CASE("tfm::format formats printf-style, any argument with %s", "[nori2]") {
    CHECK(tfm::format("%s %d %i %f %g %.3f", "a", 12, -3, 0.5f, 0.25, 3.14159) ==
          "a 12 -3 0.500000 0.25 3.142");
    CHECK(tfm::format("[%5d|%-4s|%8.2f]", 42, "ab", 2.5) == "[   42|ab  |    2.50]");
    CHECK(tfm::format("%s and %s", Color3f(1, 2, 3).toString(), std::string("text")) ==
          "[1, 2, 3] and text");
    CHECK(tfm::format("%s", 7) == "7"); // %s prints anything, as tinyformat does
    CHECK(tfm::format("100%%") == "100%");
    // A format that does not fit its arguments gives the format and why, never throws.
    CHECK_THAT(tfm::format("%d", "text"), Catch::Contains("bad format"));
}

TEST_CASE("NoriException formats printf's and fmt's syntax", "[nori2]") {
    CHECK(std::string(NoriException("%s has %d faces", "mesh", 12).what()) == "mesh has 12 faces");
    CHECK(std::string(NoriException("{} has {} faces", "mesh", 12).what()) == "mesh has 12 faces");
    CHECK(std::string(NoriException("%.2f%%", 12.345f).what()) == "12.35%");
    CHECK(std::string(NoriException("no arguments: %s {}").what()) == "no arguments: %s {}");
}

TEST_CASE("common.h's constants and helpers", "[nori2]") {
    CHECK(Epsilon == 1e-4f);
    static_assert(std::is_same_v<decltype(M_PI), float>, "M_PI is a float, as in Nori 2");
    CHECK(INV_PI * M_PI == Approx(1.0f));
    CHECK(INV_TWOPI == Approx(0.5f / M_PI));
    CHECK(INV_FOURPI == Approx(0.25f / M_PI));
    CHECK(SQRT_TWO * INV_SQRT_TWO == Approx(1.0f));
    CHECK(clamp(1.5f, 0.0f, 1.0f) == 1.0f);
    CHECK(clamp(-2, 0, 5) == 0);
    CHECK(lerp(0.25f, 2.0f, 6.0f) == 3.0f); // Nori 2's order: the weight first
    CHECK(mod(-1, 3) == 2);
    CHECK(radToDeg(degToRad(30.0f)) == Approx(30.0f));
    CHECK(fresnel(0.7f, 1.0f, 1.5f) == fresnelDielectric(0.7f, 1.0f, 1.5f));
    const Vector3f d = sphericalDirection(0.8f, 2.0f);
    CHECK(d.norm() == Approx(1.0f));
    const Point2f thetaPhi = sphericalCoordinates(d);
    CHECK(thetaPhi.x() == Approx(0.8f));
    CHECK(thetaPhi.y() == Approx(2.0f));
    Vector3f s, t;
    coordinateSystem(Vector3f(0, 0, 1), s, t);
    CHECK(std::abs(s.dot(t)) < 1e-6f);
}

TEST_CASE("common.h's string, time and memory helpers", "[nori2]") {
    CHECK(toLower("MiXeD") == "mixed");
    CHECK(toBool("TRUE"));
    CHECK_FALSE(toBool("false"));
    CHECK_THAT(errorOf([] { toBool("yes"); }), Catch::Contains("'yes'"));
    CHECK(toInt("-12") == -12);
    CHECK(toUInt("12") == 12u);
    CHECK_THAT(errorOf([] { toUInt("-1"); }), Catch::Contains("unsigned"));
    CHECK(toFloat("0.5") == 0.5f);
    CHECK(toVector3f("1, 2 3") == Eigen::Vector3f(1, 2, 3));
    CHECK(tokenize("a, b,,c") == std::vector<std::string>{"a", "b", "c"});
    CHECK(tokenize("a,,b", ",", true) == std::vector<std::string>{"a", "", "b"});
    CHECK(endsWith("scene.xml", ".xml"));
    CHECK(indent("a\nb", 2) == "a\n  b");
    CHECK(timeString(1500.0) == "1.5s");
    CHECK(timeString(12.0) == "12.0ms");
    CHECK(memString(512) == "512 B");
    CHECK(memString(3 * 1024 * 1024) == "3.0 MiB");
    CHECK(getCoreCount() >= 1);
    Timer timer;
    CHECK(timer.elapsed() >= 0.0);
    CHECK_FALSE(timer.elapsedString().empty());
}

TEST_CASE("Colours and vectors from one number, implicitly", "[nori2]") {
    const Color3f black = 0.0f;
    CHECK((black == 0.0f).all());
    auto grey = []() -> Color3f { return 0.5f; };
    CHECK(grey().isApprox(Color3f(0.5f, 0.5f, 0.5f)));
    CHECK(Color3f(-1.0f, 2.0f, -3.0f).clamp().isApprox(Color3f(0.0f, 2.0f, 0.0f)));
    const Vector3f zero = 0.0f;
    CHECK(zero.isZero());
    CHECK(Color4f(Color3f(1, 2, 3)).w() == 1.0f);
    CHECK(Vector3f(1, 2, 3).toString() == "[1, 2, 3]");
    CHECK(Vector4f(1, 2, 3, 4).w() == 4.0f);
}

TEST_CASE("Frames, rays and boxes have Nori 2's members", "[nori2]") {
    const Frame frame(Vector3f(0, 0, 1));
    CHECK(Frame::cosPhi2(Vector3f(1, 0, 0)) == Approx(1.0f));
    CHECK(Frame::sinPhi2(Vector3f(1, 0, 0)) == Approx(0.0f));
    CHECK(frame == Frame(Vector3f(0, 0, 1)));
    const Ray3f ray(Point3f(0, 0, 0), Vector3f(1, 0, 0));
    CHECK(ray.reverse().d == Vector3f(-1, 0, 0));
    CHECK(Ray3f(ray, 1.0f, 2.0f).maxt == 2.0f);
    BoundingBox3f box(Point3f(0, 0, 0), Point3f(1, 2, 3));
    CHECK(box.getVolume() == 6.0f);
    CHECK(box.getMajorAxis() == 2);
    CHECK(box.getMinorAxis() == 0);
    CHECK(box.getCorner(7) == Point3f(1, 2, 3));
    CHECK(box.contains(Point3f(0, 0, 0)));
    CHECK_FALSE(box.contains(Point3f(0, 0, 0), true));
    CHECK(box.overlaps(BoundingBox3f(Point3f(0.5f, 0.5f, 0.5f), Point3f(4, 4, 4))));
    CHECK(box.distanceTo(Point3f(4, 2, 3)) == Approx(3.0f));
    CHECK(box.rayIntersect(Ray3f(Point3f(-1, 1, 1), Vector3f(1, 0, 0))));
    CHECK(BoundingBox3f::merge(box, BoundingBox3f(Point3f(-1, 0, 0))).min.x() == -1.0f);
}

TEST_CASE("Meshes, hits and the scene answer Nori 2's accessors", "[nori2]") {
    const auto scene = loadScene(R"(<scene><integrator type="normals"/>
        <camera type="perspective"/>
        <mesh type="obj"><string name="filename" value="meshes/floor.obj"/>
            <bsdf type="diffuse"/></mesh>
        <mesh type="sphere"><point name="center" value="0, 3, 0"/><float name="radius" value="1"/>
            <emitter type="area"><color name="radiance" value="1"/></emitter></mesh>
        </scene>)",
                                 std::string(NORI_SOURCE_DIR) + "/scenes/textured");
    REQUIRE(scene->getMeshes().size() == 1); // the sphere is a shape, not a Mesh
    const Mesh *mesh = scene->getMeshes().front();
    CHECK(mesh->getVertexPositions().rows() == 3);
    CHECK(mesh->getVertexPositions().cols() == mesh->getVertexCount());
    CHECK(mesh->getIndices().cols() == mesh->getTriangleCount());
    for (uint32_t i = 0; i < mesh->getVertexCount(); ++i)
        CHECK(mesh->getVertexPositions().col(i) == mesh->positions()[i]);
    CHECK(mesh->getIndices().col(0).cast<int>() == mesh->faces()[0]);
    CHECK(mesh->getCentroid(0) == mesh->getPrimitiveCentroid(0));
    CHECK_FALSE(mesh->isEmitter());

    // Through Nori 2's pointer to the acceleration structure, down onto the floor...
    const Accel *accel = scene->getAccel();
    Intersection its;
    REQUIRE(accel->rayIntersect(Ray3f(Point3f(0.1f, 1, 0.1f), Vector3f(0, -1, 0)), its, false));
    CHECK(its.mesh == mesh);
    CHECK(its.mesh->getBSDF() != nullptr);
    float u, v, t;
    CHECK(mesh->rayIntersect(its.primIndex, Ray3f(Point3f(0.1f, 1, 0.1f), Vector3f(0, -1, 0)), u, v,
                             t));
    CHECK(t == Approx(its.t));
    // ... and up into the light, a sphere: its.mesh is any shape.
    REQUIRE(scene->rayIntersect(Ray3f(Point3f(0, 0.5f, 0), Vector3f(0, 1, 0)), its));
    CHECK(its.mesh == its.shape);
    CHECK(its.mesh->isEmitter());
    CHECK(scene->getSampler() != nullptr);
    CHECK(scene->getIntegrator() != nullptr);
    CHECK(scene->getCamera() != nullptr);
}

TEST_CASE("Warp has the course's functions", "[nori2]") {
    CHECK(Warp::squareToUniformSquare(Point2f(0.25f, 0.5f)) == Point2f(0.25f, 0.5f));
    const Point2f inTriangle = Warp::squareToUniformTriangle(Point2f(0.9f, 0.8f));
    CHECK(inTriangle.x() + inTriangle.y() <= 1.0f);
    CHECK(Warp::squareToUniformTrianglePdf(inTriangle) == 2.0f);
    CHECK(Warp::squareToUniformTrianglePdf(Point2f(0.8f, 0.8f)) == 0.0f);
}

TEST_CASE("getFileResolver finds files next to the scene being loaded", "[nori2]") {
    filesystem::resolver *resolver = getFileResolver();
    const size_t before = resolver->size();
    // While a scene loads, its folder comes first; afterwards it is gone again.
    loadScene(R"(<scene><integrator type="normals"/><camera type="perspective"/></scene>)",
              std::string(NORI_SOURCE_DIR) + "/scenes/textured");
    CHECK(resolver->size() == before);
    filesystem::resolver local;
    local.prepend(std::string(NORI_SOURCE_DIR) + "/scenes/textured");
    const filesystem::path found = local.resolve("meshes/floor.obj");
    CHECK(found.is_file());
    CHECK(found.extension() == "obj");
    CHECK(found.filename() == "floor.obj");
}
