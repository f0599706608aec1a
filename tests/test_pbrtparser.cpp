// pbrt-v4's scene file format (pbrtparser.h): tokens, directives with their positional
// arguments, typed parameter lists, Include and Import, and every malformation an error at
// its file:line:column.
#include <nori/compression.h>
#include <nori/pbrtparser.h>

#include "testutil.h"

#include <catch2/catch.hpp>

using namespace nori;
using namespace nori::testing;
using Catch::Contains;

namespace {

std::vector<pbrt::Directive> parse(const std::string &text) {
    std::vector<pbrt::Directive> out;
    pbrt::parseString(text, "scene.pbrt", [&](const pbrt::Directive &d) { out.push_back(d); });
    return out;
}

std::vector<std::string> names(const std::vector<pbrt::Directive> &directives) {
    std::vector<std::string> out;
    out.reserve(directives.size());
    for (const auto &d : directives)
        out.push_back(d.name);
    return out;
}

std::vector<pbrt::Directive> parseFile(const std::string &path) {
    std::vector<pbrt::Directive> out;
    pbrt::parseFile(path, [&](const pbrt::Directive &d) { out.push_back(d); });
    return out;
}

} // namespace

TEST_CASE("pbrt-v4 directives come with their arguments, parameters and locations",
          "[pbrt][parser]") {
    const auto d = parse(R"(# a comment line
LookAt 0 1 6.8  0 1 0  0 1 0   # trailing comment
Camera "perspective" "float fov" [ 19.5 ] "float lensradius" 0.01
Film "rgb" "integer xresolution" [64] "string filename" "out.exr"
WorldBegin
Texture "checks" "spectrum" "checkerboard" "float uscale" 8 "rgb tex1" [ .8 .8 .8 ]
MediumInterface "fog" ""
MediumInterface "smoke"
Shape "trianglemesh" "point3 P" [ -1 0 -1  1 0 -1  1 0 1 ] "integer indices" [ 0 1 2 ]
  "normal N" [ 0 1 0 0 1 0 0 1 0 ] "bool alpha" "true" "spectrum s" "metal-Au-eta"
ActiveTransform StartTime
Transform [ 1 0 0 0  0 1 0 0  0 0 1 0  0.5 0.3 0.2 1 ]
Option "bool disablepixeljitter" true
Option "integer seed" 7
LightSource "infinite" "string filename" "sky \"noon\"\t.exr"
AttributeBegin AttributeEnd
WorldEnd
)");
    CHECK(names(d) == std::vector<std::string>{
                          "LookAt", "Camera", "Film", "WorldBegin", "Texture", "MediumInterface",
                          "MediumInterface", "Shape", "ActiveTransform", "Transform", "Option",
                          "Option", "LightSource", "AttributeBegin", "AttributeEnd", "WorldEnd"});
    CHECK(d[0].numbers == std::vector<double>{0, 1, 6.8, 0, 1, 0, 0, 1, 0});
    CHECK(d[0].location.str() == "scene.pbrt:2:1");
    CHECK(d[1].strings == std::vector<std::string>{"perspective"});
    REQUIRE(d[1].parameters.size() == 2);
    CHECK(d[1].parameters[0].type == "float");
    CHECK(d[1].parameters[0].name == "fov");
    CHECK(d[1].parameters[0].numbers == std::vector<double>{19.5});
    CHECK(d[1].parameters[1].numbers == std::vector<double>{0.01});
    CHECK(d[1].parameters[1].location.str() == "scene.pbrt:3:43");
    CHECK(d[2].parameters[0].numbers == std::vector<double>{64}); // "[64]" without spaces
    CHECK(d[2].parameters[1].strings == std::vector<std::string>{"out.exr"});
    CHECK(d[4].strings == std::vector<std::string>{"checks", "spectrum", "checkerboard"});
    CHECK(d[4].parameters[1].numbers == std::vector<double>{0.8, 0.8, 0.8});
    CHECK(d[5].strings == std::vector<std::string>{"fog", ""});
    CHECK(d[6].strings == std::vector<std::string>{"smoke"});
    const auto &shape = d[7];
    REQUIRE(shape.parameters.size() == 5);
    CHECK(shape.parameters[2].type == "normal3"); // "normal" as pbrt-v4 upgrades it
    CHECK(shape.parameters[3].bools == std::vector<bool>{true});
    CHECK(shape.parameters[4].strings == std::vector<std::string>{"metal-Au-eta"});
    CHECK(d[8].strings == std::vector<std::string>{"StartTime"});
    CHECK(d[9].numbers.size() == 16);
    CHECK(d[9].numbers[12] == 0.5);
    CHECK(d[10].strings == std::vector<std::string>{"bool disablepixeljitter", "true"});
    CHECK(d[11].numbers == std::vector<double>{7});
    CHECK(d[12].parameters[0].strings == std::vector<std::string>{"sky \"noon\"\t.exr"});
}

TEST_CASE("pbrt-v4 Include reads in place, Import between AttributeBegin and End",
          "[pbrt][parser]") {
    TempDir folder;
    folder.write("geometry/shapes.pbrt", "Shape \"sphere\"\nInclude \"more.pbrt\"\n");
    folder.write("geometry/more.pbrt", "Shape \"disk\"");
    folder.write("named.pbrt",
                 "MakeNamedMaterial \"m\" \"string type\" \"diffuse\"\nTranslate 1 2 3\n");
    folder.write("compressed.pbrt.gz", gzip("Shape \"cylinder\"\n"));
    const std::string main = folder.write("scene.pbrt", R"(WorldBegin
Include "geometry/shapes.pbrt"
Import "named.pbrt"
NamedMaterial "m"
Include "compressed.pbrt.gz"
)");
    const auto d = parseFile(main);
    CHECK(names(d) == std::vector<std::string>{"WorldBegin", "Shape", "Shape", "AttributeBegin",
                                               "MakeNamedMaterial", "Translate", "AttributeEnd",
                                               "NamedMaterial", "Shape"});
    CHECK(d[2].strings == std::vector<std::string>{"disk"});
    CHECK_THAT(d[2].location.str(), Contains("geometry/more.pbrt:1:1"));
    CHECK(d[8].strings == std::vector<std::string>{"cylinder"});
    // Include is not available when parsing text (the fuzz target's mode).
    CHECK_THAT(errorOf([] { parse("Include \"x.pbrt\""); }),
               Contains("scene.pbrt:1:9: Include is not available here"));
    // A missing file is reported where the Include stands; a cycle too.
    folder.write("loop.pbrt", "Include \"loop.pbrt\"\n");
    CHECK_THAT(errorOf([&] { parseFile((folder.path() / "loop.pbrt").string()); }),
               Contains("loop.pbrt:1:9") && Contains("includes itself"));
    folder.write("missing.pbrt", "\n  Include \"nowhere.pbrt\"\n");
    CHECK_THAT(errorOf([&] { parseFile((folder.path() / "missing.pbrt").string()); }),
               Contains("missing.pbrt:2:11") && Contains("nowhere.pbrt"));
}

TEST_CASE("Malformed pbrt-v4 files are errors at file:line:column", "[pbrt][parser][errors]") {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"Shpe \"sphere\"", "scene.pbrt:1:1: unknown directive 'Shpe' (did you mean 'Shape'?)"},
        {"Shape \"sphere\" \"flaot radius\" 1",
         "scene.pbrt:1:16: unknown parameter type 'flaot' (did you mean 'float'?)"},
        {"Shape \"sphere\" \"float\" 1", "is not a parameter declaration"},
        {"Shape \"sphere\n\"", "scene.pbrt:1:7: a string is not closed on its line"},
        {"Shape \"sphere\" \"float radius\" [ 1 2", "the file ends in the middle of a directive"},
        {"Translate 1 x 3", "scene.pbrt:1:13: 'x' is not a number"},
        {"Translate 1 2", "the file ends in the middle of a directive"},
        {"Translate 1 2 1e999", "'1e999' is not a finite number"},
        {"Film \"rgb\" \"integer xresolution\" 6.5", "scene.pbrt:1:34: '6.5' is not an integer"},
        {"Shape \"x\" \"float radius\" [ 1 \"two\" ]", "expects one kind of value"},
        {"Shape \"x\" \"point3 P\" [ 1 2 ]", "\"point3 P\" expects triples of numbers"},
        {"Shape \"x\" \"string name\" 3", "\"string name\" expects strings in quotes"},
        {"Shape \"x\" \"rgb c\" [ ]", "expects at least one value"},
        {"Transform [ 1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 ]",
         "scene.pbrt:1:43: expected a number, found ']'"},
        {"ConcatTransform 1 0 0 0", "ConcatTransform takes [ 16 numbers ]"},
        {"ActiveTransform Sometimes", "ActiveTransform takes All, StartTime or EndTime"},
        {"\"floating\"", "scene.pbrt:1:1: expected a directive, found the string \"floating\""},
        {"Shape sphere", "expected a type in quotes, found 'sphere'"},
        {"Shape \"x\" \"string s\" \"a\\qb\"", "unknown escape '\\q'"},
        {"LookAt 0 0 0\n  0 0 -1\n  0 1", "scene.pbrt:3:5: the file ends in the middle"},
    };
    for (const auto &entry : cases) {
        const std::string &text = entry.first, &message = entry.second;
        INFO(text);
        CHECK_THAT(errorOf([&] { parse(text); }), Contains(message));
    }
}
