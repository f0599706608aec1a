// Transforms: points, vectors and normals transform differently; lookat and rotate
// follow Nori's conventions.
#include <nori/transform.h>

#include "testutil.h"

#include <catch2/catch.hpp>

using namespace nori;
using Catch::Contains;
using nori::testing::errorOf;

TEST_CASE("Translation moves points but not vectors", "[transform]") {
    Transform t = Transform::translate(Vector3f(1, 2, 3));
    CHECK((t * Point3f(1, 1, 1)).isApprox(Point3f(2, 3, 4)));
    CHECK((t * Vector3f(1, 1, 1)).isApprox(Vector3f(1, 1, 1)));
    CHECK((t.inverse() * (t * Point3f(5, -1, 2))).isApprox(Point3f(5, -1, 2)));
}

TEST_CASE("Rotation is right-handed and given in degrees", "[transform]") {
    Transform r = Transform::rotate(Vector3f(0, 0, 1), 90.0f);
    CHECK((r * Vector3f(1, 0, 0)).isApprox(Vector3f(0, 1, 0), 1e-6f));
    CHECK((r * Vector3f(0, 1, 0)).isApprox(Vector3f(-1, 0, 0), 1e-6f));
    Transform about = Transform::rotate(Vector3f(0, 2, 0), 90.0f); // axis need not be unit
    CHECK((about * Vector3f(0, 0, 1)).isApprox(Vector3f(1, 0, 0), 1e-6f));
    CHECK((r.getMatrix() * r.getInverseMatrix()).isApprox(Eigen::Matrix4f::Identity()));
}

TEST_CASE("Normals stay perpendicular under non-uniform scale", "[transform]") {
    // A plane with normal (1,1,0)/√2 containing the tangent (1,-1,0).
    Transform s = Transform::scale(Vector3f(4, 1, 1));
    Vector3f tangent = s * Vector3f(1, -1, 0);
    Normal3f normal = s * Normal3f(1, 1, 0);
    CHECK(std::abs(tangent.dot(normal)) < 1e-6f);
    // Transforming the normal as a vector would be wrong:
    Vector3f wrong = s * Vector3f(1, 1, 0);
    CHECK(std::abs(tangent.dot(wrong)) > 1.0f);
}

TEST_CASE("lookat places the camera at origin looking along +z toward target", "[transform]") {
    Point3f origin(1, 2, 3), target(1, 2, -5);
    Transform view = Transform::lookAt(origin, target, Vector3f(0, 1, 0));
    CHECK((view * Point3f(0, 0, 0)).isApprox(origin));
    CHECK((view * Vector3f(0, 0, 1)).isApprox(Vector3f(0, 0, -1), 1e-6f));
    CHECK((view * Vector3f(0, 1, 0)).isApprox(Vector3f(0, 1, 0), 1e-6f));
    // Camera +x is up × dir ("left" in Nori's lookat): (0,1,0) × (0,0,-1) = (-1,0,0).
    CHECK((view * Vector3f(1, 0, 0)).isApprox(Vector3f(-1, 0, 0), 1e-6f));

    CHECK_THAT(
        errorOf([] { Transform::lookAt(Point3f(0, 0, 0), Point3f(0, 1, 0), Vector3f(0, 1, 0)); }),
        Contains("parallel"));
    CHECK_THAT(
        errorOf([] { Transform::lookAt(Point3f(1, 1, 1), Point3f(1, 1, 1), Vector3f(0, 1, 0)); }),
        Contains("same point"));
}

TEST_CASE("Singular matrices and zero scales are rejected", "[transform]") {
    CHECK_THAT(errorOf([] { (void)Transform(Eigen::Matrix4f::Zero()); }), Contains("singular"));
    CHECK_THAT(errorOf([] { Transform::scale(Vector3f(1, 0, 1)); }), Contains("zero factor"));
}
