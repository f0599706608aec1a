// The XML parser: Nori 2's format, our extensions, and an error with a location for
// every kind of mistake.
#include <nori/bsdf.h>
#include <nori/parallel.h>
#include <nori/parser.h>
#include <nori/scene.h>

#include "recorder.h"
#include "testutil.h"

#include <catch2/catch.hpp>

using namespace nori;
using Catch::Contains;
using nori::testing::errorOf;
using nori::testing::Recorder;
using nori::testing::TempDir;

namespace {

std::shared_ptr<Recorder> parseRecorder(const std::string &xml, const Defines &defines = {}) {
    auto recorder = std::dynamic_pointer_cast<Recorder>(loadFromXMLString(xml, ".", defines));
    REQUIRE(recorder);
    return recorder;
}

std::string parseError(const std::string &xml, const Defines &defines = {}) {
    return errorOf([&] { loadFromXMLString(xml, ".", defines); });
}

} // namespace

TEST_CASE("Parser reads properties of every type, with Nori's value syntax", "[parser]") {
    auto r = parseRecorder(R"(<test type="recorder">
        <boolean name="flag" value="true"/>
        <integer name="count" value="-12"/>
        <float name="alpha" value="2.5e-1"/>
        <string name="label" value="hello world"/>
        <color name="albedo" value="0.1 0.2 0.3"/>
        <point name="position" value="1,2,3"/>
        <point name="uv" value="0.5, 0.25"/>
        <vector name="direction" value="0, 0,1"/>
        <vector name="offset" value="3 4"/>
    </test>)");
    CHECK(r->flag);
    CHECK(r->count == -12);
    CHECK(r->alpha == 0.25f);
    CHECK(r->label == "hello world");
    CHECK(r->albedo.isApprox(Color3f(0.1f, 0.2f, 0.3f)));
    CHECK(r->position == Point3f(1, 2, 3));
    CHECK(r->uv == Point2f(0.5f, 0.25f));
    CHECK(r->direction == Vector3f(0, 0, 1));
    CHECK(r->offset == Vector2f(3, 4));
    CHECK(r->activations == 1);
}

TEST_CASE("Parser accepts scalar shorthand for colours and scale", "[parser]") {
    auto r = parseRecorder(R"(<test type="recorder">
        <color name="albedo" value="0.5"/>
        <transform name="toWorld"><scale value="2"/></transform>
    </test>)");
    CHECK(r->albedo.isApprox(Color3f(0.5f)));
    CHECK(
        r->toWorld.getMatrix().isApprox(Eigen::Vector4f(2, 2, 2, 1).asDiagonal().toDenseMatrix()));
}

TEST_CASE("Parser loads a Nori 2 file with a blank line before <?xml", "[parser]") {
    TempDir dir;
    std::string file = dir.write("scene.xml", "\n<?xml version=\"1.0\" encoding=\"utf-8\"?>\n"
                                              "<test type=\"recorder\">\n"
                                              "  <integer name=\"count\" value=\"3\"/>\n"
                                              "</test>\n");
    auto recorder = std::dynamic_pointer_cast<Recorder>(loadFromXML(file));
    REQUIRE(recorder);
    CHECK(recorder->count == 3);
}

TEST_CASE("Parser loads a scene written the way Nori 2's course files are", "[parser]") {
    TempDir dir;
    // An octahedron, with Nori's formatting of the scene: blank line before a
    // single-quoted declaration, tabs, a nested BSDF, comma-separated lookat.
    dir.write("octahedron.obj", "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n"
                                "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\n"
                                "f 3 1 6\nf 2 3 6\nf 4 2 6\nf 1 4 6\n");
    const std::string file = dir.write("ajax-normals.xml", R"(
<?xml version='1.0' encoding='utf-8'?>

<scene>
	<integrator type="normals"/>

	<camera type="perspective">
		<transform name="toWorld">
			<scale value="-1,1,1"/>
			<lookat target="0, 0, 0" origin="0.5, 0.8, 4" up="0, 1, 0"/>
		</transform>
		<float name="fov" value="40"/>
		<integer name="width" value="64"/>
		<integer name="height" value="48"/>
	</camera>

	<mesh type="obj">
		<string name="filename" value="octahedron.obj"/>
		<bsdf type="diffuse">
			<color name="albedo" value="0.75,0.75,0.75"/>
		</bsdf>
	</mesh>
</scene>
)");
    auto scene = std::dynamic_pointer_cast<Scene>(loadFromXML(file));
    REQUIRE(scene);
    REQUIRE(scene->getShapes().size() == 1);
    CHECK(scene->getShapes()[0]->getPrimitiveCount() == 8);
    CHECK(scene->getCamera()->getOutputSize() == Vector2i(64, 48));
    // The camera looks at the octahedron: the central ray hits it.
    Ray3f ray;
    scene->getCamera()->sampleRay(ray, Point2f(32, 24), Point2f(0.5f, 0.5f));
    CHECK(scene->rayIntersect(ray));
}

TEST_CASE("Parser binds named children, ids and refs", "[parser]") {
    auto r = parseRecorder(R"(<test type="recorder">
        <test type="recorder" id="shared" name="first"/>
        <ref id="shared" name="again"/>
        <test type="recorder"/>
    </test>)");
    REQUIRE(r->children.size() == 3);
    CHECK(r->children[0].first == "first");
    CHECK(r->children[1].first == "again");
    CHECK(r->children[0].second == r->children[1].second); // the same object, not a copy
    CHECK(r->children[2].first.empty());
    // A shared child is activated once, when it is declared.
    CHECK(std::static_pointer_cast<Recorder>(r->children[0].second)->activations == 1);
}

TEST_CASE("A BSDF with an id directly in <scene> is a declaration for <ref>", "[parser]") {
    auto scene = std::dynamic_pointer_cast<Scene>(loadFromXMLString(R"(<scene>
        <bsdf type="diffuse" id="white"><color name="albedo" value="0.7"/></bsdf>
        <integrator type="normals"/><camera type="perspective"/>
        <mesh type="sphere"><ref id="white"/></mesh>
    </scene>)"));
    REQUIRE(scene);
    CHECK(scene->getShapes().at(0)->getBSDF()->toString() == "Diffuse[albedo=(0.7, 0.7, 0.7)]");
    // Without an id it has no use at the top level: the scene refuses it.
    CHECK_THAT(parseError(R"(<scene><bsdf type="diffuse"/></scene>)"),
               Contains("a scene does not accept a bsdf"));
}

TEST_CASE("Parser substitutes $variables from -D and <default>", "[parser]") {
    const std::string xml = R"(<test type="recorder">
        <default name="n" value="4"/>
        <default name="kind" value="recorder"/>
        <integer name="count" value="$n"/>
        <string name="label" value="x$kind-y"/>
        <test type="$kind"/>
    </test>)";
    CHECK(parseRecorder(xml)->count == 4);
    CHECK(parseRecorder(xml)->label == "xrecorder-y");
    // A definition from the command line wins over <default>.
    CHECK(parseRecorder(xml, {{"n", "9"}})->count == 9);
    CHECK_THAT(parseError(R"(<test type="recorder"><integer name="count" value="$cuont"/></test>)",
                          {{"count", "1"}}),
               Contains("<string>:1:24") && Contains("'$cuont' is not defined") &&
                   Contains("did you mean 'count'?"));
}

TEST_CASE("Parser composes transform operations in the order written", "[parser]") {
    auto r = parseRecorder(R"(<test type="recorder">
        <transform name="toWorld">
            <scale value="2,2,2"/>
            <translate value="1 0 0"/>
            <rotate axis="0,0,1" angle="90"/>
        </transform>
    </test>)");
    // scale, then translate, then rotate: (1,0,0) -> (2,0,0) -> (3,0,0) -> (0,3,0).
    Point3f p = r->toWorld * Point3f(1, 0, 0);
    CHECK(p.isApprox(Point3f(0, 3, 0), 1e-5f));

    auto m = parseRecorder(R"(<test type="recorder"><transform name="toWorld">
        <matrix value="1 0 0 5  0 1 0 6  0 0 1 7  0 0 0 1"/>
    </transform></test>)");
    CHECK((m->toWorld * Point3f(0, 0, 0)).isApprox(Point3f(5, 6, 7)));
}

TEST_CASE("Parser includes files relative to the including file, and detects cycles", "[parser]") {
    TempDir dir;
    dir.write("parts/more.xml", R"(<scene>
        <integer name="count" value="5"/>
        <test type="recorder" name="fromInclude"/>
        <include filename="mesh.xml"/>
    </scene>)");
    dir.write("parts/mesh.xml", R"(<scene><string name="filename" value="bunny.obj"/></scene>)");
    const std::string main = dir.write("main.xml", R"(<test type="recorder">
        <include filename="parts/more.xml"/>
    </test>)");
    auto r = std::dynamic_pointer_cast<Recorder>(loadFromXML(main));
    REQUIRE(r);
    CHECK(r->count == 5);
    REQUIRE(r->children.size() == 1);
    CHECK(r->children[0].first == "fromInclude");
    // The file name resolves against parts/, where mesh.xml lives.
    CHECK(r->filename == (dir.path() / "parts" / "bunny.obj").string());

    dir.write("a.xml", R"(<scene><include filename="b.xml"/></scene>)");
    dir.write("b.xml", R"(<scene><include filename="a.xml"/></scene>)");
    const std::string cyclic =
        dir.write("cyclic.xml", R"(<test type="recorder"><include filename="a.xml"/></test>)");
    CHECK_THAT(errorOf([&] { loadFromXML(cyclic); }),
               Contains("b.xml:1:9") && Contains("forms a cycle"));
}

TEST_CASE("Parser errors name the file, line, column and offending name", "[parser]") {
    SECTION("misspelled property, with did-you-mean") {
        CHECK_THAT(parseError("<test type=\"recorder\">\n  <color name=\"albdo\" value=\"1\"/>\n"
                              "</test>"),
                   Contains("<string>:2:4") && Contains("'albdo'") && Contains("test 'recorder'") &&
                       Contains("did you mean 'albedo'?"));
    }
    SECTION("unknown plugin, with did-you-mean") {
        CHECK_THAT(parseError("<scene>\n <integrator type=\"normls\"/>\n</scene>"),
                   Contains("<string>:2:3") && Contains("unknown integrator plugin 'normls'") &&
                       Contains("did you mean 'normals'?"));
    }
    SECTION("plugin of the wrong kind") {
        CHECK_THAT(parseError("<scene><bsdf type=\"normals\"/></scene>"),
                   Contains("<string>:1:9") && Contains("'normals' is an integrator, not a bsdf"));
    }
    SECTION("unknown tag") {
        CHECK_THAT(parseError("<test type=\"recorder\"><flaot name=\"alpha\" value=\"1\"/></test>"),
                   Contains("<string>:1:24") && Contains("unknown tag <flaot>") &&
                       Contains("did you mean 'float'?"));
    }
    SECTION("unexpected and missing attributes") {
        CHECK_THAT(parseError("<test type=\"recorder\"><float name=\"alpha\" vale=\"1\"/></test>"),
                   Contains("unexpected attribute 'vale' in <float>") &&
                       Contains("did you mean 'value'?"));
        CHECK_THAT(parseError("<test type=\"recorder\"><float name=\"alpha\"/></test>"),
                   Contains("<string>:1:24") && Contains("missing the attribute 'value'"));
        CHECK_THAT(parseError("<scene><mesh/></scene>"),
                   Contains("<mesh> is missing the attribute 'type'"));
    }
    SECTION("malformed numbers") {
        CHECK_THAT(
            parseError("<test type=\"recorder\"><float name=\"alpha\" value=\"1.0f\"/></test>"),
            Contains("<string>:1:24") && Contains("'1.0f'"));
        CHECK_THAT(
            parseError("<test type=\"recorder\"><integer name=\"count\" value=\"2.5\"/></test>"),
            Contains("'2.5' as an integer"));
        CHECK_THAT(
            parseError("<test type=\"recorder\"><color name=\"albedo\" value=\"1,2\"/></test>"),
            Contains("has 2 components, expected 1 or 3"));
        CHECK_THAT(
            parseError("<test type=\"recorder\"><boolean name=\"flag\" value=\"yes\"/></test>"),
            Contains("'yes' is neither 'true' nor 'false'"));
    }
    SECTION("a property of the wrong type") {
        CHECK_THAT(
            parseError("<test type=\"recorder\">\n<string name=\"alpha\" value=\"x\"/></test>"),
            Contains("<string>:2:2") && Contains("'alpha' is a string, but a float"));
    }
    SECTION("a property given twice") {
        CHECK_THAT(parseError("<test type=\"recorder\"><float name=\"alpha\" value=\"1\"/>\n"
                              "<float name=\"alpha\" value=\"2\"/></test>"),
                   Contains("<string>:2:2") && Contains("'alpha' is specified twice"));
    }
    SECTION("elements in the wrong place") {
        CHECK_THAT(parseError("<float name=\"alpha\" value=\"1\"/>"),
                   Contains("root element must be an object"));
        CHECK_THAT(parseError("<test type=\"recorder\"><translate value=\"1,2,3\"/></test>"),
                   Contains("<translate> may only appear inside a <transform>"));
        CHECK_THAT(parseError("<test type=\"recorder\"><transform name=\"toWorld\"><float "
                              "name=\"a\" value=\"1\"/></transform></test>"),
                   Contains("<float> may not appear inside a <transform>"));
        CHECK_THAT(parseError("<test type=\"recorder\">oops</test>"),
                   Contains("unexpected text 'oops'"));
        CHECK_THAT(parseError("<test type=\"recorder\"><float name=\"alpha\" value=\"1\">"
                              "<float name=\"b\" value=\"1\"/></float></test>"),
                   Contains("<float> takes no content"));
    }
    SECTION("ids and refs") {
        CHECK_THAT(parseError("<test type=\"recorder\"><ref id=\"nothing\"/></test>"),
                   Contains("<string>:1:24") && Contains("unknown id 'nothing'"));
        CHECK_THAT(parseError("<test type=\"recorder\"><test type=\"recorder\" id=\"a\"/>\n"
                              "<test type=\"recorder\" id=\"a\"/></test>"),
                   Contains("<string>:2:2") && Contains("id 'a' is already used at <string>:1:24"));
    }
    SECTION("XML syntax") {
        // pugixml parses the text in place; the message is made from the text as written.
        CHECK_THAT(parseError("<scene>\n<integrator type=\"normals\">\n</scene>"),
                   Contains("<string>:3:1: XML syntax error: <integrator> opened at <string>:2:1 "
                            "is not closed before '</scene>'"));
    }
    SECTION("a child the parent does not accept") {
        CHECK_THAT(parseError("<scene>\n<integrator type=\"normals\">\n"
                              "  <sampler type=\"independent\"/>\n</integrator></scene>"),
                   Contains("<string>:3:4") && Contains("an integrator does not accept a sampler"));
    }
    SECTION("two children for one slot") {
        CHECK_THAT(parseError("<scene>\n<integrator type=\"normals\"/>\n<integrator "
                              "type=\"ao\"/></scene>"),
                   Contains("<string>:3:2") && Contains("a scene takes only one integrator"));
    }
    SECTION("an incomplete scene") {
        CHECK_THAT(parseError("<scene>\n<integrator type=\"normals\"/>\n</scene>"),
                   Contains("<string>:1:2") && Contains("the scene has no camera"));
    }
    SECTION("a bad parameter value, checked by the plugin") {
        CHECK_THAT(parseError("<scene>\n<mesh type=\"sphere\"><float name=\"radius\" "
                              "value=\"-1\"/></mesh></scene>"),
                   Contains("<string>:2:2") && Contains("'radius' must be positive, got -1"));
    }
    SECTION("a missing file") {
        CHECK_THAT(errorOf([] { loadFromXML("/nonexistent/scene.xml"); }),
                   Contains("cannot open XML scene file '/nonexistent/scene.xml': no such file"));
        CHECK_THAT(parseError("<test type=\"recorder\"><include filename=\"nope.xml\"/></test>"),
                   Contains("<string>:1:24") && Contains("nope.xml"));
        CHECK_THAT(parseError("<scene><mesh type=\"obj\"><string name=\"filename\" "
                              "value=\"missing.obj\"/></mesh></scene>"),
                   Contains("<string>:1:9") && Contains("cannot open OBJ mesh file") &&
                       Contains("missing.obj"));
    }
}

TEST_CASE("Scenes load from several threads at once", "[parser]") {
    // Each load puts its folder in Nori 2's process-wide file resolver; concurrent loads
    // once freed the same entry twice (the agreement test loads its batches in parallel).
    testing::TempDir dir;
    dir.write("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n");
    const std::string xml = R"(<scene><integrator type="normals"/>
        <camera type="perspective"><integer name="width" value="4"/><integer name="height" value="4"/></camera>
        <mesh type="obj"><string name="filename" value="quad.obj"/></mesh></scene>)";
    std::vector<size_t> loaded(2000, 0);
    parallelFor(size_t(0), loaded.size(), [&](size_t i) {
        loaded[i] = testing::loadScene(xml, dir.path().string())->getShapes().size();
    });
    CHECK(std::count(loaded.begin(), loaded.end(), size_t(1)) == 2000);
}
