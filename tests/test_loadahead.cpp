// Files read ahead while the parser builds the scene (LoadAhead): every read the parser
// starts is the one its element takes, in order, with the reader's errors as they were.
#include <nori/bitmap.h>
#include <nori/imagefile.h>
#include <nori/loadahead.h>
#include <nori/mesh.h>
#include <nori/objfile.h>
#include <nori/parallel.h>
#include <nori/parser.h>
#include <nori/pbrtimport.h>
#include <nori/scene.h>
#include <nori/texture.h>
#include <nori/texturecache.h>

#include "testutil.h"

#include <catch2/catch.hpp>

#include <atomic>
#include <filesystem>
#include <mutex>
#include <set>

using namespace nori;
using Catch::Contains;
using nori::testing::errorOf;
using nori::testing::TempDir;

namespace {

/// A reader that counts its calls and fails on a path ending in "bad".
std::atomic<int> g_reads{0};
const bool g_counterRegistered = [] {
    LoadAhead::registerReader("test_counter", [](const std::string &path) {
        ++g_reads;
        if (path.size() >= 3 && path.compare(path.size() - 3, 3, "bad") == 0)
            throw NoriException("{}: line 7: cannot read this", path);
        return std::any(path + "!");
    });
    return true;
}();

/// The same, read ahead once per path.
std::atomic<int> g_onceReads{0};
NORI_REGISTER_READER(
    "test_once",
    [](const std::string &path) {
        ++g_onceReads;
        return std::any(path + "?");
    },
    LoadAhead::Sharing::PerPath);

/// An OBJ mesh that says whether the parser had started reading its file: the paths the
/// parser resolved are the ones shapes ask for.
std::mutex g_takenMutex;
std::multiset<std::string> g_takenAhead, g_readHere;

class AheadMesh : public Mesh {
public:
    explicit AheadMesh(const PropertyList &props) {
        m_name = props.getPath("filename");
        std::optional<MeshData> data = LoadAhead::take<MeshData>("test_ahead_obj", m_name);
        {
            std::lock_guard<std::mutex> lock(g_takenMutex);
            (data ? g_takenAhead : g_readHere).insert(m_name);
        }
        takeMeshData(data ? std::move(*data) : readOBJ(m_name), false, false);
        finishLoading(props.getTransform("toWorld", Transform()));
    }
};

NORI_REGISTER_CLASS(AheadMesh, "test_ahead_obj");
NORI_REGISTER_READER(
    "test_ahead_obj", [](const std::string &path) { return std::any(readOBJ(path)); },
    LoadAhead::Sharing::PerElement);
NORI_REGISTER_LOAD_AHEAD(AheadMesh, "test_ahead_obj", "test_ahead_obj");

/// A texture of one colour, its image's first pixel, that says whether the parser had
/// started reading its image (with the reader of `image` textures and `envmap` lights).
std::multiset<std::string> g_imagesTakenAhead, g_imagesReadHere;

class AheadImage : public Texture {
public:
    explicit AheadImage(const PropertyList &props) {
        const std::string path = props.getPath("filename");
        std::optional<ImageFile> image = LoadAhead::take<ImageFile>(kTextureImageReader, path);
        {
            std::lock_guard<std::mutex> lock(g_takenMutex);
            (image ? g_imagesTakenAhead : g_imagesReadHere).insert(path);
        }
        m_value = (image ? std::move(*image) : readImageFile(path)).pixels(0, 0);
    }
    Color3f eval(const TextureQuery &) const override { return m_value; }
    Color3f average() const override { return m_value; }
    std::string toString() const override { return "AheadImage[]"; }

private:
    Color3f m_value;
};

NORI_REGISTER_CLASS(AheadImage, "test_ahead_image");
NORI_REGISTER_LOAD_AHEAD(AheadImage, "test_ahead_image", kTextureImageReader);

std::string triangleObj(float z) {
    return fmt::format("v 0 0 {0}\nv 1 0 {0}\nv 0 1 {0}\nf 1 2 3\n", z);
}

} // namespace

TEST_CASE("LoadAhead hands each started read to one take, in order, errors included",
          "[loadahead]") {
    CHECK_FALSE(LoadAhead::take<std::string>("test_counter", "a")); // no load ahead alive
    const int readsBefore = g_reads;
    {
        LoadAhead ahead;
        ahead.start("test_counter", "a");
        ahead.start("test_counter", "b");
        ahead.start("test_counter", "a");
        ahead.start("test_counter", "x.bad");
        ahead.start("no_such_plugin", "a"); // no reader: not started
        ahead.start("test_counter", "never taken");
        CHECK(LoadAhead::take<std::string>("test_counter", "a") == "a!");
        CHECK(LoadAhead::take<std::string>("test_counter", "b") == "b!");
        CHECK(LoadAhead::take<std::string>("test_counter", "a") == "a!");
        CHECK_FALSE(LoadAhead::take<std::string>("test_counter", "a")); // both taken
        CHECK_FALSE(LoadAhead::take<std::string>("no_such_plugin", "a"));
        CHECK_THROWS_WITH(LoadAhead::take<std::string>("test_counter", "x.bad"),
                          "x.bad: line 7: cannot read this");
        {
            // A nested load (a plugin that loads a scene) has its own reads.
            LoadAhead inner;
            CHECK_FALSE(LoadAhead::take<std::string>("test_counter", "never taken"));
        }
    } // "never taken" is dropped, read or not, and nothing waits for it
    // a, b, a and x.bad were read once each; "never taken" at most once.
    CHECK(g_reads - readsBefore >= 4);
    CHECK(g_reads - readsBefore <= 5);
    CHECK_FALSE(LoadAhead::take<std::string>("test_counter", "b")); // gone with its load

    // A PerPath reader reads a file once, for the first take; a second take reads itself.
    const int onceBefore = g_onceReads;
    {
        LoadAhead ahead;
        ahead.start("test_once", "c");
        ahead.start("test_once", "d");
        ahead.start("test_once", "c");
        CHECK(LoadAhead::take<std::string>("test_once", "c") == "c?");
        CHECK(LoadAhead::take<std::string>("test_once", "d") == "d?");
        CHECK_FALSE(LoadAhead::take<std::string>("test_once", "c"));
        ahead.start("test_once", "c"); // started before: not again
        CHECK_FALSE(LoadAhead::take<std::string>("test_once", "c"));
    }
    CHECK(g_onceReads - onceBefore == 2);
}

TEST_CASE("Shapes take the files the parser read ahead: relative, included, grouped, twice",
          "[loadahead]") {
    TempDir dir;
    dir.write("meshes/one.obj", triangleObj(0.0f));
    dir.write("meshes/two.obj", triangleObj(1.0f));
    dir.write("meshes/three.obj", triangleObj(2.0f));
    dir.write("parts/part.xml", R"(<scene>
        <mesh type="test_ahead_obj"><string name="filename" value="../meshes/three.obj"/></mesh>
    </scene>)");
    const std::string scene = dir.write("scene.xml", R"(<scene>
        <default name="which" value="two"/>
        <camera type="perspective"/>
        <integrator type="normals"/>
        <mesh type="test_ahead_obj"><string name="filename" value="meshes/one.obj"/></mesh>
        <mesh type="test_ahead_obj"><string name="filename" value="./meshes/one.obj"/>
            <transform name="toWorld"><translate value="5, 0, 0"/></transform></mesh>
        <mesh type="shapegroup" id="group">
            <mesh type="test_ahead_obj"><string name="filename" value="meshes/two.obj"/></mesh>
        </mesh>
        <mesh type="instance"><ref id="group"/></mesh>
        <mesh type="test_ahead_obj"><string name="filename" value="meshes/$which.obj"/></mesh>
        <include filename="parts/part.xml"/>
    </scene>)");
    {
        std::lock_guard<std::mutex> lock(g_takenMutex);
        g_takenAhead.clear();
        g_readHere.clear();
    }
    auto root = std::dynamic_pointer_cast<Scene>(loadFromXML(scene));
    REQUIRE(root);
    const std::string one = (dir.path() / "meshes/one.obj").string(),
                      two = (dir.path() / "meshes/two.obj").string(),
                      three = (dir.path() / "meshes/three.obj").string();
    std::lock_guard<std::mutex> lock(g_takenMutex);
    // Everything but the file named through a $variable was read ahead.
    CHECK(g_takenAhead == std::multiset<std::string>{one, one, two, three});
    CHECK(g_readHere == std::multiset<std::string>{two});
    // The scene is what it would be without reading ahead: four meshes of its own (the
    // group's is the instance's), the second copy of one.obj moved by its own transform.
    CHECK(root->getMeshes().size() == 4);
    CHECK(root->getBoundingBox().max.x() == Approx(6.0f));
}

TEST_CASE("Textures and environment maps take the images read ahead, once per file",
          "[loadahead][texture]") {
    // The shipped plugins that decode images through loadTextureImage read ahead.
    REQUIRE(LoadAhead::readerOf(NoriObject::ETexture, "image"));
    CHECK(*LoadAhead::readerOf(NoriObject::ETexture, "image") == kTextureImageReader);
    REQUIRE(LoadAhead::readerOf(NoriObject::EEmitter, "envmap"));
    CHECK(*LoadAhead::readerOf(NoriObject::EEmitter, "envmap") == kTextureImageReader);
    CHECK_FALSE(LoadAhead::readerOf(NoriObject::EEmitter, "image")); // by class and name

    TempDir dir;
    dir.write("triangle.obj", triangleObj(0.0f));
    Bitmap red(Eigen::Vector2i(2, 1)), blue(Eigen::Vector2i(1, 1));
    red.setConstant(Color3f(0.5f, 0.0f, 0.0f));
    blue.setConstant(Color3f(0.0f, 0.0f, 0.25f));
    std::filesystem::create_directories(dir.path() / "textures");
    red.saveEXR((dir.path() / "textures/red.exr").string());
    blue.saveEXR((dir.path() / "blue.exr").string());
    // red.exr is named by two textures: read ahead for the first, read by the second.
    const std::string scene = dir.write("scene.xml", R"(<scene>
        <camera type="perspective"/>
        <integrator type="normals"/>
        <mesh type="obj"><string name="filename" value="triangle.obj"/>
            <bsdf type="diffuse"><texture type="test_ahead_image" name="albedo">
                <string name="filename" value="textures/red.exr"/></texture></bsdf></mesh>
        <mesh type="obj"><string name="filename" value="triangle.obj"/>
            <bsdf type="diffuse"><texture type="test_ahead_image" name="albedo">
                <string name="filename" value="./textures/red.exr"/></texture></bsdf></mesh>
        <mesh type="obj"><string name="filename" value="triangle.obj"/>
            <bsdf type="diffuse"><texture type="test_ahead_image" name="albedo">
                <string name="filename" value="blue.exr"/></texture></bsdf></mesh>
        <emitter type="envmap"><string name="filename" value="blue.exr"/></emitter>
    </scene>)");
    {
        std::lock_guard<std::mutex> lock(g_takenMutex);
        g_imagesTakenAhead.clear();
        g_imagesReadHere.clear();
    }
    auto root = std::dynamic_pointer_cast<Scene>(loadFromXML(scene));
    REQUIRE(root);
    const std::string redPath = (dir.path() / "textures/red.exr").string(),
                      bluePath = (dir.path() / "blue.exr").string();
    {
        std::lock_guard<std::mutex> lock(g_takenMutex);
        CHECK(g_imagesTakenAhead == std::multiset<std::string>{redPath, bluePath});
        CHECK(g_imagesReadHere == std::multiset<std::string>{redPath});
    }
    REQUIRE(root->getEmitters().size() == 1);

    // A broken image read ahead reports its error when its element is reached, on every
    // thread count with the same words; an error before it comes first.
    dir.write("broken.png", "not a PNG");
    const std::string broken = dir.write("broken.xml", R"(<scene>
        <mesh type="obj"><string name="filename" value="triangle.obj"/>
            <bsdf type="diffuse"><texture type="image" name="albedo">
                <string name="filename" value="broken.png"/></texture></bsdf></mesh>
    </scene>)");
    std::string serialError, aheadError;
    ThreadLimit(1).run([&] { serialError = errorOf([&] { loadFromXML(broken); }); });
    ThreadLimit(0).run([&] { aheadError = errorOf([&] { loadFromXML(broken); }); });
    CHECK_THAT(aheadError, Contains("broken.png"));
    CHECK(aheadError == serialError);
    const std::string earlier = dir.write("earlier.xml", R"(<scene>
        <mesh type="obj"><string name="filename" value="triangle.obj"/>
            <float name="nope" value="1"/></mesh>
        <emitter type="envmap"><string name="filename" value="broken.png"/></emitter>
    </scene>)");
    const std::string earlierError = errorOf([&] { loadFromXML(earlier); });
    CHECK_THAT(earlierError, Contains("nope"));
    CHECK_THAT(earlierError, !Contains("broken.png"));
}

TEST_CASE("A file read ahead reports its error when its shape is reached, not before",
          "[loadahead]") {
    TempDir dir;
    dir.write("good.obj", triangleObj(0.0f));
    dir.write("broken.obj", "v 0 0 0\nv 1 0\n");
    // The broken file's read fails first (it is read ahead), but the scene's first error
    // is the unknown parameter of the element before it.
    const std::string scene = dir.write("scene.xml", R"(<scene>
        <mesh type="obj"><string name="filename" value="good.obj"/></mesh>
        <mesh type="obj"><string name="filename" value="good.obj"/><float name="nope" value="1"/></mesh>
        <mesh type="obj"><string name="filename" value="broken.obj"/></mesh>
    </scene>)");
    const std::string error = errorOf([&] { loadFromXML(scene); });
    CHECK_THAT(error, Contains("nope"));
    CHECK_THAT(error, !Contains("broken.obj"));

    const std::string second = dir.write("second.xml", R"(<scene>
        <mesh type="obj"><string name="filename" value="good.obj"/></mesh>
        <mesh type="obj"><string name="filename" value="broken.obj"/></mesh>
    </scene>)");
    CHECK_THAT(errorOf([&] { loadFromXML(second); }),
               Contains("broken.obj:2: vertex position needs 3 numbers, got 2"));
}

TEST_CASE("A pbrt-v4 scene of many PLY files and textures is the same read ahead as one by one",
          "[loadahead][pbrt]") {
    TempDir dir;
    const auto made =
        nori::testing::runCommand(MAKE_PLY_SCENE_EXECUTABLE,
                                  {dir.path().string(), "--meshes", "24", "--triangles", "4800",
                                   "--instances", "60", "--textures", "5", "--texture-size", "16"});
    INFO(made.output);
    REQUIRE(made.exitCode == 0);
    // One thread: no helpers, each shape reads its file itself; all: the helpers read.
    auto load = [&](const std::string &file, int threads) {
        std::shared_ptr<Scene> scene;
        ThreadLimit(threads).run([&] {
            pbrt::ConvertOptions options;
            options.xmlDirectory = dir.path().string();
            const pbrt::Conversion conversion =
                pbrt::convertFile((dir.path() / file).string(), options);
            scene = std::dynamic_pointer_cast<Scene>(
                loadFromXMLString(conversion.xml, options.xmlDirectory));
        });
        REQUIRE(scene);
        return scene;
    };
    for (const char *file : {"plys.pbrt", "instances.pbrt"}) {
        INFO(file);
        const auto serial = load(file, 1), ahead = load(file, 0);
        CHECK(ahead->getBoundingBox().min == serial->getBoundingBox().min);
        CHECK(ahead->getBoundingBox().max == serial->getBoundingBox().max);
        REQUIRE(ahead->getMeshes().size() == serial->getMeshes().size());
        for (size_t i = 0; i < ahead->getMeshes().size(); ++i) {
            CHECK(ahead->getMeshes()[i]->getName() == serial->getMeshes()[i]->getName());
            CHECK(ahead->getMeshes()[i]->positions() == serial->getMeshes()[i]->positions());
            // Textured by image i mod 5: the same reflectance at the same uv.
            const BSDF *aheadBSDF = ahead->getMeshes()[i]->getBSDF(),
                       *serialBSDF = serial->getMeshes()[i]->getBSDF();
            REQUIRE(aheadBSDF);
            REQUIRE(serialBSDF);
            CHECK(aheadBSDF->toString() == serialBSDF->toString());
        }
    }
    CHECK(load("plys.pbrt", 0)->getMeshes().size() == 24);
}
