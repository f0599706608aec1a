// Spectra to RGB (spectrum.h): the one method every spectrum goes through, checked where
// the answer is known (a flat reflectance is white, D65 light is white, Planck's law and
// its peak), the named spectra and .spd files, and the textures that carry them.
#include "testutil.h"

#include <nori/bsdf.h>
#include <nori/fresnel.h>
#include <nori/parser.h>
#include <nori/spectrum.h>

#include <catch2/catch.hpp>

using namespace nori;
using namespace nori::testing;

TEST_CASE("Spectra to RGB: flat reflectance and D65 light are white", "[spectrum]") {
    const Color3f flat = reflectanceToRGB([](float) { return 1.0f; });
    INFO(flat.transpose());
    CHECK(flat.isApprox(Color3f(1.0f), 1e-3f));
    const Color3f half = reflectanceToRGB([](float) { return 0.5f; });
    CHECK(half.isApprox(Color3f(0.5f), 1e-3f));
    // D65 is sRGB's white: as light its channels are equal, and its Y is its mean over ȳ.
    const PiecewiseLinearSpectrum &d65 = namedSpectrum("stdillum-D65");
    const Color3f white = emissionToRGB([&](float lambda) { return d65(lambda); });
    INFO(white.transpose());
    CHECK(white.g() == Approx(white.r()).epsilon(2e-3));
    CHECK(white.b() == Approx(white.r()).epsilon(2e-3));
    // A narrow line at 610 nm is red, at 450 nm blue.
    const Color3f red =
        emissionToRGB([](float l) { return std::abs(l - 610.0f) < 3.0f ? 1.0f : 0.0f; });
    CHECK(red.r() > 4.0f * std::abs(red.g()));
    const Color3f blue =
        emissionToRGB([](float l) { return std::abs(l - 450.0f) < 3.0f ? 1.0f : 0.0f; });
    CHECK(blue.b() > 4.0f * std::abs(blue.g()));
}

TEST_CASE("Planck's law and pbrt-v4's normalised blackbody", "[spectrum]") {
    // 2hc²/λ⁵/(exp(hc/λkT) − 1) at 500 nm and 5000 K (CODATA 2010 constants).
    CHECK(planck(500.0, 5000.0) == Approx(1.2107185523532752e13).epsilon(1e-9));
    // Normalised to 1 at Wien's peak, below 1 elsewhere.
    for (const float temperature : {2000.0f, 5000.0f, 9000.0f}) {
        const float peak = 2.8977721e6f / temperature;
        CHECK(normalizedBlackbody(peak, temperature) == Approx(1.0f).epsilon(1e-5));
        CHECK(normalizedBlackbody(peak * 1.2f, temperature) < 1.0f);
        CHECK(normalizedBlackbody(peak * 0.8f, temperature) < 1.0f);
    }
    // Warm light is red, hot light blue.
    auto colour = [](float temperature) {
        return emissionToRGB(
            [temperature](float l) { return normalizedBlackbody(l, temperature); });
    };
    const Color3f warm = colour(2500.0f), hot = colour(12000.0f);
    CHECK(warm.r() > warm.g());
    CHECK(warm.g() > warm.b());
    CHECK(hot.b() > hot.r());
    const auto texture = std::dynamic_pointer_cast<Texture>(loadFromXMLString(
        R"(<texture type="blackbody"><float name="temperature" value="2500"/>
            <float name="scale" value="3"/></texture>)"));
    REQUIRE(texture);
    CHECK(texture->average().isApprox(3.0f * warm, 1e-5f));
    CHECK_THAT(
        errorOf([] {
            loadFromXMLString(
                R"(<texture type="blackbody"><float name="temperature" value="-5"/></texture>)");
        }),
        Catch::Contains("'temperature' must be positive"));
}

TEST_CASE("Named spectra, .spd files and inline pairs give the same colours", "[spectrum]") {
    // Gold's η: low in the red, high in the blue (it reflects red and yellow).
    const PiecewiseLinearSpectrum &goldEta = namedSpectrum("metal-Au-eta");
    CHECK(goldEta(700.0f) < 0.2f);
    CHECK(goldEta(400.0f) > 1.6f);
    const Color3f eta = reflectanceToRGB([&](float l) { return goldEta(l); });
    CHECK(eta.r() < eta.g());
    CHECK(eta.g() < eta.b());
    CHECK(isNamedSpectrum("metal-CuZn-k"));
    CHECK_THAT(errorOf([] { namedSpectrum("metal-Au-et"); }),
               Catch::Contains("did you mean 'metal-Au-eta'"));

    TempDir folder;
    const std::string spd =
        folder.write("ramp.spd", "# a ramp\n400 0.1\n500 0.3  # comment\n600 0.8\n700 0.9\n");
    auto texture = [&](const std::string &xml) {
        auto t = std::dynamic_pointer_cast<Texture>(loadFromXMLString(xml, folder.path().string()));
        REQUIRE(t);
        return t->average();
    };
    const Color3f fromFile =
        texture(R"(<texture type="spectrum"><string name="filename" value="ramp.spd"/></texture>)");
    const Color3f inline_ = texture(R"(<texture type="spectrum">
        <string name="values" value="400:0.1, 500:0.3, 600:0.8, 700:0.9"/></texture>)");
    CHECK((fromFile == inline_).all());
    CHECK(fromFile.r() > fromFile.b());
    for (const auto &[content, message] : std::vector<std::pair<std::string, std::string>>{
             {"400 0.1\n500\n", ":2: a wavelength without its value"},
             {"400 0.1\n300 0.2\n", ":2: wavelength 300 does not follow 400"},
             {"400 abc\n", ":1: 'abc' is not a number"},
             {"# nothing\n", "holds no (wavelength, value) pairs"}}) {
        const std::string path = folder.write("bad.spd", content);
        CHECK_THAT(errorOf([&] { readSpectrumFile(path); }),
                   Catch::Contains("bad.spd") && Catch::Contains(message));
    }
    // Brass, magnesium oxide and titanium dioxide by name on the conductors.
    for (const char *metal : {"CuZn", "MgO", "TiO2"}) {
        Color3f e, k;
        lookupConductor(metal, e, k);
        CHECK((e > 0.0f).all());
        CHECK((k >= 0.0f).all());
    }
}

TEST_CASE("Every conductor name of Mitsuba 0.6 has measured eta and k", "[spectrum][bsdf]") {
    // Mitsuba 0.6's table of conductor presets (its conductor plugin's documentation).
    const std::vector<std::string> names = {
        "a-C",       "Ag",         "Al",         "AlAs",       "AlAs_palik",
        "AlSb",      "AlSb_palik", "Au",         "Be",         "Be_palik",
        "Cr",        "CsI",        "CsI_palik",  "Cu",         "Cu_palik",
        "Cu2O",      "Cu2O_palik", "CuO",        "CuO_palik",  "d-C",
        "d-C_palik", "Hg",         "Hg_palik",   "HgTe",       "HgTe_palik",
        "Ir",        "Ir_palik",   "K",          "K_palik",    "Li",
        "Li_palik",  "MgO",        "MgO_palik",  "Mo",         "Mo_palik",
        "Na_palik",  "Nb",         "Nb_palik",   "Ni_palik",   "Rh",
        "Rh_palik",  "Se",         "Se_palik",   "Se-e",       "Se-e_palik",
        "SiC",       "SiC_palik",  "SnTe",       "SnTe_palik", "Ta",
        "Ta_palik",  "Te",         "Te_palik",   "Te-e",       "Te-e_palik",
        "ThF4",      "ThF4_palik", "TiC",        "TiC_palik",  "TiN",
        "TiN_palik", "TiO2",       "TiO2_palik", "TiO2-e",     "TiO2-e_palik",
        "VC",        "VC_palik",   "V_palik",    "VN",         "VN_palik",
        "W",         "none"};
    CHECK(names.size() == 72);
    for (const std::string &name : names) {
        CAPTURE(name);
        Color3f eta, k;
        lookupConductor(name, eta, k);
        CHECK((eta >= 0.0f).all());
        CHECK((k >= 0.0f).all());
        CHECK(eta.allFinite());
        CHECK(k.allFinite());
    }
    const auto normalReflectance = [](const std::string &name) {
        Color3f eta, k;
        lookupConductor(name, eta, k);
        return fresnelConductor(1.0f, eta, k);
    };
    // "none" reflects everything at every angle.
    Color3f eta, k;
    lookupConductor("none", eta, k);
    for (float cosTheta : {1.0f, 0.7f, 0.3f, 0.05f})
        CHECK(fresnelConductor(cosTheta, eta, k).isApprox(Color3f(1.0f), 1e-5f));
    // Diamond is a dielectric (k = 0) with η from 2.41 (red) to 2.46 (blue): R ≈ 0.17.
    lookupConductor("d-C", eta, k);
    INFO("d-C eta " << eta.transpose() << " k " << k.transpose());
    CHECK((k.array() < 1e-3f).all());
    CHECK(eta.r() == Approx(2.415f).margin(0.01f));
    CHECK(eta.b() == Approx(2.45f).margin(0.015f));
    CHECK(eta.b() > eta.r());
    // Chromium, tungsten and nickel at normal incidence, against R = ((n−1)² + k²) /
    // ((n+1)² + k²) of their tables at 650, 550 and 450 nm (an RGB channel averages a
    // band, so within 3 %): Cr 3.64+4.36i, 3.12+4.42i, 1.92+4.15i; W 3.70+2.94i,
    // 3.50+2.73i, 3.31+2.53i; Ni 2.02+3.82i, 1.78+3.26i, 1.63+2.66i.
    const auto reflectance = [](float n, float kappa) {
        return ((n - 1) * (n - 1) + kappa * kappa) / ((n + 1) * (n + 1) + kappa * kappa);
    };
    const Color3f chromium = normalReflectance("Cr"), tungsten = normalReflectance("W"),
                  nickel = normalReflectance("Ni_palik");
    INFO("Cr " << chromium.transpose() << ", W " << tungsten.transpose() << ", Ni "
               << nickel.transpose());
    CHECK(chromium.isApprox(
        Color3f(reflectance(3.64f, 4.36f), reflectance(3.12f, 4.42f), reflectance(1.92f, 4.15f)),
        0.03f));
    CHECK(tungsten.isApprox(
        Color3f(reflectance(3.70f, 2.94f), reflectance(3.50f, 2.73f), reflectance(3.31f, 2.53f)),
        0.03f));
    CHECK(nickel.isApprox(
        Color3f(reflectance(2.02f, 3.82f), reflectance(1.78f, 3.26f), reflectance(1.63f, 2.66f)),
        0.03f));
    CHECK(nickel.r() > nickel.b());
    CHECK_THAT(errorOf([] {
                   Color3f e, kk;
                   lookupConductor("Chromium", e, kk);
               }),
               Catch::Contains("unknown metal 'Chromium'") && Catch::Contains("W"));
}
