// nori-make-ply-scene DIR [--meshes N] [--triangles T] [--instances I] [--textures K]
//                    [--texture-size S]: writes a pbrt-v4 scene of the kind real scenes
// are (pbrt-v4's crown: 3.5 M triangles in 786 PLY files), for the loading and memory
// figures of scripts/bench_pbrt.sh:
//   DIR/meshes/blob-NNNN.ply  N binary PLY files of T triangles in all, each a bumpy
//                             sphere of its own bumps, with vertex normals and uvs;
//   DIR/textures/tex-NNNN.png K PNG images of S×S pixels (default 512), each stripes of
//                             its own colours and frequency, written only with --textures;
//   DIR/plys.pbrt             the N meshes side by side on a grid, each placed once;
//   DIR/instances.pbrt        I instances of the N meshes (ObjectBegin / ObjectInstance),
//                             written only with --instances.
// Both scenes: a diffuse material, grey or (with --textures) mesh i textured by image
// i mod K, a distant light and an infinite light, a camera looking down at the grid,
// pbrt-v4's `path` integrator at 1 spp, 640×480.
#include "app/cli.h"
#include <nori/bitmap.h>
#include <nori/meshdata.h>
#include <nori/parallel.h>
#include <nori/pcg32.h>
#include <nori/plyfile.h>
#include <nori/strutil.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <utility>

using namespace nori;
namespace fs = std::filesystem;

namespace {

/// A sphere of radius ~0.4 with bumps r = 0.4·(1 + a·sin(fθ·θ)·sin(fφ·φ)), the amplitude
/// and frequencies drawn from `seed`: a latitude–longitude grid of `rings` rings and
/// 2·rings columns, the seam's vertices repeated so that u runs from 0 to 1. Normals are
/// the unit sphere's (smooth shading); uv are (φ/2π, θ/π).
MeshData bumpySphere(int rings, uint64_t seed) {
    PCG32 generator(seed, 7);
    const float amplitude = 0.02f + 0.08f * generator.nextFloat();
    const float thetaFrequency = std::floor(4.0f + 12.0f * generator.nextFloat());
    const float phiFrequency = std::floor(4.0f + 12.0f * generator.nextFloat());
    const int columns = 2 * rings;
    MeshData mesh;
    for (int ring = 0; ring <= rings; ++ring)
        for (int column = 0; column <= columns; ++column) {
            const float theta = kPi * static_cast<float>(ring) / static_cast<float>(rings);
            const float phi = 2.0f * kPi * static_cast<float>(column) / static_cast<float>(columns);
            const Vector3f direction(std::sin(theta) * std::cos(phi), std::cos(theta),
                                     std::sin(theta) * std::sin(phi));
            const float r = 0.4f * (1.0f + amplitude * std::sin(thetaFrequency * theta) *
                                               std::sin(phiFrequency * phi));
            mesh.positions.emplace_back(r * direction);
            mesh.normals.emplace_back(direction);
            mesh.texCoords.emplace_back(static_cast<float>(column) / static_cast<float>(columns),
                                        static_cast<float>(ring) / static_cast<float>(rings));
        }
    auto index = [columns](int ring, int column) { return ring * (columns + 1) + column; };
    for (int ring = 0; ring < rings; ++ring)
        for (int column = 0; column < columns; ++column) {
            // The poles' rows hold one triangle a column, the others two.
            if (ring > 0)
                mesh.triangles.emplace_back(index(ring, column), index(ring, column + 1),
                                            index(ring + 1, column + 1));
            if (ring + 1 < rings)
                mesh.triangles.emplace_back(index(ring, column), index(ring + 1, column + 1),
                                            index(ring + 1, column));
        }
    return mesh;
}

/// The header of both scenes: camera above the grid of `side` × `side` cells looking
/// down at its centre, film, sampler, integrator, lights, material.
/// Texture `index`: diagonal stripes between two colours of its own, `size` pixels square.
Bitmap stripes(int size, uint64_t index) {
    PCG32 generator(index, 13);
    const Color3f a(generator.nextFloat(), generator.nextFloat(), generator.nextFloat());
    const Color3f b(generator.nextFloat(), generator.nextFloat(), generator.nextFloat());
    const float frequency = 2.0f * kPi * std::floor(2.0f + 14.0f * generator.nextFloat());
    Bitmap image(Eigen::Vector2i(size, size));
    for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
            const float t = 0.5f + 0.5f * std::sin(frequency * static_cast<float>(x + y) /
                                                   static_cast<float>(size));
            image(y, x) = a * t + b * (1.0f - t);
        }
    return image;
}

/// The material of mesh `mesh`: grey, or its texture's name as the reflectance.
std::string material(size_t mesh, size_t textures) {
    if (textures == 0)
        return "";
    return fmt::format("  Material \"diffuse\" \"texture reflectance\" \"tex{}\"\n",
                       mesh % textures);
}

std::string sceneHeader(int side, const std::string &film, size_t textures) {
    const float extent = static_cast<float>(side);
    std::string header =
        fmt::format("# Written by nori-make-ply-scene.\n"
                    "LookAt {0} {1} {2}  {0} 0 {0}  0 1 0\n"
                    "Camera \"perspective\" \"float fov\" [45]\n"
                    "Film \"rgb\" \"string filename\" [\"{3}\"]\n"
                    "    \"integer xresolution\" [640] \"integer yresolution\" [480]\n"
                    "Sampler \"zsobol\" \"integer pixelsamples\" [1]\n"
                    "Integrator \"path\" \"integer maxdepth\" [5]\n"
                    "WorldBegin\n"
                    "LightSource \"distant\" \"point3 from\" [1 4 2] \"point3 to\" [0 0 0]\n"
                    "    \"rgb L\" [2 2 1.8]\n"
                    "LightSource \"infinite\" \"rgb L\" [0.3 0.35 0.45]\n"
                    "Material \"diffuse\" \"rgb reflectance\" [0.6 0.6 0.6]\n",
                    0.5f * extent, 1.1f * extent, -0.35f * extent, film);
    for (size_t i = 0; i < textures; ++i)
        header += fmt::format("Texture \"tex{0}\" \"spectrum\" \"imagemap\" \"string filename\" "
                              "[\"textures/tex-{0:04}.png\"]\n",
                              i);
    return header;
}

/// The centre (x, z) of cell `i` of a grid `side` cells wide, cells of size 1.
std::pair<float, float> cellCentre(size_t i, size_t side) {
    const size_t row = i / side, column = i % side;
    return {static_cast<float>(column) + 0.5f, static_cast<float>(row) + 0.5f};
}

struct Arguments {
    std::string directory;
    int meshes = 256;
    size_t triangles = 2000000;
    size_t instances = 0;
    size_t textures = 0;
    int textureSize = 512;
};

int run(const Arguments &arguments) {
    if (arguments.meshes <= 0 || arguments.triangles < 8 * static_cast<size_t>(arguments.meshes))
        throw NoriException("--meshes must be positive and --triangles at least 8 a mesh");
    if (arguments.textureSize < 1 || arguments.textureSize > 16384)
        throw NoriException("--texture-size must be in [1, 16384], got {}", arguments.textureSize);
    const fs::path directory(arguments.directory);
    fs::create_directories(directory / "meshes");
    // 2·C·(R − 1) triangles a sphere with C = 2R columns: R from the share of each mesh.
    const double perMesh = static_cast<double>(arguments.triangles) / arguments.meshes;
    const int rings =
        std::max(2, static_cast<int>(std::lround(0.5 + 0.5 * std::sqrt(1.0 + perMesh))));
    std::vector<std::string> names(static_cast<size_t>(arguments.meshes));
    std::vector<size_t> counts(names.size());
    parallelForEach(size_t(0), names.size(), [&](size_t i) {
        names[i] = fmt::format("meshes/blob-{:04}.ply", i);
        const MeshData mesh = bumpySphere(rings, i);
        counts[i] = mesh.triangles.size();
        writePLY((directory / names[i]).string(), mesh);
    });
    size_t total = 0;
    for (size_t count : counts)
        total += count;
    if (arguments.textures > 0) {
        fs::create_directories(directory / "textures");
        parallelForEach(size_t(0), arguments.textures, [&](size_t i) {
            stripes(arguments.textureSize, i)
                .savePNG((directory / fmt::format("textures/tex-{:04}.png", i)).string());
        });
    }

    // One mesh a cell of a square grid, each placed once.
    const int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(names.size()))));
    {
        std::ofstream out(directory / "plys.pbrt");
        out << sceneHeader(side, "plys.exr", arguments.textures);
        for (size_t i = 0; i < names.size(); ++i) {
            const auto [x, z] = cellCentre(i, static_cast<size_t>(side));
            out << fmt::format("AttributeBegin\n  Translate {} 0.4 {}\n{}"
                               "  Shape \"plymesh\" \"string filename\" [\"{}\"]\nAttributeEnd\n",
                               x, z, material(i, arguments.textures), names[i]);
        }
        if (!out)
            throw NoriException("cannot write '{}'", (directory / "plys.pbrt").string());
    }
    std::cout << fmt::format("meshes {}\ntriangles {}\ntextures {}\n", names.size(), total,
                             arguments.textures);
    if (arguments.instances == 0)
        return 0;

    // The meshes as objects, instanced on a finer grid, each with its own rotation.
    const int instanceSide =
        static_cast<int>(std::ceil(std::sqrt(static_cast<double>(arguments.instances))));
    const float cell = static_cast<float>(side) / static_cast<float>(instanceSide);
    std::ofstream out(directory / "instances.pbrt");
    out << sceneHeader(side, "instances.exr", arguments.textures);
    for (size_t i = 0; i < names.size(); ++i)
        out << fmt::format("ObjectBegin \"blob{}\"\n{}  Shape \"plymesh\" \"string filename\" "
                           "[\"{}\"]\nObjectEnd\n",
                           i, material(i, arguments.textures), names[i]);
    PCG32 generator(arguments.instances, 11);
    for (size_t i = 0; i < arguments.instances; ++i) {
        const float scale = cell * (0.6f + 0.4f * generator.nextFloat());
        const float angle = 360.0f * generator.nextFloat();
        const auto [x, z] = cellCentre(i, static_cast<size_t>(instanceSide));
        out << fmt::format("AttributeBegin\n  Translate {} {} {}\n  Rotate {} 0 1 0\n"
                           "  Scale {} {} {}\n  ObjectInstance \"blob{}\"\nAttributeEnd\n",
                           cell * x, 0.4f * scale, cell * z, angle, scale, scale, scale,
                           i % names.size());
    }
    if (!out)
        throw NoriException("cannot write '{}'", (directory / "instances.pbrt").string());
    std::cout << fmt::format("instances {}\ninstanced_triangles {}\n", arguments.instances,
                             arguments.instances * (total / names.size()));
    return 0;
}

} // namespace

int main(int argc, char **argv) {
    Arguments arguments;
    return runCommandLine(
        argc, argv, "nori-make-ply-scene",
        "Writes a pbrt-v4 scene of many binary PLY meshes (DIR/plys.pbrt), and with --instances "
        "one that instances them (DIR/instances.pbrt), with --textures textured by PNG images, "
        "for loading and memory figures.",
        [&](CLI::App &app) {
            app.add_option("directory", arguments.directory, "where to write the scene")
                ->type_name("DIR")
                ->required();
            app.add_option("--meshes", arguments.meshes, "PLY files (default 256)")->type_name("N");
            app.add_option("--triangles", arguments.triangles,
                           "triangles of all files together (default 2000000)")
                ->type_name("T");
            app.add_option("--instances", arguments.instances,
                           "also write instances.pbrt with I instances (default: not)")
                ->type_name("I");
            app.add_option("--textures", arguments.textures,
                           "PNG textures, mesh i textured by image i mod K (default: none)")
                ->type_name("K");
            app.add_option("--texture-size", arguments.textureSize,
                           "the textures' width and height in pixels (default 512)")
                ->type_name("S");
        },
        [&](const CLI::App &) { return run(arguments); });
}
