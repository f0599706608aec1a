// Plugin doc comments: every plugin in plugins/ documents itself (what it models, every
// parameter, runnable examples), and reads no parameter its doc block does not name.
#include <nori/parser.h>
#include <nori/plugindoc.h>

#include "testutil.h"

#include <catch2/catch.hpp>

#include <fstream>
#include <map>
#include <set>

using namespace nori;
using Catch::Contains;
using nori::testing::errorOf;

namespace {

/// The plugins registered from the project's own files (plugins/builtin/shipped.txt), not from
/// a user's files in plugins/ nor from the tests' own plugins.
std::vector<std::pair<NoriObject::EClassType, std::string>> shippedPlugins() {
    std::vector<std::pair<NoriObject::EClassType, std::string>> plugins;
    for (const auto &[type, name] : NoriObjectFactory::registeredClasses())
        if (isShippedPlugin(type, name))
            plugins.emplace_back(type, name);
    return plugins;
}

} // namespace

TEST_CASE("Doc comments parse into name, summary, parameters and examples", "[docs]") {
    const PluginDoc doc = parsePluginDoc(R"(/*
 * phong — a glossy lobe (Lafortune and Willems 1994). More text. And more.
 *
 * Parameters:
 *   kd        color    0.5    diffuse albedo
 *   exponent  float    20     the lobe's
 *                             sharpness
 *   eta, k    color    (1, 1, 1)  two names
 *
 *   <bsdf type="phong"/>
 *
 *   <bsdf type="phong">
 *       <float name="exponent" value="5"/>
 *   </bsdf>
 */)");
    CHECK(doc.name == "phong");
    CHECK(doc.summary == "a glossy lobe (Lafortune and Willems 1994).");
    REQUIRE(doc.parameters.size() == 3);
    CHECK(doc.parameters[1].names == std::vector<std::string>{"exponent"});
    CHECK(doc.parameters[1].meaning == "the lobe's sharpness");
    CHECK(doc.parameters[2].names == std::vector<std::string>{"eta", "k"});
    CHECK(doc.parameters[2].defaultValue == "(1, 1, 1)");
    CHECK(doc.documents("k"));
    CHECK_FALSE(doc.documents("ks"));
    REQUIRE(doc.examples.size() == 2);
    CHECK(doc.examples[1] ==
          "<bsdf type=\"phong\">\n    <float name=\"exponent\" value=\"5\"/>\n</bsdf>\n");

    CHECK_THAT(errorOf([] { parsePluginDoc("/*\n * phong: no dash\n *\n * No parameters.\n */"); }),
               Contains("must start with 'name — what it models'"));
    CHECK_THAT(errorOf([] {
                   parsePluginDoc(
                       "/*\n * a — b\n *\n * Parameters:\n *   x float 1 one space\n */");
               }),
               Contains("needs four columns two spaces apart"));
    CHECK_THAT(errorOf([] {
                   parsePluginDoc(
                       "/*\n * a — b\n *\n * Parameters:\n *   x  real  1  wrong type\n */");
               }),
               Contains("has the type 'real'"));
    CHECK_THAT(errorOf([] { parsePluginDoc("/*\n * a — b\n */"); }),
               Contains("neither 'Parameters:' nor 'No parameters'"));
    // A reflowed comment: the end of one line's meaning joined to the next parameter.
    CHECK_THAT(errorOf([] {
                   parsePluginDoc("/*\n * a — b\n *\n * Parameters:\n"
                                  " *   maxDepth  integer  -1  bounces after the camera ray\n"
                                  " * (-1: unbounded) rrDepth  integer  3  roulette\n */");
               }),
               Contains("names '(-1:', which is not a parameter name"));
}

TEST_CASE("Every plugin has a doc block with its name and at least one example", "[docs]") {
    const auto plugins = shippedPlugins();
    REQUIRE(plugins.size() > 30);
    for (const auto &[type, name] : plugins) {
        INFO(name << " (" << NoriObjectFactory::entry(type, name).sourceFile << ")");
        const std::string comment = docCommentOf(type, name);
        REQUIRE_FALSE(comment.empty());
        const PluginDoc doc = parsePluginDoc(comment);
        CHECK(doc.names(name));
        CHECK_FALSE(doc.summary.empty());
        CHECK_FALSE(doc.examples.empty());
    }
}

TEST_CASE("Every file of plugins/builtin/shipped.txt exists and registers a plugin", "[docs]") {
    std::set<std::string> registeringFiles;
    for (const auto &[type, name] : shippedPlugins())
        registeringFiles.insert(shortSourcePath(NoriObjectFactory::entry(type, name).sourceFile));
    std::ifstream list(std::string(NORI_SOURCE_DIR) + "/plugins/builtin/shipped.txt");
    REQUIRE(list);
    int files = 0;
    for (std::string line; std::getline(list, line);) {
        if (line.empty() || line[0] == '#')
            continue;
        ++files;
        INFO(line);
        CHECK(registeringFiles.count("plugins/builtin/" + line) == 1);
    }
    CHECK(files == static_cast<int>(registeringFiles.size()));
}

TEST_CASE("Every plugin's examples load, and it reads only documented parameters", "[docs]") {
    // Which parameters each plugin asked its property list for, as the examples build them.
    using Plugin = std::pair<NoriObject::EClassType, std::string>;
    std::map<Plugin, std::set<std::string>> queried;
    NoriObjectFactory::setObserver(
        [&](NoriObject::EClassType type, const std::string &name, const PropertyList &props) {
            std::set<std::string> &names = queried[Plugin(type, name)]; // also without parameters
            for (const std::string &parameter : props.queriedNames())
                names.insert(parameter);
        });
    for (const auto &plugin : shippedPlugins()) {
        const auto &[type, name] = plugin;
        const PluginDoc doc = parsePluginDoc(docCommentOf(type, name));
        queried.erase(plugin);
        for (const std::string &example : doc.examples) {
            INFO(name << " example:\n" << example);
            // Examples name files relative to the repository (scenes/...).
            CHECK_NOTHROW(loadFromXMLString(example, NORI_SOURCE_DIR));
        }
        INFO(name);
        CHECK(queried.count(plugin) == 1); // an example built it
        const std::vector<ParameterDoc> &common = commonParameters(type);
        for (const std::string &parameter : queried[plugin]) {
            INFO(name << " reads '" << parameter << "'");
            CHECK((doc.documents(parameter) ||
                   std::any_of(common.begin(), common.end(), [&](const ParameterDoc &doc) {
                       return doc.names.front() == parameter;
                   })));
        }
    }
    NoriObjectFactory::setObserver({});
}

TEST_CASE("nori --list-plugins filters by kind and prints one plugin's doc", "[docs][cli]") {
    using nori::testing::runNori;
    auto bsdfs = runNori({"--list-plugins", "bsdf"});
    CHECK(bsdfs.exitCode == 0);
    CHECK_THAT(bsdfs.output, Contains("bsdf:\n") && Contains("  diffuse ") &&
                                 Contains("an ideal Lambertian reflector") &&
                                 !Contains("integrator:"));
    auto diffuse = runNori({"--list-plugins", "diffuse"});
    CHECK(diffuse.exitCode == 0);
    CHECK_THAT(diffuse.output, Contains("diffuse (bsdf, plugins/builtin/bsdfs/diffuse.cpp)") &&
                                   Contains("albedo  color/texture  0.5") &&
                                   Contains("<bsdf type=\"diffuse\">"));
    auto typo = runNori({"--list-plugins", "difuse"});
    CHECK(typo.exitCode == 1);
    CHECK_THAT(typo.output, Contains("'difuse' is neither a kind of plugin nor a plugin (did you "
                                     "mean 'diffuse'?)"));
}
