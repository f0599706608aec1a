// The pbrt-v4 importer's mapping (pbrtimport.h): what each pbrt-v4 entity becomes in our
// XML, its errors and warnings, and `nori scene.pbrt` / `nori convert` giving one image.
#include <nori/imagefile.h>
#include <nori/mesh.h>
#include <nori/pbrtimport.h>

#include "testutil.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>

using namespace nori;
using namespace nori::testing;
using Catch::Contains;
namespace fs = std::filesystem;

namespace {

constexpr double kImportTestPi = 3.14159265358979323846;

const char *kImportTestHeader = R"(
LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective" "float fov" [40]
Film "rgb" "integer xresolution" [200] "integer yresolution" [100]
Sampler "independent" "integer pixelsamples" [4]
WorldBegin
)";

pbrt::Conversion importPbrt(const std::string &body,
                            const std::string &header = kImportTestHeader) {
    const pbrt::Scene scene = pbrt::readSceneString(header + body, "test.pbrt");
    pbrt::ConvertOptions options;
    return pbrt::convertScene(scene, options);
}

std::string importError(const std::string &body) {
    return errorOf([&] { importPbrt(body); });
}

/// The number after `name="NAME" value="` in the XML.
double importedNumber(const std::string &xml, const std::string &name) {
    const std::string key = "name=\"" + name + "\" value=\"";
    const size_t at = xml.find(key);
    REQUIRE(at != std::string::npos);
    return std::stod(xml.substr(at + key.size()));
}

} // namespace

TEST_CASE("pbrt-v4's fov spans the shorter image axis", "[pbrt][import]") {
    // 200 × 100: fov is vertical, ours horizontal: 2·atan(2·tan 20°).
    const double wide = importedNumber(importPbrt("").xml, "fov");
    CHECK(wide == Approx(2.0 * std::atan(2.0 * std::tan(20.0 * kImportTestPi / 180.0)) * 180.0 /
                         kImportTestPi)
                      .epsilon(1e-6));
    // 100 × 200: fov is horizontal already.
    const std::string tall = R"(
LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective" "float fov" [40]
Film "rgb" "integer xresolution" [100] "integer yresolution" [200]
WorldBegin
)";
    CHECK(importedNumber(importPbrt("", tall).xml, "fov") == Approx(40.0).epsilon(1e-6));
    CHECK_THAT(importPbrt("").xml, Contains("\"eth\"") && Contains("sampleBorder"));
}

TEST_CASE("pbrt-v4's surfaces reflect on both sides", "[pbrt][import]") {
    const std::string xml = importPbrt(R"(
Material "diffuse" "rgb reflectance" [0.2 0.3 0.4]
Shape "sphere"
Material "conductor" "float roughness" [0.3]
Shape "sphere"
Material "dielectric"
Shape "sphere"
)")
                                .xml;
    // diffuse and conductor are wrapped, the dielectric transmits and is two-sided as it is.
    size_t wrappers = 0;
    for (size_t at = xml.find("type=\"twosided\""); at != std::string::npos;
         at = xml.find("type=\"twosided\"", at + 1))
        ++wrappers;
    CHECK(wrappers == 2);
    CHECK_THAT(xml, Contains("type=\"roughconductor\"") && Contains("type=\"dielectric\""));
    // pbrt-v4's roughness 0.3 is α = √0.3; indices relative to vacuum.
    CHECK(importedNumber(xml, "alpha") == Approx(std::sqrt(0.3)).epsilon(1e-6));
    CHECK(importedNumber(xml, "extIOR") == 1.0);
    // The scene loads through our XML.
    CHECK(loadScene(xml)->getShapes().size() == 3);
}

TEST_CASE("ReverseOrientation and mirroring transforms turn meshes as pbrt-v4 does",
          "[pbrt][import]") {
    const std::string triangle =
        "Shape \"trianglemesh\" \"point3 P\" [0 0 0  1 0 0  0 1 0] \"integer indices\" [0 1 2]\n";
    CHECK_THAT(importPbrt(triangle).xml, Contains("0 1 2") && !Contains("flipNormals"));
    CHECK_THAT(importPbrt("ReverseOrientation\n" + triangle).xml, Contains("flipNormals"));
    // A mirror image turns the winding back (pbrt-v4's transformSwapsHandedness).
    CHECK_THAT(importPbrt("Scale -1 1 1\n" + triangle).xml, Contains("0 2 1"));
}

TEST_CASE("pbrt-v4 illuminants: rgb as given, spectra at luminance 1", "[pbrt][import]") {
    const std::string rgb = importPbrt(R"(
AreaLightSource "diffuse" "rgb L" [0.2 0.5 0.9] "float scale" [2]
Shape "sphere"
)")
                                .xml;
    CHECK_THAT(rgb, Contains("\"0.4, 1, 1.8\""));
    for (const char *spectrum : {"\"blackbody L\" [3000]", "\"spectrum L\" \"stdillum-D65\""}) {
        INFO(spectrum);
        const std::shared_ptr<Scene> scene =
            loadScene(importPbrt(std::string("AreaLightSource \"diffuse\" ") + spectrum +
                                 " \"float scale\" [2]\nShape \"sphere\"\n")
                          .xml);
        const Color3f power = scene->getEmitters().front()->getPower();
        // Power = π·L·area of a unit sphere: luminance 2·π·4π.
        CHECK(power.getLuminance() ==
              Approx(2.0 * kImportTestPi * 4.0 * kImportTestPi).epsilon(1e-3));
    }
}

TEST_CASE("pbrt-v4's crop window, pixel bounds and screen window map onto our camera",
          "[pbrt][import]") {
    auto header = [](const std::string &camera, const std::string &film) {
        return "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [40] " + camera +
               "\nFilm \"rgb\" \"integer xresolution\" [200] " + "\"integer yresolution\" [100] " +
               film + "\nWorldBegin\n";
    };
    // Fractions rounded up to pixels (pbrt-v4's FilmBaseParameters), in either order.
    const std::string cropped =
        importPbrt("", header("", "\"float cropwindow\" [0.7 0.101 0.25 0.5]")).xml;
    CHECK(importedNumber(cropped, "cropOffsetX") == 21);
    CHECK(importedNumber(cropped, "cropWidth") == 140 - 21);
    CHECK(importedNumber(cropped, "cropOffsetY") == 25);
    CHECK(importedNumber(cropped, "cropHeight") == 25);
    // Pixel bounds are clamped to the image; the crop window wins over them.
    const std::string bounds =
        importPbrt("", header("", "\"integer pixelbounds\" [-5 50 90 120]")).xml;
    CHECK(importedNumber(bounds, "cropOffsetX") == 0);
    CHECK(importedNumber(bounds, "cropWidth") == 50);
    CHECK(importedNumber(bounds, "cropOffsetY") == 90);
    CHECK(importedNumber(bounds, "cropHeight") == 10);
    CHECK(importedNumber(importPbrt("", header("", "\"integer pixelbounds\" [0 10 0 10] "
                                                   "\"float cropwindow\" [0.5 1 0 1]"))
                             .xml,
                         "cropOffsetX") == 100);
    CHECK_THAT(importPbrt("").xml, !Contains("crop"));
    CHECK_THAT(errorOf([&] { importPbrt("", header("", "\"float cropwindow\" [0.5 0.5 0 1]")); }),
               Contains("test.pbrt:3:") && Contains("is empty"));
    // A centred window of the image's aspect is our usual fov; any other is written out.
    CHECK_THAT(importPbrt("", header("\"float screenwindow\" [-2 2 -1 1]", "")).xml,
               !Contains("screenWindow"));
    const std::string offAxis =
        importPbrt("", header("\"float screenwindow\" [-1 3 -1 1]", "")).xml;
    CHECK_THAT(offAxis, Contains("<string name=\"screenWindow\" value=\"-1 3 -1 1\""));
    CHECK(importedNumber(offAxis, "fov") == Approx(40.0));
    CHECK_THAT(importPbrt("", header("\"float frameaspectratio\" [1]", "")).xml,
               Contains("<string name=\"screenWindow\" value=\"-1 1 -1 1\""));
    CHECK_THAT(errorOf([&] { importPbrt("", header("\"float screenwindow\" [1 -1 0 1]", "")); }),
               Contains("xmin < xmax"));
    // White balance onto the camera; none unless asked.
    CHECK(importedNumber(importPbrt("", header("", "\"float whitebalance\" [5000]")).xml,
                         "whiteBalance") == 5000);
    CHECK_THAT(importPbrt("").xml, !Contains("whiteBalance"));
}

TEST_CASE("pbrt-v4 files with mistakes give located errors with suggestions", "[pbrt][import]") {
    CHECK_THAT(importError("Material \"diffuse\" \"rgb reflectanse\" [0.5 0.5 0.5]\n"
                           "Shape \"sphere\"\n"),
               Contains("test.pbrt:7:") && Contains("reflectanse") &&
                   Contains("did you mean 'reflectance'"));
    CHECK_THAT(importError("Material \"difuse\"\nShape \"sphere\"\n"),
               Contains("test.pbrt:7:") && Contains("'difuse'") && Contains("'diffuse'"));
    CHECK_THAT(importError("Shape \"spere\"\n"), Contains("'sphere'"));
    CHECK_THAT(importError("Material \"diffuse\" \"texture reflectance\" \"chek\"\n"
                           "Texture \"check\" \"spectrum\" \"checkerboard\"\n"
                           "Shape \"sphere\"\n"),
               Contains("no spectrum texture named 'chek'") && Contains("'check'"));
    CHECK_THAT(importError("Material \"diffuse\" \"bool reflectance\" true\nShape \"sphere\"\n"),
               Contains("wrong type"));
    CHECK_THAT(importError("Shape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0 1 1 0] "
                           "\"integer indices\" [0 1 7]\n"),
               Contains("index 7"));
    CHECK_THAT(importError("MediumInterface \"fog\" \"\"\nShape \"sphere\"\n"),
               Contains("no medium named 'fog'"));
}

TEST_CASE("unsupported pbrt-v4 features warn once per file, naming the stand-in",
          "[pbrt][import]") {
    const pbrt::Conversion conversion = importPbrt(R"(
Material "hair"
Shape "sphere"
Material "hair" "float eta" [1.6]
Shape "sphere"
Shape "curve" "point3 P" [0 0 0 1 0 0 1 1 0 0 1 0]
LightSource "goniometric" "string filename" "x.exr"
)");
    size_t hair = 0;
    for (const std::string &warning : conversion.warnings)
        hair += warning.find("'hair'") != std::string::npos;
    CHECK(hair == 1);
    std::string all;
    for (const std::string &warning : conversion.warnings)
        all += warning + "\n";
    CHECK_THAT(all, Contains("diffuse grey of 0.5") && Contains("'curve'") && Contains("skipped") &&
                        Contains("'goniometric'") && Contains("test.pbrt:"));
}

TEST_CASE("pbrt-v4 shapes without a plugin of their own become triangle meshes", "[pbrt][import]") {
    // A Loop subdivision surface of an octahedron, 2 levels: 8·4² triangles over a closed
    // surface, every vertex pushed to the limit surface: a convex combination of the
    // octahedron's corners, the six corners themselves at the limit position
    // (1 − 4γ)·v + γ·Σ neighbours = v/2 of a valence-4 vertex (γ = 1/8), normals outward.
    const std::shared_ptr<Scene> scene = loadScene(importPbrt(R"(
Shape "loopsubdiv" "integer levels" [2]
  "point3 P" [0 1 0  1 0 0  0 0 1  -1 0 0  0 0 -1  0 -1 0]
  "integer indices" [0 2 1  0 3 2  0 4 3  0 1 4  5 1 2  5 2 3  5 3 4  5 4 1]
Translate 3 0 0
Shape "sphere" "float zmax" [0.5]
Translate 3 0 0
Shape "bilinearmesh" "point3 P" [0 0 0  1 0 0  0 1 0  1 1 0]
)")
                                                       .xml);
    const auto &shapes = scene->getShapes();
    REQUIRE(shapes.size() == 3);
    const auto *surface = dynamic_cast<const Mesh *>(shapes[0].get());
    REQUIRE(surface);
    CHECK(surface->getTriangleCount() == 8 * 16);
    const MatrixXf &positions = surface->getVertexPositions();
    const MatrixXf &normals = surface->getVertexNormals();
    REQUIRE(normals.cols() == positions.cols());
    for (uint32_t i = 0; i < surface->getVertexCount(); ++i) {
        const Vector3f p = positions.col(i), n = normals.col(i);
        CHECK(p.cwiseAbs().sum() <= 1.0f + 1e-5f);
        CHECK(n.dot(p) > 0.0f);
        if (i < 6)
            CHECK(p.norm() == Approx(0.5f).epsilon(1e-5));
    }
    const auto *bilinear = dynamic_cast<const Mesh *>(shapes[2].get());
    REQUIRE(bilinear);
    CHECK(bilinear->getTriangleCount() == 2);
    CHECK(bilinear->getArea() == Approx(1.0f));
}

TEST_CASE("trianglemesh reads its numbers back exactly", "[pbrt][import][shapes]") {
    const std::shared_ptr<Scene> scene = loadScene(R"(<scene>
        <integrator type="normals"/> <camera type="perspective"/>
        <mesh type="trianglemesh">
            <string name="positions" value="0.1 1e-7 -12345.6789, 1 0 0, 0.333333343 1 0"/>
        </mesh></scene>)");
    const auto *mesh = dynamic_cast<const Mesh *>(scene->getShapes().front().get());
    REQUIRE(mesh);
    const MatrixXf &positions = mesh->getVertexPositions();
    CHECK(positions(0, 0) == 0.1f);
    CHECK(positions(1, 0) == 1e-7f);
    CHECK(positions(2, 0) == -12345.6789f);
    CHECK(positions(0, 2) == 1.0f / 3.0f);
    CHECK_THAT(
        errorOf([] {
            loadScene(
                R"(<scene><integrator type="normals"/><camera type="perspective"/><mesh type="trianglemesh">
                       <string name="positions" value="0 0 0, 1 0 0, 0 1 0, 1 1 0"/>
                       </mesh></scene>)");
        }),
        Contains("'indices' is required"));
    CHECK_THAT(
        errorOf([] {
            loadScene(
                R"(<scene><integrator type="normals"/><camera type="perspective"/><mesh type="trianglemesh">
                       <string name="positions" value="0 0 0, 1 0 zero, 0 1 0"/>
                       </mesh></scene>)");
        }),
        Contains("\"zero\""));
}

TEST_CASE("nori renders a .pbrt file and its `nori convert` output to the same image",
          "[pbrt][import][cli]") {
    const TempDir dir;
    // Large enough an inline mesh (a subdivided octahedron of 258 vertices) that convert
    // writes it as a PLY file; a texture, a medium and an instance for the rest.
    dir.write("scene.pbrt", R"(
LookAt 0 1 -4  0 0 0  0 1 0
Camera "perspective" "float fov" [45]
Film "rgb" "integer xresolution" [24] "integer yresolution" [16] "string filename" "named.exr"
Sampler "independent" "integer pixelsamples" [8]
Integrator "volpath" "integer maxdepth" [4]
WorldBegin
LightSource "infinite" "rgb L" [0.5 0.6 0.7]
AttributeBegin
  AreaLightSource "diffuse" "blackbody L" [4000] "float scale" [5]
  Shape "trianglemesh" "point3 P" [-1 2 -1  1 2 -1  1 2 1  -1 2 1] "integer indices" [0 2 1 0 3 2]
AttributeEnd
Texture "checks" "spectrum" "checkerboard" "float uscale" [8] "float vscale" [8]
Material "diffuse" "texture reflectance" "checks"
Shape "bilinearmesh" "point3 P" [-3 -1 -3  3 -1 -3  -3 -1 3  3 -1 3] "point2 uv" [0 0 1 0 0 1 1 1]
MakeNamedMedium "fog" "string type" "homogeneous" "rgb sigma_a" [0.2 0.3 0.4] "rgb sigma_s" [1 1 1]
AttributeBegin
  Material "interface"
  MediumInterface "fog" ""
  Shape "sphere" "float radius" [0.6]
AttributeEnd
ObjectBegin "blob"
  Material "coateddiffuse" "rgb reflectance" [0.7 0.2 0.1]
  Shape "loopsubdiv" "integer levels" [3]
    "point3 P" [0 1 0  1 0 0  0 0 1  -1 0 0  0 0 -1  0 -1 0]
    "integer indices" [0 2 1  0 3 2  0 4 3  0 1 4  5 1 2  5 2 3  5 3 4  5 4 1]
ObjectEnd
AttributeBegin
  Translate 1.5 0 0
  Scale 0.5 0.5 0.5
  ObjectInstance "blob"
AttributeEnd
)");
    const ProcessResult direct = runNori({(dir.path() / "scene.pbrt").string(), "--no-progress"});
    INFO(direct.output);
    REQUIRE(direct.exitCode == 0);
    // The film's filename names the output, next to the scene.
    REQUIRE(fs::exists(dir.path() / "named.exr"));

    const ProcessResult converted = runNori({"convert", (dir.path() / "scene.pbrt").string(), "-o",
                                             (dir.path() / "out/ours.xml").string()});
    INFO(converted.output);
    REQUIRE(converted.exitCode == 0);
    REQUIRE(fs::exists(dir.path() / "out/ours_meshes"));
    const ProcessResult rendered =
        runNori({(dir.path() / "out/ours.xml").string(), "--no-progress"});
    INFO(rendered.output);
    REQUIRE(rendered.exitCode == 0);
    CHECK(identicalImages(readImageFile((dir.path() / "named.exr").string()).pixels,
                          readImageFile((dir.path() / "out/ours.exr").string()).pixels));
}

TEST_CASE("a broken .pbrt file is a located error and a non-zero exit", "[pbrt][import][cli]") {
    const TempDir dir;
    dir.write("broken.pbrt", "WorldBegin\nShape \"sphere\" \"float radius\" [1]\n"
                             "Material \"diffuse\" \"rgb reflectance\" [0.5 0.5]\n");
    const ProcessResult result = runNori({(dir.path() / "broken.pbrt").string()});
    CHECK(result.exitCode != 0);
    CHECK_THAT(result.output, Contains("broken.pbrt:3:") && Contains("reflectance"));
}

TEST_CASE("pbrt-v4 textures map onto ours", "[pbrt][import]") {
    const std::string xml = importPbrt(R"(
Texture "checks" "spectrum" "checkerboard" "float uscale" [4] "float vscale" [2]
  "rgb tex1" [0.8 0.8 0.8] "rgb tex2" [0.1 0.2 0.3]
Texture "photo" "spectrum" "imagemap" "string filename" "photo.png"
Texture "hdr" "spectrum" "imagemap" "string filename" "sky.exr" "float scale" [2]
Texture "rough" "float" "imagemap" "string filename" "rough.png" "bool invert" true
Material "diffuse" "texture reflectance" "checks"
Shape "sphere"
Material "diffuse" "texture reflectance" "photo"
Shape "sphere"
Material "diffuse" "texture reflectance" "hdr"
Shape "sphere"
Material "conductor" "texture roughness" "rough" "bool remaproughness" false
Shape "sphere"
)")
                                .xml;
    // The checkerboard: tex1 on even cells of s = 4u, t = 2v.
    CHECK_THAT(xml, Contains("type=\"checkerboard_float\"") && Contains("\"0.25, 0.5\""));
    // pbrt-v4 decodes PNG from sRGB and anything else as linear.
    const size_t photo = xml.find("photo.png"), sky = xml.find("sky.exr");
    REQUIRE(photo != std::string::npos);
    REQUIRE(sky != std::string::npos);
    CHECK(xml.find("\"srgb\"", photo) < xml.find("\"linear\"", photo));
    CHECK(xml.find("\"linear\"", sky) < xml.find("</texture>", sky));
    // scale wraps the image; invert is 1 − x as a mix of 1 and 0.
    CHECK_THAT(xml, Contains("type=\"scale\"") && Contains("type=\"mix\""));
    // Textures are declared before everything that refers to them.
    CHECK(xml.find("id=\"texture:checks\"") < xml.find("<!-- the scene -->"));
}

TEST_CASE("pbrt-v4's image encodings: sRGB, linear, gamma G, for 8-bit images only",
          "[pbrt][import]") {
    auto imported = [](const std::string &file, const std::string &encoding) {
        return importPbrt("Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"" + file +
                          "\" " + encoding +
                          "\nMaterial \"diffuse\" \"texture reflectance\" \"t\"\n"
                          "Shape \"sphere\"\n")
            .xml;
    };
    CHECK_THAT(imported("a.png", "\"string encoding\" \"gamma 2.2\""),
               Contains("<float name=\"gamma\" value=\"2.2\"") && !Contains("colorSpace"));
    CHECK_THAT(imported("a.tga", ""), Contains("\"linear\""));
    CHECK_THAT(imported("a.tga", "\"string encoding\" \"sRGB\""), Contains("\"srgb\""));
    CHECK_THAT(imported("a.exr", "\"string encoding\" \"sRGB\""),
               Contains("\"linear\"") && !Contains("\"srgb\""));
    CHECK_THAT(imported("a.exr", "\"string encoding\" \"gamma 2.2\""),
               Contains("\"linear\"") && !Contains("gamma"));
    CHECK_THAT(errorOf([&] { imported("a.png", "\"string encoding\" \"gama 2.2\""); }),
               Contains("test.pbrt:7:") && Contains("'gama 2.2' is not"));
}

TEST_CASE("a pbrt-v4 camera inside a medium gets that medium", "[pbrt][import]") {
    const std::string header = R"(
MakeNamedMedium "fog" "string type" "homogeneous" "rgb sigma_a" [0.1 0.1 0.1]
MediumInterface "" "fog"
LookAt 0 0 -5  0 0 0  0 1 0
Camera "perspective" "float fov" [40]
Film "rgb" "integer xresolution" [8] "integer yresolution" [8]
WorldBegin
)";
    // The medium is declared before the camera that refers to it.
    const std::shared_ptr<Scene> scene = loadScene(importPbrt("Shape \"sphere\"\n", header).xml);
    REQUIRE(scene->getCamera()->getMedium() != nullptr);
}

TEST_CASE("pbrt-v4's anisotropic and textured roughness map onto alphaU, alphaV and remapping",
          "[pbrt][import]") {
    const std::string anisotropic = importPbrt(R"(
Material "conductor" "float uroughness" [0.04] "float vroughness" [0.25]
Shape "sphere"
)")
                                        .xml;
    CHECK(importedNumber(anisotropic, "alphaU") == Approx(0.2));
    CHECK(importedNumber(anisotropic, "alphaV") == Approx(0.5));
    CHECK_THAT(anisotropic, !Contains("remapRoughness"));
    // A texture is remapped by the plugin, and so then is the constant beside it.
    const std::string textured = importPbrt(R"(
Texture "r" "float" "imagemap" "string filename" "rough.png"
Material "conductor" "texture uroughness" "r" "float vroughness" [0.25]
Shape "sphere"
Material "dielectric" "texture roughness" "r" "bool remaproughness" false
Shape "sphere"
)")
                                     .xml;
    CHECK_THAT(textured, Contains("<ref name=\"alphaU\" id=\"floattexture:r\"") &&
                             Contains("<float name=\"alphaV\" value=\"0.25\"") &&
                             Contains("<boolean name=\"remapRoughness\" value=\"true\"") &&
                             Contains("<ref name=\"alpha\" id=\"floattexture:r\""));
    CHECK(textured.find("remapRoughness") == textured.rfind("remapRoughness"));
}
