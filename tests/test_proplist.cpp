// PropertyList: typed getters, defaults, type errors, unread-property detection.
#include <nori/proplist.h>
#include <nori/strutil.h>

#include "testutil.h"

#include <catch2/catch.hpp>

using namespace nori;
using Catch::Contains;
using nori::testing::errorOf;

TEST_CASE("PropertyList returns set values and defaults", "[proplist]") {
    PropertyList props;
    props.setBoolean("flag", true);
    props.setInteger("count", 7);
    props.setFloat("alpha", 0.25f);
    props.setString("label", "hello");
    props.setColor("albedo", Color3f(0.1f, 0.2f, 0.3f));
    props.setPoint("position", Point3f(1, 2, 3));
    props.setVector("direction", Vector3f(0, 0, 1));
    props.set("uv", Point2f(0.5f, 0.75f));

    CHECK(props.getBoolean("flag") == true);
    CHECK(props.getInteger("count") == 7);
    CHECK(props.getFloat("alpha") == 0.25f);
    CHECK(props.getString("label") == "hello");
    CHECK(props.getColor("albedo").isApprox(Color3f(0.1f, 0.2f, 0.3f)));
    CHECK(props.getPoint("position") == Point3f(1, 2, 3));
    CHECK(props.getVector("direction") == Vector3f(0, 0, 1));
    CHECK(props.getPoint2("uv") == Point2f(0.5f, 0.75f));
    CHECK(props.getFloat("missing", 4.5f) == 4.5f);
    CHECK(props.getInteger("missingInt", -3) == -3);
    CHECK(props.unreadProperties().empty());
}

TEST_CASE("PropertyList promotes an integer to a float", "[proplist]") {
    PropertyList props;
    props.setInteger("radius", 3);
    CHECK(props.getFloat("radius") == 3.0f);
    CHECK(props.getFloat("radius", 1.0f) == 3.0f);
}

TEST_CASE("PropertyList reports missing, mistyped and duplicate properties", "[proplist]") {
    PropertyList props;
    props.set("alpha", std::string("rough"), "scene.xml:4:9");
    CHECK_THAT(errorOf([&] { props.getFloat("alpha"); }),
               Contains("scene.xml:4:9") && Contains("'alpha' is a string, but a float"));
    CHECK_THAT(errorOf([&] { props.getColor("albedo"); }),
               Contains("'albedo'") && Contains("required"));
    CHECK_THAT(errorOf([&] { props.set("alpha", 1.0f, "scene.xml:5:9"); }),
               Contains("scene.xml:5:9") && Contains("twice") && Contains("scene.xml:4:9"));

    PropertyList flat;
    flat.set("center", Point2f(1, 2), "a.xml:1:1");
    CHECK_THAT(errorOf([&] { flat.getPoint("center"); }), Contains("point (2D)"));
}

TEST_CASE("PropertyList names a property nobody read, with a suggestion", "[proplist]") {
    PropertyList props;
    props.set("albdo", Color3f(0.5f), "scene.xml:12:13");
    props.setFloat("alpha", 0.1f);
    props.getColor("albedo", Color3f(0.5f)); // the plugin asks for the right name
    props.getFloat("alpha");
    REQUIRE(props.unreadProperties() == std::vector<std::string>{"albdo"});
    const std::string message = errorOf([&] { props.checkAllRead("bsdf 'diffuse'"); });
    CHECK_THAT(message, Contains("scene.xml:12:13") && Contains("'albdo'") &&
                            Contains("bsdf 'diffuse'") && Contains("did you mean 'albedo'?"));

    SECTION("without a close name, the known parameters are listed") {
        PropertyList other;
        other.set("colour", Color3f(0.5f), "scene.xml:2:3");
        other.getColor("albedo", Color3f(0.5f));
        other.getFloat("roughness", 0.1f);
        CHECK_THAT(errorOf([&] { other.checkAllRead("bsdf 'x'"); }),
                   Contains("its parameters: albedo, roughness"));
    }
}

TEST_CASE("PropertyList resolves relative paths against the XML file's folder", "[proplist]") {
    PropertyList props;
    props.set("filename", std::string("meshes/bunny.obj"), "", "/data/scenes");
    props.set("absolute", std::string("/abs/file.obj"), "", "/data/scenes");
    CHECK(props.getPath("filename") == "/data/scenes/meshes/bunny.obj");
    CHECK(props.getPath("absolute") == "/abs/file.obj");
}

TEST_CASE("Did-you-mean finds names one edit away and ignores unrelated ones", "[proplist]") {
    const std::vector<std::string> names = {"albedo", "intIOR", "extIOR", "alpha"};
    CHECK(closestMatch("albdo", names) == "albedo");   // deletion
    CHECK(closestMatch("albedoo", names) == "albedo"); // insertion
    CHECK(closestMatch("albeod", names) == "albedo");  // transposition
    CHECK(closestMatch("intior", names) == "intIOR");  // case only
    CHECK(closestMatch("roughness", names).empty());
    CHECK(closestMatch("x", {"y"}).empty()); // one edit, but nothing in common
    CHECK(editDistance("kitten", "sitting") == 3);
}

TEST_CASE("jsonString escapes quotes, backslashes and control characters (RFC 8259 §7)",
          "[strutil]") {
    CHECK(jsonString("cbox.xml") == "\"cbox.xml\"");
    CHECK(jsonString("a \"b\" \\ c") == "\"a \\\"b\\\" \\\\ c\"");
    CHECK(jsonString("line\nnext\ttab\x01") == "\"line\\nnext\\ttab\\u0001\"");
    CHECK(jsonString("σ² ok") == "\"σ² ok\""); // UTF-8 passes through
}
