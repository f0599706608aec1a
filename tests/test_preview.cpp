// The preview server's data, through a real HTTP client on loopback: the float image is
// the published one bit for bit, the status follows the render, the stop flag needs its
// header. (tests/preview/test_preview.py drives the page itself in a browser.)
#include "app/preview.h"

#include <catch2/catch.hpp>
#include <httplib.h>

#include <cstring>

using namespace nori;
using Catch::Matchers::Contains;

namespace {

/// A 3×2 image: the beauty holds a ramp with one NaN, "depth" one channel.
LayeredImage testImage() {
    Bitmap beauty(Vector2i(3, 2));
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x)
            beauty(y, x) = Color3f(static_cast<float>(x), static_cast<float>(y), 0.25f * x * y);
    beauty(1, 2).x() = std::numeric_limits<float>::quiet_NaN();
    LayeredImage image(Vector2i(3, 2));
    image.addLayer("", {"R", "G", "B"}, beauty);
    LayeredImage::Channel depth(2, 3);
    depth << 1.5f, 2.5f, 3.5f, 4.5f, 5.5f, 6.5f;
    image.addChannel("depth.Z", depth);
    return image;
}

std::vector<float> floatsOf(const std::string &body) {
    std::vector<float> values(body.size() / sizeof(float));
    std::memcpy(values.data(), body.data(), values.size() * sizeof(float));
    return values;
}

} // namespace

TEST_CASE("The preview serves the published image bit for bit and the render's status",
          "[preview]") {
    std::atomic<bool> stop{false};
    PreviewServer server(0, "scene \"one\".xml", &stop);
    REQUIRE(server.port() > 0);
    httplib::Client client("127.0.0.1", server.port());

    auto status = client.Get("/status");
    REQUIRE(status);
    CHECK(status->status == 200);
    CHECK_THAT(status->body, Contains("\"title\":\"scene \\\"one\\\".xml\"") &&
                                 Contains("\"state\":\"loading\"") && Contains("\"frame\":0"));
    CHECK(client.Get("/image?layer=")->status == 404); // nothing published yet

    server.beginRender(64, 0.0);
    PassReport report;
    report.pass = 3;
    report.samplesPerPixel = 4;
    report.targetSamplesPerPixel = 64;
    report.seconds = 2.0;
    server.publishPass(testImage(), report);
    status = client.Get("/status");
    CHECK_THAT(status->body, Contains("\"state\":\"rendering\"") && Contains("\"frame\":1") &&
                                 Contains("\"pass\":3") && Contains("\"spp\":4") &&
                                 Contains("\"targetSpp\":64") && Contains("\"width\":3") &&
                                 Contains("{\"name\":\"\",\"channels\":3}") &&
                                 Contains("{\"name\":\"depth\",\"channels\":1}"));

    auto beauty = client.Get("/image?layer=");
    REQUIRE(beauty);
    CHECK(beauty->get_header_value("X-Width") == "3");
    CHECK(beauty->get_header_value("X-Height") == "2");
    CHECK(beauty->get_header_value("X-Channels") == "3");
    CHECK(beauty->get_header_value("X-Frame") == "1");
    const std::vector<float> rgb = floatsOf(beauty->body);
    REQUIRE(rgb.size() == 18);
    const Bitmap expected = testImage().layer("");
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 3; ++x)
            for (int c = 0; c < 3; ++c) {
                const float value = rgb[(y * 3 + x) * 3 + c];
                if (x == 2 && y == 1 && c == 0)
                    CHECK(std::isnan(value)); // NaN reaches the page, which shows it black
                else
                    CHECK(value == expected(y, x)[c]);
            }
    const std::vector<float> depth = floatsOf(client.Get("/image?layer=depth")->body);
    CHECK(depth == std::vector<float>{1.5f, 2.5f, 3.5f, 4.5f, 5.5f, 6.5f});

    // /stop needs its header; with it, the flag is set.
    CHECK(client.Post("/stop", "", "text/plain")->status == 403);
    CHECK_FALSE(stop.load());
    const httplib::Headers headers{{"X-Nori-Action", "stop"}};
    CHECK(client.Post("/stop", headers, "", "text/plain")->status == 204);
    CHECK(stop.load());

    server.finishRender(testImage(), true, 3.0, 8);
    status = client.Get("/status");
    CHECK_THAT(status->body, Contains("\"state\":\"stopped\"") && Contains("\"frame\":2") &&
                                 Contains("\"spp\":8") && Contains("\"eta\":0.000"));
    CHECK(client.Get("/nothing")->status == 404);
}

TEST_CASE("Two previews cannot share a port", "[preview]") {
    PreviewServer first(0, "a.xml", nullptr);
    try {
        PreviewServer second(first.port(), "b.xml", nullptr);
        FAIL("the second server bound a busy port");
    } catch (const NoriException &error) {
        CHECK_THAT(error.what(), Contains(fmt::format("127.0.0.1:{}", first.port())));
    }
}
