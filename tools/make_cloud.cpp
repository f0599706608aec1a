// nori-make-cloud DIR [RESOLUTION]: writes the procedural cloud of the media example
// (scenes/media) as DIR/cloud.vol (Mitsuba's grid format) and DIR/cloud.nvdb (NanoVDB),
// the same RESOLUTION³ density grid (default 40) over the object-space cube [−1, 1]³:
// a union of soft spheres with a flattened base, eroded by three octaves of value noise,
// densities in [0, 1]. The output depends on nothing but RESOLUTION.
#include "app/cli.h"
#include <nori/hash.h>
#include <nori/volumegrid.h>

#include <filesystem>
#include <iostream>

using namespace nori;

namespace {

/// Smooth value noise: hashed lattice values in [0, 1), interpolated with the smoothstep
/// weights 3t² − 2t³ (Perlin 1985's "noise" without gradients).
float valueNoise(const Vector3f &p, int octave) {
    const Vector3f floorP(p.array().floor().matrix());
    const Vector3f f = p - floorP;
    const Vector3f w = f.cwiseProduct(f).cwiseProduct(Vector3f::Constant(3.0f) - 2.0f * f);
    float result = 0.0f;
    for (int corner = 0; corner < 8; ++corner) {
        const Vector3i offset(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
        const Vector3i cell = floorP.cast<int>() + offset;
        const uint64_t hash = hashValues(uint32_t(cell.x()), uint32_t(cell.y()), uint32_t(cell.z()),
                                         uint32_t(octave));
        const float value = float(hash >> 40) / float(uint64_t(1) << 24);
        float weight = 1.0f;
        for (int axis = 0; axis < 3; ++axis)
            weight *= offset[axis] ? w[axis] : 1.0f - w[axis];
        result += weight * value;
    }
    return result;
}

float cloudDensity(const Vector3f &p) {
    struct Blob {
        Vector3f centre;
        float radius;
    };
    static const Blob blobs[] = {{{0.0f, -0.15f, 0.0f}, 0.55f},
                                 {{-0.42f, -0.25f, 0.1f}, 0.4f},
                                 {{0.45f, -0.2f, -0.05f}, 0.42f},
                                 {{0.1f, 0.22f, 0.05f}, 0.4f},
                                 {{-0.18f, 0.12f, -0.25f}, 0.35f}};
    float shape = -1.0f;
    for (const Blob &blob : blobs)
        shape = std::max(shape, 1.0f - (p - blob.centre).norm() / blob.radius);
    float noise = 0.0f, amplitude = 0.5f;
    for (int octave = 0; octave < 3; ++octave, amplitude *= 0.5f)
        noise += amplitude *
                 valueNoise(p * (4.0f * float(1 << octave)) + Vector3f(7.0f, 3.0f, 5.0f), octave);
    // A flat base: the cloud thins out over y ∈ [−0.55, −0.4].
    const float base = std::clamp((p.y() + 0.55f) / 0.15f, 0.0f, 1.0f);
    return std::clamp((shape + 0.45f * (noise - 0.45f)) * 3.0f, 0.0f, 1.0f) * base;
}

int run(const std::string &directory, int resolution) {
    if (resolution < 2 || resolution > 512)
        throw NoriException("RESOLUTION must lie in [2, 512], got {}", resolution);
    std::vector<float> values(size_t(resolution) * resolution * resolution);
    size_t index = 0;
    for (int z = 0; z < resolution; ++z)
        for (int y = 0; y < resolution; ++y)
            for (int x = 0; x < resolution; ++x) {
                // The voxel centre in [−1, 1]³.
                const Vector3f p =
                    (Vector3f(float(x), float(y), float(z)) + Vector3f::Constant(0.5f)) *
                        (2.0f / float(resolution)) -
                    Vector3f::Constant(1.0f);
                values[index++] = cloudDensity(p);
            }
    Eigen::Matrix4f unitToObject = Eigen::Matrix4f::Identity();
    unitToObject.topLeftCorner<3, 3>() *= 2.0f;
    unitToObject.topRightCorner<3, 1>() = Eigen::Vector3f::Constant(-1.0f);
    const VolumeGrid grid(Vector3i::Constant(resolution), 1, std::move(values),
                          Transform(unitToObject), "cloud");
    std::filesystem::create_directories(directory);
    grid.writeVol(directory + "/cloud.vol");
    grid.writeNanoVDB(directory + "/cloud.nvdb", "density");
    std::cout << fmt::format("wrote {0}/cloud.vol and {0}/cloud.nvdb ({1}x{1}x{1} voxels)\n",
                             directory, resolution);
    return 0;
}

} // namespace

int main(int argc, char **argv) {
    std::string directory;
    int resolution = 40;
    return runCommandLine(
        argc, argv, "nori-make-cloud",
        "Writes the procedural cloud of the media example as DIR/cloud.vol and DIR/cloud.nvdb.",
        [&](CLI::App &app) {
            app.add_option("directory", directory, "where to write")->type_name("DIR")->required();
            app.add_option("resolution", resolution,
                           "voxels along each axis, 2 to 512 (default 40)")
                ->type_name("RESOLUTION");
        },
        [&](const CLI::App &) { return run(directory, resolution); });
}
