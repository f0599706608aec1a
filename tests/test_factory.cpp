// The object factory: registration, duplicates, listing, creation by kind.
#include <nori/object.h>

#include "recorder.h"
#include "testutil.h"

#include <nori/plugindoc.h>

#include <catch2/catch.hpp>

using namespace nori;
using Catch::Contains;
using nori::testing::errorOf;

TEST_CASE("Factory lists every plugin with its kind", "[factory]") {
    auto classes = NoriObjectFactory::registeredClasses();
    auto has = [&](NoriObject::EClassType type, const std::string &name) {
        return std::find(classes.begin(), classes.end(), std::make_pair(type, name)) !=
               classes.end();
    };
    CHECK(has(NoriObject::EIntegrator, "normals"));
    CHECK(has(NoriObject::EIntegrator, "ao"));
    CHECK(has(NoriObject::EIntegrator, "simple"));
    CHECK(has(NoriObject::EMesh, "obj"));
    CHECK(has(NoriObject::EMesh, "sphere"));
    CHECK(has(NoriObject::ECamera, "perspective"));
    CHECK(has(NoriObject::ESampler, "independent"));
    CHECK(has(NoriObject::EBSDF, "diffuse"));
    for (const char *filter : {"box", "tent", "gaussian", "mitchell"})
        CHECK(has(NoriObject::EReconstructionFilter, filter));
    CHECK(std::is_sorted(classes.begin(), classes.end()));
    // No name was registered twice at start-up.
    CHECK_NOTHROW(NoriObjectFactory::checkRegistry());
}

TEST_CASE("Factory rejects a name registered twice", "[factory]") {
    auto constructor = [](const PropertyList &props) -> std::shared_ptr<NoriObject> {
        return std::make_shared<nori::testing::Recorder>(props);
    };
    CHECK_THAT(errorOf([&] {
                   NoriObjectFactory::registerClass("diffuse", NoriObject::EBSDF, constructor,
                                                    "elsewhere.cpp");
               }),
               Contains("'diffuse' is registered twice as a bsdf") && Contains("elsewhere.cpp"));
    // Within a kind only: the `constant` texture and the `constant` emitter are two plugins.
    const auto kinds = NoriObjectFactory::kindsOf("constant");
    CHECK(kinds.size() == 2);
    // At static-initialisation time the second registration is kept aside, and
    // checkRegistry() reports it (two files that are not ours: neither replaces the other).
    NoriObjectFactory::registerStatic("recorder", NoriObject::ETest, constructor, __FILE__);
    CHECK_THAT(errorOf([] { NoriObjectFactory::checkRegistry(); }),
               Contains("'recorder' is registered twice"));
}

TEST_CASE("A user's plugin of one of our names replaces ours, until --builtin", "[factory]") {
    // As a course's mirror.cpp would at start-up: a file that is not ours registers `mirror`.
    REQUIRE(isShippedPlugin(NoriObject::EBSDF, "mirror"));
    NoriObjectFactory::registerStatic(
        "mirror", NoriObject::EBSDF,
        [](const PropertyList &props) -> std::shared_ptr<NoriObject> {
            return std::make_shared<nori::testing::Recorder>(props);
        },
        "/course/mirror.cpp");
    CHECK_NOTHROW(NoriObjectFactory::checkRegistry());
    const auto replacements = NoriObjectFactory::replacements();
    REQUIRE(replacements.size() == 1);
    CHECK(replacements[0].name == "mirror");
    CHECK(replacements[0].yourFile == "/course/mirror.cpp");
    CHECK_THAT(replacements[0].ourFile, Contains("plugins/builtin/bsdfs/mirror.cpp"));
    // The name makes the user's plugin; "builtin:mirror" ours.
    CHECK(NoriObjectFactory::createInstance("mirror", NoriObject::EBSDF, {})->getClassType() ==
          NoriObject::ETest);
    CHECK(NoriObjectFactory::createInstance("builtin:mirror", NoriObject::EBSDF, {})
              ->getClassType() == NoriObject::EBSDF);
    CHECK_THAT(errorOf([] { NoriObjectFactory::useBuiltin("diffuse"); }),
               Contains("no plugin of yours replaces one of ours called 'diffuse'") &&
                   Contains("yours replace: mirror"));
    // --builtin mirror: ours again, and nothing is replaced any more.
    NoriObjectFactory::useBuiltin("mirror");
    CHECK(NoriObjectFactory::replacements().empty());
    CHECK(NoriObjectFactory::createInstance("mirror", NoriObject::EBSDF, {})->getClassType() ==
          NoriObject::EBSDF);
}

TEST_CASE("Factory creates by name and checks the kind and the properties", "[factory]") {
    PropertyList props;
    props.setColor("albedo", Color3f(0.25f));
    auto bsdf = NoriObjectFactory::createInstance("diffuse", NoriObject::EBSDF, props);
    REQUIRE(bsdf);
    CHECK(bsdf->getClassType() == NoriObject::EBSDF);

    CHECK_THAT(errorOf([] {
                   NoriObjectFactory::createInstance("difuse", NoriObject::EBSDF, PropertyList());
               }),
               Contains("unknown bsdf plugin 'difuse' (did you mean 'diffuse'?)"));
    CHECK_THAT(errorOf([] {
                   NoriObjectFactory::createInstance("zzz", NoriObject::ESampler, PropertyList());
               }),
               Contains("unknown sampler plugin 'zzz' (known sampler plugins: independent, sobol, "
                        "stratified)"));
    PropertyList typo;
    typo.setColor("albdo", Color3f(0.25f));
    CHECK_THAT(
        errorOf([&] { NoriObjectFactory::createInstance("diffuse", NoriObject::EBSDF, typo); }),
        Contains("'albdo' is not a parameter of bsdf 'diffuse' (did you mean 'albedo'?)"));
}
