// nori-make-textures DIR: writes the example scenes' textures (scenes/textured/textures),
// so that every image in the repository is made by the project's own code:
//   bricks.png         256×256 sRGB albedo: running-bond bricks in mortar
//   bricks_normal.png  the matching tangent-space normal map (bevelled brick edges)
//   bricks_height.png  the matching height map (for bump mapping)
//   checker.png        256×256 black-and-white checkerboard of 8×8 cells
//   sky.exr            256×128 lat-long environment (envmap's convention): a blue sky
//                      brightening toward the horizon, a grey ground and a small sun
#include "app/cli.h"
#include <nori/bitmap.h>
#include <nori/vector.h>

#include <filesystem>
#include <iostream>

using namespace nori;

namespace {

constexpr int kSize = 256;
constexpr int kBrickWidth = 64, kBrickHeight = 32, kMortar = 3, kBevel = 6;

/// Where a texel lies in the brick pattern: its brick, and its distance (in texels) to
/// the brick's nearest edge along x and y, signed by the side (negative: in mortar).
struct BrickTexel {
    int row, column;
    float dx, dy; ///< distance to the nearest vertical / horizontal edge
    float sx, sy; ///< −1 or +1: which edge (left/right, bottom/top) is nearest
};

BrickTexel brickAt(int x, int y) {
    BrickTexel b;
    b.row = y / kBrickHeight;
    const int shifted = x + (b.row % 2) * kBrickWidth / 2; // running bond
    b.column = shifted / kBrickWidth;
    const float u = (shifted % kBrickWidth) + 0.5f, v = (y % kBrickHeight) + 0.5f;
    const float left = u - kMortar, right = kBrickWidth - u, bottom = v - kMortar,
                top = kBrickHeight - v;
    b.dx = std::min(left, right);
    b.sx = left < right ? -1.0f : 1.0f;
    b.dy = std::min(bottom, top);
    b.sy = bottom < top ? -1.0f : 1.0f;
    return b;
}

/// A deterministic value in [0, 1) per brick (an integer hash), for colour variation.
float brickHash(int row, int column) {
    uint32_t h = static_cast<uint32_t>(row * 73856093) ^ static_cast<uint32_t>(column * 19349663);
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return (h & 0xffffu) / 65536.0f;
}

/// Height in [0, 1]: 0 in the mortar, rising over the bevel to 1 on the brick's face.
float brickHeight(const BrickTexel &b) {
    const float edge = std::min(b.dx, b.dy);
    return std::clamp(edge / kBevel, 0.0f, 1.0f);
}

void writeTextures(const std::filesystem::path &directory) {
    std::filesystem::create_directories(directory);
    Bitmap albedo(Eigen::Vector2i(kSize, kSize)), normals(Eigen::Vector2i(kSize, kSize)),
        height(Eigen::Vector2i(kSize, kSize)), checker(Eigen::Vector2i(kSize, kSize));
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            // Image rows run top to bottom; the pattern is built bottom-up (v up).
            const int row = kSize - 1 - y;
            const BrickTexel b = brickAt(x, row);
            const bool mortar = b.dx < 0.0f || b.dy < 0.0f;
            const float shade = brickHash(b.row, b.column);
            albedo.coeffRef(y, x) =
                mortar ? Color3f(0.55f, 0.53f, 0.5f)
                       : Color3f(0.45f + 0.2f * shade, 0.16f + 0.06f * shade, 0.1f + 0.04f * shade);
            height.coeffRef(y, x) = Color3f(brickHeight(b));
            // Normal of the bevel: tilted toward the nearest edge where the height ramps.
            Vector3f n(0.0f, 0.0f, 1.0f);
            if (!mortar && b.dx < kBevel && b.dx <= b.dy)
                n = Vector3f(b.sx, 0.0f, 1.0f);
            else if (!mortar && b.dy < kBevel)
                n = Vector3f(0.0f, b.sy, 1.0f);
            n.normalize();
            normals.coeffRef(y, x) =
                Color3f(0.5f * n.x() + 0.5f, 0.5f * n.y() + 0.5f, 0.5f * n.z() + 0.5f);
            checker.coeffRef(y, x) = Color3f(((x / 32 + row / 32) % 2) ? 0.05f : 0.8f);
        }
    // savePNG encodes to sRGB: write data maps through the inverse so they store values.
    auto asData = [](Bitmap image) {
        for (Color3f &pixel : image.reshaped())
            pixel = pixel.toLinearRGB();
        return image;
    };
    albedo.savePNG((directory / "bricks.png").string());
    checker.savePNG((directory / "checker.png").string());
    asData(normals).savePNG((directory / "bricks_normal.png").string());
    asData(height).savePNG((directory / "bricks_height.png").string());
}

/// A procedural sky in envmap's lat-long convention (v = θ/π from +y, u = φ/2π): sky
/// radiance rising from the zenith to the horizon, a dim ground, and a sun 4° across at
/// 35° elevation whose radiance makes it give about three times the sky's irradiance.
void writeSky(const std::filesystem::path &file) {
    constexpr int width = 256, height = 128;
    const float sunTheta = degToRad(90.0f - 35.0f), sunPhi = degToRad(60.0f);
    const Vector3f sun(std::sin(sunPhi) * std::sin(sunTheta), std::cos(sunTheta),
                       -std::cos(sunPhi) * std::sin(sunTheta));
    const float sunCos = std::cos(degToRad(2.0f));
    Bitmap sky(Eigen::Vector2i(width, height));
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const float theta = (y + 0.5f) * kPi / height, phi = (x + 0.5f) * 2.0f * kPi / width;
            const Vector3f d(std::sin(phi) * std::sin(theta), std::cos(theta),
                             -std::cos(phi) * std::sin(theta));
            Color3f value;
            if (d.y() < 0.0f) {
                value = Color3f(0.12f, 0.1f, 0.08f); // ground
            } else {
                const float toHorizon = 1.0f - d.y(); // 0 at the zenith, 1 at the horizon
                value = Color3f(0.25f, 0.45f, 0.95f) * (1.0f - toHorizon) +
                        Color3f(0.85f, 0.9f, 1.0f) * toHorizon;
            }
            if (d.dot(sun) > sunCos)
                value = Color3f(2600.0f, 2400.0f, 2000.0f);
            sky(y, x) = value;
        }
    sky.saveEXR(file.string());
}

} // namespace

int main(int argc, char **argv) {
    std::string directory;
    return runCommandLine(
        argc, argv, "nori-make-textures",
        "Writes the example scenes' textures (scenes/textured/textures).",
        [&](CLI::App &app) {
            app.add_option("directory", directory, "where to write")
                ->type_name("DIRECTORY")
                ->required();
        },
        [&](const CLI::App &) {
            writeTextures(directory);
            writeSky(std::filesystem::path(directory) / "sky.exr");
            return 0;
        },
        2);
}
