// pbrt-v4's graphics state (pbrtscene.h): transforms composed as pbrt-v4 composes them,
// attributes saved and restored, every entity recorded with the state it was declared in,
// and pbrt-v4's rejections as located errors.
#include <nori/pbrtscene.h>

#include "testutil.h"

#include <catch2/catch.hpp>

using namespace nori;
using namespace nori::testing;
using Catch::Contains;

namespace {

Eigen::Vector3d apply(const pbrt::Matrix &m, double x, double y, double z) {
    const Eigen::Vector4d p = m * Eigen::Vector4d(x, y, z, 1.0);
    return p.head<3>() / p.w();
}

bool near(const Eigen::Vector3d &a, const Eigen::Vector3d &b) {
    return (a - b).norm() < 1e-9;
}

} // namespace

TEST_CASE("pbrt-v4 transforms compose right to left, as pbrt-v4 applies them", "[pbrt][scene]") {
    const pbrt::Scene scene = pbrt::readSceneString(R"(
LookAt 0 0 5  0 0 0  0 1 0
Camera "perspective"
WorldBegin
Translate 1 0 0
Rotate 90 0 0 1
Shape "sphere"                                         # 0
Identity
Transform [ 1 0 0 0  0 1 0 0  0 0 1 0  5 6 7 1 ]
Shape "sphere"                                         # 1
ConcatTransform [ 2 0 0 0  0 2 0 0  0 0 2 0  0 0 0 1 ]
Shape "sphere"                                         # 2
CoordSysTransform "camera"
Shape "sphere"                                         # 3
CoordinateSystem "mine"
Identity
Scale 1 1 -1
CoordSysTransform "mine"
Shape "sphere"                                         # 4
)",
                                                    "scene.pbrt");
    // The camera at (0, 0, 5) looking at the origin: +z forward, +y up, and +x = up × dir,
    // pbrt-v4's left-handed camera frame, so camera +x is world −x here.
    const pbrt::Matrix &camera = scene.camera.toWorld;
    CHECK(near(apply(camera, 0, 0, 0), {0, 0, 5}));
    CHECK(near(apply(camera, 0, 0, 1), {0, 0, 4}));
    CHECK(near(apply(camera, 0, 1, 0), {0, 1, 5}));
    CHECK(near(apply(camera, 1, 0, 0), {-1, 0, 5}));
    REQUIRE(scene.shapes.size() == 5);
    // Translate · Rotate: the point is turned first, then moved.
    CHECK(near(apply(scene.shapes[0].toWorld, 1, 0, 0), {1, 1, 0}));
    // Transform's 16 numbers are the matrix's columns: the last four, the translation.
    CHECK(near(apply(scene.shapes[1].toWorld, 0, 0, 0), {5, 6, 7}));
    CHECK(near(apply(scene.shapes[2].toWorld, 1, 0, 0), {7, 6, 7}));
    // CoordSysTransform "camera": the camera's frame.
    CHECK(near(apply(scene.shapes[3].toWorld, 1, 0, 0), {-1, 0, 5}));
    CHECK(near(apply(scene.shapes[4].toWorld, 1, 0, 0), {-1, 0, 5}));
    CHECK(scene.warnings.empty());
}

TEST_CASE("pbrt-v4 attributes: materials, lights, media and orientation per shape",
          "[pbrt][scene]") {
    const pbrt::Scene scene = pbrt::readSceneString(R"(
Film "rgb" "integer xresolution" 64
MakeNamedMedium "fog" "string type" "homogeneous" "float scale" 2
MediumInterface "" "fog"
Camera "perspective" "float fov" 30
WorldBegin
Attribute "shape" "float radius" 2 "float zmax" 1
Shape "sphere" "float radius" 3                            # 0: its own radius wins
AttributeBegin
    Material "conductor" "float roughness" 0.1
    ReverseOrientation
    AreaLightSource "diffuse" "rgb L" [ 1 2 3 ]
    MediumInterface "fog"
    Shape "disk"                                           # 1
    MakeNamedMaterial "white" "string type" "diffuse" "rgb reflectance" [ .8 .8 .8 ]
    NamedMaterial "white"
    Shape "disk"                                           # 2
AttributeEnd
Shape "disk"                                               # 3: the state before the block
TransformBegin
    Translate 0 0 1
TransformEnd
Texture "checks" "spectrum" "checkerboard" "float uscale" 4
Texture "checks" "float" "constant" "float value" 0.5
ObjectBegin "thing"
    Shape "sphere"
ObjectEnd
Translate 0 1 0
ObjectInstance "thing"
LightSource "point" "rgb I" [ 1 1 1 ]
)",
                                                    "scene.pbrt");
    CHECK(scene.film.type == "rgb");
    REQUIRE(scene.film.find("xresolution"));
    CHECK(scene.camera.medium == "fog");
    CHECK(scene.sampler.type == "zsobol"); // pbrt-v4's defaults where the file names none
    CHECK(scene.integrator.type == "volpath");
    REQUIRE(scene.shapes.size() == 4);
    const auto &sphere = scene.shapes[0];
    CHECK(sphere.find("radius")->numbers == std::vector<double>{3});
    CHECK(sphere.find("zmax")->numbers == std::vector<double>{1});
    CHECK(sphere.material == 0); // pbrt-v4's default diffuse material
    CHECK(scene.materials[0].type == "diffuse");
    CHECK(sphere.outsideMedium == "fog");
    const auto &lit = scene.shapes[1];
    CHECK(lit.reverseOrientation);
    CHECK(scene.materials[size_t(lit.material)].type == "conductor");
    REQUIRE(lit.areaLight >= 0);
    CHECK(scene.areaLights[size_t(lit.areaLight)].find("L")->numbers ==
          std::vector<double>{1, 2, 3});
    CHECK(lit.insideMedium == "fog");
    CHECK(lit.outsideMedium == "fog");
    CHECK(scene.shapes[2].namedMaterial == "white");
    CHECK(scene.namedMaterials.at("white").type == "diffuse");
    CHECK(!scene.namedMaterials.at("white").find("type"));
    const auto &after = scene.shapes[3];
    CHECK(!after.reverseOrientation);
    CHECK(after.areaLight == -1);
    CHECK(after.material == 0);
    CHECK(after.find("radius")->numbers == std::vector<double>{2}); // Attribute default
    REQUIRE(scene.textures.size() == 2);
    CHECK(scene.textures[0].valueType == "spectrum");
    CHECK(scene.textures[1].type == "constant");
    REQUIRE(scene.instances.size() == 1);
    CHECK(scene.instances[0].shapes.size() == 1);
    REQUIRE(scene.instanceUses.size() == 1);
    CHECK(near(apply(scene.instanceUses[0].toWorld, 0, 0, 0), {0, 1, 0}));
    CHECK(scene.lights.size() == 1);
    CHECK(scene.media.size() == 1);
    CHECK(scene.media[0].type == "homogeneous");
    REQUIRE(scene.warnings.size() == 1);
    CHECK_THAT(scene.warnings[0], Contains("scene.pbrt:20:1") && Contains("TransformBegin"));
}

TEST_CASE("pbrt-v4 warns once about motion blur and other colour spaces", "[pbrt][scene]") {
    const pbrt::Scene scene = pbrt::readSceneString(R"(
ColorSpace "aces2065-1"
WorldBegin
ActiveTransform EndTime
Translate 1 0 0
ActiveTransform All
Shape "sphere"
Shape "sphere"
)",
                                                    "scene.pbrt");
    REQUIRE(scene.warnings.size() == 2);
    CHECK_THAT(scene.warnings[0], Contains("colour space 'aces2065-1'"));
    CHECK_THAT(scene.warnings[1], Contains("scene.pbrt:7:1") && Contains("motion blur"));
    // The start transform is the one rendered.
    CHECK(near(apply(scene.shapes[0].toWorld, 0, 0, 0), {0, 0, 0}));
}

TEST_CASE("What pbrt-v4 rejects is an error where it stands", "[pbrt][scene][errors]") {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"Shape \"sphere\"\nWorldBegin", "scene.pbrt:1:1: Shape belongs after WorldBegin"},
        {"WorldBegin\nCamera \"perspective\"", "scene.pbrt:2:1: Camera belongs before WorldBegin"},
        {"WorldBegin\nAttributeEnd", "scene.pbrt:2:1: AttributeEnd without a matching begin"},
        {"WorldBegin\n  AttributeBegin\nShape \"sphere\"",
         "scene.pbrt:2:3: this AttributeBegin has no AttributeEnd"},
        {"WorldBegin\nNamedMaterial \"whte\"\nMakeNamedMaterial \"white\" \"string type\" "
         "\"diffuse\"",
         "scene.pbrt:2:1: NamedMaterial 'whte' is never defined (did you mean 'white'?)"},
        {"WorldBegin\nObjectInstance \"tree\"",
         "scene.pbrt:2:1: ObjectInstance of 'tree', which no ObjectBegin defines"},
        {"WorldBegin\nMakeNamedMaterial \"m\" \"string type\" \"diffuse\"\n"
         "MakeNamedMaterial \"m\" \"string type\" \"diffuse\"",
         "scene.pbrt:3:1: named material 'm' is defined twice"},
        {"WorldBegin\nMakeNamedMaterial \"m\" \"float roughness\" 1", "needs a \"string type\""},
        {"LookAt 0 0 0  0 1 0  0 1 0", "LookAt's up vector and viewing direction point the same"},
        {"WorldBegin\nAttribute \"shpe\" \"float radius\" 1",
         "unknown Attribute target 'shpe' (did you mean 'shape'?)"},
        {"Camera \"perspective\"", "the file ends before WorldBegin"},
        {"WorldBegin\nObjectBegin \"a\"\nAttributeEnd", "AttributeEnd inside the ObjectBegin"},
        {"WorldBegin\nTexture \"t\" \"color\" \"constant\"", "\"float\" or \"spectrum\""},
    };
    for (const auto &entry : cases) {
        const std::string &text = entry.first, &message = entry.second;
        INFO(text);
        CHECK_THAT(errorOf([&] { pbrt::readSceneString(text, "scene.pbrt"); }), Contains(message));
    }
}
