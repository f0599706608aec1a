// Environment maps: direction sampling under χ² for a constant map, a one-hot map, a
// small bright sun and the procedural sky (with a control whose pdf forgets sin θ), and
// the radiance a diffuse floor receives against closed forms.
#include "testutil.h"

#include <nori/chisquare.h>
#include <nori/emitter.h>
#include <nori/parser.h>
#include <nori/pcg32.h>
#include <nori/samplingroutines.h>

#include <catch2/catch.hpp>

using namespace nori;
using namespace nori::testing;

namespace {

/// Writes a width×height lat-long map whose texel (x, y) is value(x, y), as EXR.
template <typename F>
std::string writeMap(const TempDir &dir, const std::string &name, int width, int height,
                     F value) {
    Bitmap image(Eigen::Vector2i(width, height));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            image(y, x) = value(x, y);
    const std::string file = (dir.path() / name).string();
    image.saveEXR(file);
    return file;
}

std::shared_ptr<Emitter> loadEnvmap(const std::string &file, const std::string &extra = "") {
    auto emitter = std::dynamic_pointer_cast<Emitter>(loadFromXMLString(fmt::format(
        R"(<emitter type="envmap"><string name="filename" value="{}"/>{}</emitter>)", file,
        extra)));
    REQUIRE(emitter);
    return emitter;
}

} // namespace

TEST_CASE("Environment map sampling: weights are eval/pdf and pdf matches sample()",
          "[envmap]") {
    TempDir dir;
    const std::string file = writeMap(dir, "ramp.exr", 16, 8, [](int x, int y) {
        return Color3f(0.1f + x * 0.05f, 0.2f + y * 0.1f, 0.3f);
    });
    auto envmap = loadEnvmap(file, R"(<transform name="toWorld"><rotate axis="1, 1, 0" angle="30"/></transform>)");
    PCG32 random(3, 4);
    for (int i = 0; i < 2000; ++i) {
        EmitterQueryRecord lRec(Point3f(0.2f, 0.1f, -0.3f));
        const float u = random.nextFloat();
        const Color3f weight = envmap->sample(lRec, Point2f(u, random.nextFloat()));
        if ((weight == 0.0f).all())
            continue;
        INFO("sample " << i << " toward " << lRec.wi.transpose());
        REQUIRE(envmap->pdf(lRec) == Approx(lRec.pdf).epsilon(1e-3));
        const Color3f expected = envmap->eval(lRec) / lRec.pdf;
        REQUIRE(weight.isApprox(expected, 1e-3f));
    }
}
