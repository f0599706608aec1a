// The OBJ loader: the forms that occur in the wild, and errors with line numbers.
#include <nori/mesh.h>
#include <nori/parser.h>
#include <nori/scene.h>

#include "testutil.h"

#include <catch2/catch.hpp>

using namespace nori;
using Catch::Contains;
using nori::testing::errorOf;
using nori::testing::TempDir;

namespace {

std::shared_ptr<Mesh> loadObj(const TempDir &dir, const std::string &obj) {
    dir.write("mesh.obj", obj);
    PropertyList props;
    props.set("filename", std::string("mesh.obj"), "", dir.path().string());
    return std::dynamic_pointer_cast<Mesh>(
        NoriObjectFactory::createInstance("obj", NoriObject::EMesh, props));
}

std::string objError(const std::string &obj) {
    TempDir dir;
    return errorOf([&] { loadObj(dir, obj); });
}

} // namespace

TEST_CASE("OBJ: a triangle without normals or uvs", "[obj]") {
    TempDir dir;
    auto mesh = loadObj(dir, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    REQUIRE(mesh->getPrimitiveCount() == 1);
    CHECK(mesh->normals().empty());
    CHECK(mesh->texCoords().empty());
    CHECK(mesh->surfaceArea(0) == Approx(0.5f));

    Intersection its;
    float t;
    Point2f coords;
    Ray3f ray(Point3f(0.25f, 0.25f, 1.0f), Vector3f(0, 0, -1));
    REQUIRE(mesh->rayIntersect(0, ray, t, coords));
    its.t = t;
    mesh->setHitInformation(0, ray, coords, its);
    CHECK(t == Approx(1.0f));
    CHECK(its.p.isApprox(Point3f(0.25f, 0.25f, 0.0f)));
    CHECK(its.geoFrame.n.isApprox(Normal3f(0, 0, 1)));
    CHECK(its.shFrame.n.isApprox(Normal3f(0, 0, 1)));
    // Barycentric uvs when the file has none.
    CHECK(its.uv.isApprox(Point2f(0.25f, 0.25f)));
}

TEST_CASE("OBJ: vertex normals decide the front side, whatever the winding", "[obj]") {
    // Wound counter-clockwise seen from +z (normal +z), but the normals point to −z.
    TempDir dir;
    auto mesh = loadObj(dir, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 -1\nf 1//1 2//1 3//1\n");
    Intersection its;
    float t;
    Point2f coords;
    const Ray3f ray(Point3f(0.25f, 0.25f, -1.0f), Vector3f(0, 0, 1));
    REQUIRE(mesh->rayIntersect(0, ray, t, coords));
    its.t = t;
    mesh->setHitInformation(0, ray, coords, its);
    CHECK(its.shFrame.n.isApprox(Normal3f(0, 0, -1)));
    CHECK(its.geoFrame.n.isApprox(Normal3f(0, 0, -1)));
    // Points sampled for area lights carry the same normal.
    for (float u : {0.1f, 0.5f, 0.9f})
        CHECK(mesh->sampleSurface(Point2f(u, 0.3f)).n.isApprox(Normal3f(0, 0, -1)));
    // Without normals the winding decides.
    auto plain = loadObj(dir, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    CHECK(plain->sampleSurface(Point2f(0.5f, 0.5f)).n.isApprox(Normal3f(0, 0, 1)));
}

TEST_CASE("OBJ: quads and convex polygons become fans sharing their corners", "[obj]") {
    TempDir dir;
    auto quad = loadObj(dir, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n");
    CHECK(quad->getPrimitiveCount() == 2);
    CHECK(quad->positions().size() == 4);
    CHECK(quad->surfaceArea(0) + quad->surfaceArea(1) == Approx(1.0f));

    auto hexagon = loadObj(dir, "v 2 0 0\nv 1 1.7 0\nv -1 1.7 0\nv -2 0 0\nv -1 -1.7 0\n"
                                "v 1 -1.7 0\nf 1 2 3 4 5 6\n");
    CHECK(hexagon->getPrimitiveCount() == 4);
}

TEST_CASE("OBJ: negative indices, v/vt/vn and v//vn forms", "[obj]") {
    TempDir dir;
    auto mesh = loadObj(dir, "# comment\no thing\ng group\ns off\nusemtl red\n"
                             "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                             "vn 0 0 2\n"
                             "f -3/-3/-1 -2/-2/-1 -1/-1/-1\n");
    REQUIRE(mesh->getPrimitiveCount() == 1);
    REQUIRE(mesh->normals().size() == 3);
    CHECK(mesh->normals()[0].isApprox(Normal3f(0, 0, 1))); // normalised
    REQUIRE(mesh->texCoords().size() == 3);
    CHECK(mesh->texCoords()[1].isApprox(Point2f(1, 0)));

    auto normalsOnly = loadObj(dir, "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n");
    CHECK(normalsOnly->normals().size() == 3);
    CHECK(normalsOnly->texCoords().empty());
}

TEST_CASE("OBJ: toWorld transforms positions and normals", "[obj]") {
    TempDir dir;
    dir.write("m.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n");
    auto scene = std::dynamic_pointer_cast<Scene>(loadFromXMLString(R"(<scene>
        <integrator type="normals"/><camera type="perspective"/>
        <mesh type="obj"><string name="filename" value="m.obj"/>
            <transform name="toWorld"><rotate axis="1,0,0" angle="90"/>
            <translate value="0,0,5"/></transform></mesh></scene>)",
                                                                    dir.path().string()));
    REQUIRE(scene);
    auto mesh = std::dynamic_pointer_cast<Mesh>(scene->getShapes().at(0));
    CHECK(mesh->positions()[2].isApprox(Point3f(0, 0, 6), 1e-6f));
    CHECK(mesh->normals()[0].isApprox(Normal3f(0, -1, 0), 1e-6f));
}

TEST_CASE("OBJ: malformed lines are errors with their line number", "[obj]") {
    CHECK_THAT(objError("v 0 0 0\nv 1 0\n"),
               Contains("mesh.obj:2:") && Contains("vertex position needs 3 numbers, got 2"));
    CHECK_THAT(objError("v 0 0 0\nv 1 x 0\n"), Contains("mesh.obj:2:") && Contains("'x'"));
    CHECK_THAT(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n"),
               Contains("mesh.obj:5:") && Contains("vertex index 4 is out of range"));
    CHECK_THAT(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n"),
               Contains("mesh.obj:4:") && Contains("index -4 is out of range"));
    CHECK_THAT(objError("v 0 0 0\nv 1 0 0\nf 1 2\n"),
               Contains("mesh.obj:3:") && Contains("at least 3 vertices"));
    CHECK_THAT(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/1 3/1\n"),
               Contains("mesh.obj:4:") && Contains("texture coordinate index 1 is out of range"));
    CHECK_THAT(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/2/3/4 2 3\n"),
               Contains("malformed face vertex '1/2/3/4'"));
    CHECK_THAT(objError("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n"),
               Contains("vertex index 0 is out of range"));
}
