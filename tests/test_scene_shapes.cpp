// The shapes of real scenes: Mitsuba's rectangle, disk, cube and cylinder (χ² tests of
// their area sampling, each with a planted wrong density it must reject) and PLY meshes in
// every encoding, which render exactly as the same mesh read from an OBJ.
#include "testutil.h"

#include <nori/compression.h>
#include <nori/emitter.h>
#include <nori/filesystem.h>
#include <nori/parser.h>
#include <nori/plyfile.h>
#include <nori/render.h>
#include <nori/samplingroutines.h>
#include <nori/scene.h>
#include <nori/serializedfile.h>
#include <nori/shape.h>

#include <catch2/catch.hpp>

using namespace nori;
using namespace nori::testing;

namespace {

std::shared_ptr<Shape> makeShape(const std::string &xml, const std::string &directory = ".") {
    auto shape = std::dynamic_pointer_cast<Shape>(loadFromXMLString(xml, directory));
    REQUIRE(shape);
    return shape;
}

const char *const kLight = R"(<emitter type="area"><color name="radiance" value="1"/></emitter>)";

/// The shapes of the χ² tests, each an area light, placed off the origin and tilted.
std::vector<std::string> lightShapes() {
    const std::string place = R"(<transform name="toWorld"><scale value="0.6, 0.4, 0.5"/>
        <rotate axis="1, 1, 0" angle="35"/><translate value="0.2, 0.3, -0.1"/></transform>)";
    return {
        R"(<mesh type="rectangle">)" + place + kLight + "</mesh>",
        R"(<mesh type="disk">)" + place + kLight + "</mesh>",
        R"(<mesh type="cube">)" + place + kLight + "</mesh>",
        std::string(R"(<mesh type="cylinder"><point name="p0" value="0, -0.5, 0.1"/>
            <point name="p1" value="0.3, 0.6, 0"/><float name="radius" value="0.3"/>
            <transform name="toWorld"><scale value="1.5"/><rotate axis="0, 0, 1" angle="20"/>
            </transform>)") +
            kLight + "</mesh>",
    };
}

/// The same little mesh (two quads, one with a uv seam) as OBJ text and as MeshData.
const char *const kOBJ = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0.5\nv 2 1 0.5\n"
                         "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0\nvt 0.5 1\n"
                         "vn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn 0 0 1\nvn -0.4 0 0.9\nvn -0.4 0 0.9\n"
                         "f 1/1/1 2/2/2 3/3/3 4/4/4\nf 2/2/2 5/5/5 6/6/6 3/3/3\n";

MeshData plyOfOBJ() {
    MeshData mesh;
    mesh.positions = {Point3f(0, 0, 0), Point3f(1, 0, 0),    Point3f(1, 1, 0),
                      Point3f(0, 1, 0), Point3f(2, 0, 0.5f), Point3f(2, 1, 0.5f)};
    mesh.texCoords = {Point2f(0, 0), Point2f(1, 0),    Point2f(1, 1),
                      Point2f(0, 1), Point2f(0.5f, 0), Point2f(0.5f, 1)};
    mesh.normals = {Normal3f(0, 0, 1), Normal3f(0, 0, 1),        Normal3f(0, 0, 1),
                    Normal3f(0, 0, 1), Normal3f(-0.4f, 0, 0.9f), Normal3f(-0.4f, 0, 0.9f)};
    mesh.triangles = {Vector3i(0, 1, 2), Vector3i(0, 2, 3), Vector3i(1, 4, 5), Vector3i(1, 5, 2)};
    return mesh;
}

std::string asciiPLY(const MeshData &mesh, const std::string &uvNames) {
    std::string text = fmt::format("ply\r\nformat ascii 1.0\ncomment by hand\nelement vertex {}\n"
                                   "property float x\nproperty float y\nproperty float z\n"
                                   "property float nx\nproperty float ny\nproperty float nz\n"
                                   "property float {}\nelement face 2\n"
                                   "property list uchar int vertex_indices\nend_header\n",
                                   mesh.positions.size(), uvNames);
    for (size_t i = 0; i < mesh.positions.size(); ++i)
        text +=
            fmt::format("{} {} {} {} {} {} {} {}\n", mesh.positions[i].x(), mesh.positions[i].y(),
                        mesh.positions[i].z(), mesh.normals[i].x(), mesh.normals[i].y(),
                        mesh.normals[i].z(), mesh.texCoords[i].x(), mesh.texCoords[i].y());
    return text + "4 0 1 2 3\n4 1 4 5 2\n";
}

/// A binary big-endian PLY of the mesh, with a double position type, a ushort-counted
/// list and an extra per-face property to skip.
std::string bigEndianPLY(const MeshData &mesh) {
    std::string bytes = fmt::format("ply\nformat binary_big_endian 1.0\nelement vertex {}\n"
                                    "property double x\nproperty double y\nproperty double z\n"
                                    "property float nx\nproperty float ny\nproperty float nz\n"
                                    "property float s\nproperty float t\nelement face {}\n"
                                    "property list ushort uint vertex_indices\n"
                                    "property uchar flags\nend_header\n",
                                    mesh.positions.size(), mesh.triangles.size());
    auto append = [&bytes](auto value) {
        char raw[sizeof(value)];
        std::memcpy(raw, &value, sizeof(value));
        std::reverse(raw, raw + sizeof(value));
        bytes.append(raw, sizeof(value));
    };
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
        for (int k = 0; k < 3; ++k)
            append(static_cast<double>(mesh.positions[i][k]));
        for (int k = 0; k < 3; ++k)
            append(mesh.normals[i][k]);
        append(mesh.texCoords[i].x());
        append(mesh.texCoords[i].y());
    }
    for (const Vector3i &triangle : mesh.triangles) {
        append(static_cast<uint16_t>(3));
        for (int k = 0; k < 3; ++k)
            append(static_cast<uint32_t>(triangle[k]));
        bytes.push_back('\x07');
    }
    return bytes;
}

std::string sceneWith(const std::string &meshXML) {
    return R"(<scene><integrator type="path_mis"/><sampler type="independent">
        <integer name="sampleCount" value="4"/></sampler>
        <camera type="perspective"><transform name="toWorld">
        <lookat origin="1, 0.5, 3" target="1, 0.5, 0" up="0, 1, 0"/></transform>
        <float name="fov" value="50"/><integer name="width" value="24"/>
        <integer name="height" value="16"/></camera>
        <emitter type="point"><point name="position" value="1, 2, 2"/>
        <color name="power" value="60"/></emitter>)" +
           meshXML + "</scene>";
}

} // namespace

TEST_CASE("Rectangle, disk, cube and cylinder points are uniform by area", "[shape][chi2]") {
    // Points of sampleSurface() binned in the shapes' uv, against the density a uniform
    // point has there: the rectangle's, cube's (six faces over one square) and tube's uv are
    // proportional to area, uniform; the disk's (r, φ/2π) has density 2u. The planted
    // densities put the mass elsewhere. (The directions an area light on these shapes
    // samples are χ²-tested by the automatic plugin test, from the examples of `area`.)
    const std::vector<std::string> shapes = lightShapes();
    const double level = sidakCorrection(0.01, 4);
    const auto uniform = [](const Vector3f &) { return 1.0; };
    const auto planted = [](const Vector3f &uv) { return 2.0 * uv.y(); };
    struct Case {
        std::shared_ptr<Shape> shape;
        std::function<double(const Vector3f &)> density, planted;
    };
    const std::vector<Case> cases = {
        {makeShape(shapes[0]), uniform, planted},
        {makeShape(shapes[1]), [](const Vector3f &uv) { return 2.0 * uv.x(); },
         [](const Vector3f &uv) { return 2.0 * (1.0 - uv.x()); }},
        {makeShape(shapes[2]), uniform, planted},
        {makeShape(shapes[3]), uniform, planted},
    };
    uint64_t seed = 90;
    for (const Case &c : cases) {
        SamplingRoutine routine;
        routine.domain = SampleDomain::UnitSquare;
        const Shape &shape = *c.shape;
        routine.sample = [&shape](const Point2f &u, Vector3f &point) {
            const ShapeSample sample = shape.sampleSurface(u);
            point = Vector3f(sample.uv.x(), sample.uv.y(), 0.0f);
            return std::abs(sample.pdf * shape.getArea() - 1.0f) < 1e-4f;
        };
        routine.pdf = c.density;
        INFO(shape.toString());
        const ChiSquareReport truth = chiSquare(routine, seed++, level);
        INFO(truth.result.message);
        CHECK(truth.result.passed);
        CHECK(truth.samplesOutside == 0);
        routine.pdf = c.planted;
        CHECK_FALSE(chiSquare(routine, seed++, level).result.passed);
    }
}

TEST_CASE("Mitsuba's shapes have its sizes, normals and uv", "[shape]") {
    const auto disk = makeShape(R"(<mesh type="disk"><transform name="toWorld">
        <scale value="2, 0.5, 1"/><translate value="0, 0, 3"/></transform></mesh>)");
    CHECK(disk->getArea() == Approx(kPi * 2 * 0.5));
    Intersection its;
    Point2f coords;
    const Ray3f down(Point3f(1.0f, 0.25f, 5.0f), Vector3f(0, 0, -1));
    REQUIRE(disk->rayIntersect(0, down, its.t, coords));
    disk->setHitInformation(0, down, coords, its);
    CHECK(its.t == Approx(2.0f));
    CHECK(its.geoFrame.n.isApprox(Vector3f(0, 0, 1)));
    // Local (0.5, 0.5): r = √0.5, φ = 45°.
    CHECK(its.uv.x() == Approx(std::sqrt(0.5f)));
    CHECK(its.uv.y() == Approx(0.125f));
    CHECK_FALSE(
        disk->rayIntersect(0, Ray3f(Point3f(2.1f, 0, 5), Vector3f(0, 0, -1)), its.t, coords));

    const auto cylinder = makeShape(R"(<mesh type="cylinder"><point name="p0" value="0, 0, -1"/>
        <point name="p1" value="0, 0, 1"/><float name="radius" value="0.5"/></mesh>)");
    CHECK(cylinder->getArea() == Approx(2 * kPi * 0.5 * 2));
    const Ray3f side(Point3f(3, 0, 0.5f), Vector3f(-1, 0, 0));
    REQUIRE(cylinder->rayIntersect(0, side, its.t, coords));
    cylinder->setHitInformation(0, side, coords, its);
    CHECK(its.t == Approx(2.5f));
    CHECK(its.geoFrame.n.isApprox(Vector3f(1, 0, 0)));
    CHECK(its.uv.y() == Approx(0.75f));
    // From inside, the far wall; past the ends, nothing (the tube is open).
    const Ray3f inside(Point3f(0, 0, 0), Vector3f(0, 1, 0));
    REQUIRE(cylinder->rayIntersect(0, inside, its.t, coords));
    CHECK(its.t == Approx(0.5f));
    CHECK_FALSE(
        cylinder->rayIntersect(0, Ray3f(Point3f(0, 0, -3), Vector3f(0, 0, 1)), its.t, coords));
    CHECK_THAT(errorOf([] {
                   makeShape(R"(<mesh type="cylinder"><transform name="toWorld">
                       <scale value="1, 2, 1"/></transform></mesh>)");
               }),
               Catch::Contains("keep the cross-section a circle"));

    const auto cube = makeShape(R"(<mesh type="cube"/>)");
    CHECK(cube->getArea() == Approx(24.0f));
    CHECK(cube->isClosed());
    const auto rectangle =
        makeShape(R"(<mesh type="rectangle"><boolean name="flipNormals" value="true"/></mesh>)");
    CHECK(rectangle->getArea() == Approx(4.0f));
    REQUIRE(rectangle->rayIntersect(0, down, its.t, coords));
    rectangle->setHitInformation(0, down, coords, its);
    CHECK(its.geoFrame.n.z() == Approx(-1.0f));
}

TEST_CASE("A PLY mesh in any encoding renders bit for bit as the same mesh in an OBJ",
          "[shape][ply]") {
    TempDir folder;
    const MeshData mesh = plyOfOBJ();
    folder.write("mesh.obj", kOBJ);
    folder.write("ascii.ply", asciiPLY(mesh, "u\nproperty float v"));
    folder.write("texture.ply", asciiPLY(mesh, "texture_u\nproperty float texture_v"));
    folder.write("big.ply", bigEndianPLY(mesh));
    folder.write("big.ply.gz", gzip(bigEndianPLY(mesh)));
    writePLY((folder.path() / "little.ply").string(), mesh);
    const std::string directory = folder.path().string();

    // The same arrays, whatever the encoding (the OBJ's corners are in file order).
    for (const char *name : {"ascii.ply", "texture.ply", "big.ply", "big.ply.gz", "little.ply"}) {
        const MeshData read = readPLY((folder.path() / name).string());
        INFO(name);
        CHECK(read.positions == mesh.positions);
        CHECK(read.normals == mesh.normals);
        CHECK(read.texCoords == mesh.texCoords);
        CHECK(read.triangles == mesh.triangles);
    }
    const auto render = [&](const std::string &meshXML) {
        const auto scene = loadScene(sceneWith(meshXML), directory);
        return renderScene(*scene, quietOptions(2)).image;
    };
    const Bitmap obj =
        render(R"(<mesh type="obj"><string name="filename" value="mesh.obj"/></mesh>)");
    CHECK(obj(8, 12).getLuminance() > 0.0f);
    for (const char *name : {"ascii.ply", "big.ply.gz", "little.ply"}) {
        INFO(name);
        CHECK(identicalImages(
            obj, render(fmt::format(
                     R"(<mesh type="ply"><string name="filename" value="{}"/></mesh>)", name))));
    }
}

TEST_CASE("A malformed PLY file is an error naming the file and where", "[shape][ply][errors]") {
    TempDir folder;
    const std::string header = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
                               "property float y\nproperty float z\nelement face 1\n"
                               "property list uchar int vertex_indices\nend_header\n";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"not ply\n", "line 1: not a PLY file"},
        {"ply\nformat ascii 1.0\nelement vertex 3\nproperty floot x\nend_header\n",
         "line 4: unknown property type 'floot'"},
        {"ply\nformat ascii 1.0\nelement vertex 3\n", "has no 'end_header' line"},
        {header + "0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
         "line 13: face 0 names vertex 7, but there are 3"},
        {header + "0 0 0\n1 0 x\n0 1 0\n3 0 1 2\n", "line 11: 'x' is not a number"},
        {header + "0 0 0\n1 0 0\n0 1 0\n", "the file ends before its elements do"},
        {"ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\n"
         "property float y\nproperty float z\nelement face 0\n"
         "property list uchar int vertex_indices\nend_header\n",
         "claims 1000000000 items"},
        {"ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
         "end_header\n3 0 1 2\n",
         "before the 'vertex' element"},
    };
    for (size_t i = 0; i < cases.size(); ++i) {
        const std::string path = folder.write(fmt::format("bad{}.ply", i), cases[i].first);
        INFO(cases[i].first);
        CHECK_THAT(errorOf([&] { readPLY(path); }),
                   Catch::Contains(path) && Catch::Contains(cases[i].second));
    }
    const std::string truncated = folder.write("truncated.ply.gz", gzip(header).substr(0, 20));
    CHECK_THAT(errorOf([&] { readPLY(truncated); }), Catch::Contains("compressed data"));
}

TEST_CASE("A serialized mesh loads the mesh it names and renders as the same OBJ",
          "[shape][serialized]") {
    // tests/data/meshes/quads.serialized: mesh 0 a triangle, mesh 1 the quad [−1, 1]² with
    // normals and uvs (written by hand, format version 4).
    const std::string path = std::string(NORI_SOURCE_DIR) + "/tests/data/meshes/quads.serialized";
    const SerializedMesh triangle = readSerialized(path, 0);
    CHECK(triangle.name == "triangle");
    CHECK(triangle.data.positions.size() == 3);
    CHECK(triangle.data.normals.empty());
    const SerializedMesh quad = readSerialized(path, 1);
    CHECK(quad.name == "quad");
    CHECK(quad.data.triangles == std::vector<Vector3i>{Vector3i(0, 1, 2), Vector3i(2, 3, 0)});
    CHECK(quad.data.texCoords.size() == 4);
    CHECK_THAT(errorOf([&] { readSerialized(path, 2); }),
               Catch::Contains("'shapeIndex' 2 is out of range (the file holds 2 meshes"));

    TempDir folder;
    folder.write("quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                             "vt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 3/3/1 4/4/1 1/1/1\n");
    const auto render = [&](const std::string &meshXML) {
        return renderScene(*loadScene(sceneWith(meshXML), folder.path().string()), quietOptions(2))
            .image;
    };
    const std::string place =
        R"(<transform name="toWorld"><translate value="1, 0.5, 0"/></transform>)";
    CHECK(identicalImages(
        render(R"(<mesh type="obj"><string name="filename" value="quad.obj"/>)" + place +
               "</mesh>"),
        render(fmt::format(R"(<mesh type="serialized"><string name="filename" value="{}"/>
            <integer name="shapeIndex" value="1"/>{}</mesh>)",
                           path, place))));

    std::string bytes = readBinaryFile(path, "test");
    std::string damaged = bytes;
    damaged[10] = static_cast<char>(damaged[10] ^ 0x55); // inside mesh 0's zlib stream
    CHECK_THAT(errorOf([&] { parseSerialized(damaged, 0, "damaged"); }),
               Catch::Contains("'damaged'") && Catch::Contains("mesh 0 (at byte 0)"));
    CHECK_THAT(errorOf([&] { parseSerialized(bytes.substr(0, bytes.size() - 1), 0, "cut"); }),
               Catch::Contains("serialized mesh file 'cut'"));
    CHECK_THAT(errorOf([&] { parseSerialized("PK\x03\x04 not a mesh", 0, "zip"); }),
               Catch::Contains("not the format's identifier 0x041c"));
}
