// nori-make-meadow DIR [--flat]: writes the meadow example (scenes/meadow): a curved,
// tapering grass blade (blade.obj, front and back faces so both sides shade) and
// meadow.xml, 102,400 blades as three levels of instances: a clump of 100 blades
// (three shades of green) in 0.5 m × 0.5 m, a patch of 4 × 4 clumps, a meadow of 8 × 8
// patches (16 m × 16 m), each placement with a random rotation about the vertical.
// With --flat it also writes meadow_flat.xml: the same blades as 102,400 instances of
// one level (each transform composed), as a course exporter writes particle systems.
#include "app/cli.h"
#include <nori/pcg32.h>
#include <nori/strutil.h>
#include <nori/transform.h>

#include <filesystem>
#include <fstream>
#include <iostream>

using namespace nori;

namespace {

constexpr int kSegments = 6;
constexpr int kBladesPerClump = 100, kClumpsPerSide = 4, kPatchesPerSide = 8;
constexpr float kClumpSize = 0.5f;
const char *kShades[3] = {"0.10, 0.32, 0.05", "0.16, 0.40, 0.07", "0.22, 0.42, 0.10"};

/// A blade 1 high: width 0.03 at the root tapering to a point, bending over along +z
/// (z = 0.3·h²). The back face is offset by 0.002 along −z with opposite normals.
void writeBlade(const std::string &filename) {
    std::ofstream out(filename);
    if (!out)
        throw NoriException("cannot write '{}'", filename);
    out << "# A grass blade, written by nori-make-meadow.\n";
    for (int side = 0; side < 2; ++side) {
        for (int k = 0; k <= kSegments; ++k) {
            const float h = static_cast<float>(k) / kSegments;
            const float width = k == kSegments ? 0.0005f : 0.015f * (1.0f - h) + 0.001f;
            const float z = 0.3f * h * h - (side == 1 ? 0.002f : 0.0f);
            // Normal: perpendicular to the blade's tangent (0, 1, 0.6 h) within the yz-plane.
            Vector3f normal = Vector3f(0.0f, -0.6f * h, 1.0f).normalized();
            if (side == 1)
                normal = -normal;
            for (int edge = 0; edge < 2; ++edge) {
                const float x = edge == 0 ? -width : width;
                out << fmt::format(
                    "v {:.5f} {:.5f} {:.5f}\nvt {:.4f} {:.4f}\nvn {:.5f} {:.5f} {:.5f}\n", x, h, z,
                    static_cast<float>(edge), h, normal.x(), normal.y(), normal.z());
            }
        }
    }
    const int perSide = 2 * (kSegments + 1);
    for (int side = 0; side < 2; ++side)
        for (int k = 0; k < kSegments; ++k) {
            const int a = 1 + side * perSide + 2 * k, b = a + 1, c = a + 2, d = a + 3;
            auto face = [&](int i, int j, int l) {
                out << fmt::format("f {0}/{0}/{0} {1}/{1}/{1} {2}/{2}/{2}\n", i, j, l);
            };
            // Front faces wind counter-clockwise seen from +z; the back ones the other way.
            if (side == 0) {
                face(a, b, d);
                face(a, d, c);
            } else {
                face(a, d, b);
                face(a, c, d);
            }
        }
}

std::string matrixXml(const Transform &transform) {
    const Eigen::Matrix4f &m = transform.getMatrix();
    std::string values;
    for (int row = 0; row < 4; ++row)
        for (int column = 0; column < 4; ++column)
            values += fmt::format("{}{:.6g}", values.empty() ? "" : " ", m(row, column));
    return fmt::format(R"(<transform name="toWorld"><matrix value="{}"/></transform>)", values);
}

struct BladePlacement {
    int shade;
    Transform toClump;
};

/// The blades of the clump: a random spot, heading, height (0.2 to 0.4 m) and lean.
std::vector<BladePlacement> makeClump(PCG32 &random) {
    std::vector<BladePlacement> blades;
    for (int i = 0; i < kBladesPerClump; ++i) {
        // One draw per statement: the order in which a call's arguments, or an operator's
        // operands, are evaluated is unspecified (GCC and clang wrote different meadows).
        const float height = 0.2f + 0.2f * random.nextFloat();
        const float x = kClumpSize * (random.nextFloat() - 0.5f);
        const float z = kClumpSize * (random.nextFloat() - 0.5f);
        const float heading = 360.0f * random.nextFloat();
        const float lean = 20.0f * (random.nextFloat() - 0.5f);
        const int kind = static_cast<int>(random.nextUInt() % 3);
        const Transform toClump = Transform::translate(Vector3f(x, 0.0f, z)) *
                                  Transform::rotate(Vector3f(0, 1, 0), heading) *
                                  Transform::rotate(Vector3f(1, 0, 0), lean) *
                                  Transform::scale(Vector3f(height, height, height));
        blades.push_back({kind, toClump});
    }
    return blades;
}

/// A placement at cell (i, j) of an n × n grid of cells `size` wide, centred on the
/// origin, turned by a random multiple of 90° about the vertical.
Transform cellPlacement(int i, int j, int n, float size, PCG32 &random) {
    const float offset = 0.5f * size * static_cast<float>(n - 1);
    return Transform::translate(Vector3f(size * i - offset, 0.0f, size * j - offset)) *
           Transform::rotate(Vector3f(0, 1, 0), 90.0f * static_cast<float>(random.nextUInt() % 4));
}

const char *kSceneHead = R"(<?xml version="1.0" encoding="utf-8"?>
<!-- A meadow of 102,400 instanced grass blades under the procedural sky, written by
     nori-make-meadow (tools/make_meadow.cpp). {}
     nori scenes/meadow/meadow.xml
     -D lightsampler=power picks lights by power alone, not by the light tree. -->
<scene>
    <default name="integrator" value="path_mis"/>
    <default name="spp" value="16"/>
    <default name="width" value="480"/>
    <default name="height" value="270"/>
    <default name="lightsampler" value="bvh"/>
    <string name="lightSampler" value="$lightsampler"/>

    <integrator type="$integrator"/>
    <sampler type="independent"><integer name="sampleCount" value="$spp"/></sampler>
    <camera type="perspective">
        <float name="fov" value="40"/>
        <integer name="width" value="$width"/>
        <integer name="height" value="$height"/>
        <transform name="toWorld"><lookat origin="0.3, 0.75, 7.5" target="0, 0.05, 2" up="0, 1, 0"/></transform>
    </camera>
    <emitter type="envmap">
        <string name="filename" value="../textured/textures/sky.exr"/>
        <float name="scale" value="0.5"/>
    </emitter>
    <mesh type="obj">
        <string name="filename" value="../textured/meshes/floor.obj"/>
        <transform name="toWorld"><scale value="30, 1, 30"/></transform>
        <bsdf type="diffuse"><color name="albedo" value="0.18, 0.13, 0.07"/></bsdf>
    </mesh>
)";

std::string bladeGroups() {
    std::string xml;
    for (int shade = 0; shade < 3; ++shade)
        xml += fmt::format(R"(    <mesh type="shapegroup" id="blade{}">
        <mesh type="obj"><string name="filename" value="blade.obj"/>
            <bsdf type="diffuse"><color name="albedo" value="{}"/></bsdf></mesh>
    </mesh>
)",
                           shade, kShades[shade]);
    return xml;
}

void writeMeadow(const std::string &directory, bool flat) {
    PCG32 random(2026, 11);
    const std::vector<BladePlacement> clump = makeClump(random);
    std::vector<Transform> clumpsInPatch, patchesInMeadow;
    for (int i = 0; i < kClumpsPerSide; ++i)
        for (int j = 0; j < kClumpsPerSide; ++j)
            clumpsInPatch.push_back(cellPlacement(i, j, kClumpsPerSide, kClumpSize, random));
    const float patchSize = kClumpSize * kClumpsPerSide;
    for (int i = 0; i < kPatchesPerSide; ++i)
        for (int j = 0; j < kPatchesPerSide; ++j)
            patchesInMeadow.push_back(cellPlacement(i, j, kPatchesPerSide, patchSize, random));

    std::ofstream nested(directory + "/meadow.xml");
    if (!nested)
        throw NoriException("cannot write '{}/meadow.xml'", directory);
    nested << fmt::format(kSceneHead, "Three levels of instances: 100 blades in a clump, 4 × 4 "
                                      "clumps in a patch, 8 × 8 patches.")
           << bladeGroups() << "    <mesh type=\"shapegroup\" id=\"clump\">\n";
    for (const BladePlacement &blade : clump)
        nested << fmt::format("        <mesh type=\"instance\"><ref id=\"blade{}\"/>{}</mesh>\n",
                              blade.shade, matrixXml(blade.toClump));
    nested << "    </mesh>\n    <mesh type=\"shapegroup\" id=\"patch\">\n";
    for (const Transform &placement : clumpsInPatch)
        nested << fmt::format("        <mesh type=\"instance\"><ref id=\"clump\"/>{}</mesh>\n",
                              matrixXml(placement));
    nested << "    </mesh>\n";
    for (const Transform &placement : patchesInMeadow)
        nested << fmt::format("    <mesh type=\"instance\"><ref id=\"patch\"/>{}</mesh>\n",
                              matrixXml(placement));
    nested << "</scene>\n";

    if (!flat)
        return;
    std::ofstream out(directory + "/meadow_flat.xml");
    if (!out)
        throw NoriException("cannot write '{}/meadow_flat.xml'", directory);
    out << fmt::format(kSceneHead, "One level: every blade is an instance of its own.")
        << bladeGroups();
    for (const Transform &patch : patchesInMeadow)
        for (const Transform &clumpPlacement : clumpsInPatch)
            for (const BladePlacement &blade : clump)
                out << fmt::format("    <mesh type=\"instance\"><ref id=\"blade{}\"/>{}</mesh>\n",
                                   blade.shade, matrixXml(patch * clumpPlacement * blade.toClump));
    out << "</scene>\n";
}

int run(const std::string &directory, bool flat) {
    std::filesystem::create_directories(directory);
    writeBlade(directory + "/blade.obj");
    writeMeadow(directory, flat);
    std::cout << "wrote " << directory << "/blade.obj and meadow.xml"
              << (flat ? " and meadow_flat.xml" : "") << "\n";
    return 0;
}

} // namespace

int main(int argc, char **argv) {
    std::string directory;
    bool flat = false;
    return runCommandLine(
        argc, argv, "nori-make-meadow",
        "Writes the meadow example: DIR/blade.obj and DIR/meadow.xml, 102,400 grass blades in "
        "three levels of instances.",
        [&](CLI::App &app) {
            app.add_option("directory", directory, "where to write")->type_name("DIR")->required();
            app.add_flag("--flat", flat, "also write meadow_flat.xml, one instance per blade");
        },
        [&](const CLI::App &) { return run(directory, flat); });
}
