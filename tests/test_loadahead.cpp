// Files read ahead while the parser builds the scene (LoadAhead): every read the parser
// starts is the one its shape takes, in order, with the reader's errors as they were.
#include <nori/loadahead.h>
#include <nori/mesh.h>
#include <nori/objfile.h>
#include <nori/parallel.h>
#include <nori/parser.h>
#include <nori/pbrtimport.h>
#include <nori/scene.h>

#include "testutil.h"

#include <catch2/catch.hpp>

#include <atomic>
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
NORI_REGISTER_LOAD_AHEAD("test_ahead_obj",
                         [](const std::string &path) { return std::any(readOBJ(path)); });

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

TEST_CASE("A pbrt-v4 scene of many PLY files is the same read ahead as read one by one",
          "[loadahead][pbrt]") {
    TempDir dir;
    const auto made = nori::testing::runCommand(
        MAKE_PLY_SCENE_EXECUTABLE,
        {dir.path().string(), "--meshes", "24", "--triangles", "4800", "--instances", "60"});
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
        }
    }
    CHECK(load("plys.pbrt", 0)->getMeshes().size() == 24);
}
