#include "testing/agreementscenes.h"

#include <nori/bitmap.h>
#include <nori/common.h>
#include <nori/transform.h>
#include <nori/volumegrid.h>

#include <fstream>

namespace nori {

namespace {

using FileWriter = std::function<void(const std::string &path)>;

FileWriter textFile(std::string content) {
    return [content = std::move(content)](const std::string &path) {
        std::ofstream file(path);
        file << content;
        if (!file)
            throw NoriException("cannot write {}", path);
    };
}

/// A quad corner, corner + u, corner + u + v, corner + v (its normal along u × v), uv
/// over [0, 1]², as an OBJ file's text.
std::string quadOBJ(const Vector3f &corner, const Vector3f &u, const Vector3f &v) {
    std::string obj;
    for (const Vector3f &p :
         {corner, Vector3f(corner + u), Vector3f(corner + u + v), Vector3f(corner + v)})
        obj += fmt::format("v {} {} {}\n", p.x(), p.y(), p.z());
    return obj + "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n";
}

/// An axis-aligned box from `lower` to `upper` with outward faces, as an OBJ file's text.
std::string boxOBJ(const Vector3f &lower, const Vector3f &upper) {
    std::string obj;
    for (int i = 0; i < 8; ++i)
        obj += fmt::format("v {} {} {}\n", (i & 1) ? upper.x() : lower.x(),
                           (i & 2) ? upper.y() : lower.y(), (i & 4) ? upper.z() : lower.z());
    // Vertex i + 1 has x, y, z upper where bits 0, 1, 2 of i are set; each face is
    // counter-clockwise seen from outside.
    return obj + "f 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n"  // −x, +x
                 "f 1 2 6\nf 1 6 5\nf 3 7 8\nf 3 8 4\n"  // −y, +y
                 "f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\n"; // −z, +z
}

} // namespace

FileWriter skyMap(float sun) {
    return [sun](const std::string &path) {
        const int width = 64, height = 32;
        Bitmap map(Eigen::Vector2i(width, height));
        for (int y = 0; y < height; ++y)
            for (int x = 0; x < width; ++x) {
                const float cosTheta = std::cos((static_cast<float>(y) + 0.5f) * kPi / height);
                map(y, x) = cosTheta > 0.0f ? Color3f(0.25f, 0.4f, 0.9f) * (0.4f + 0.6f * cosTheta)
                                            : Color3f(0.12f, 0.1f, 0.08f);
            }
        for (int y = 6; y < 9; ++y)
            for (int x = 20; x < 23; ++x)
                map(y, x) = Color3f(sun, 0.9f * sun, 0.75f * sun);
        map.saveEXR(path);
    };
}

namespace {

/// A colour checkerboard of 4×4-texel squares on a 32×32 image, darkening along u: the
/// ramp makes every region's mean depend on where the texels fall (a periodic pattern
/// alone would hide a texture lookup shifted by a fraction of a texel).
FileWriter checkerTexture() {
    return [](const std::string &path) {
        Bitmap image(Eigen::Vector2i(32, 32));
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                const Color3f square = ((x / 4 + y / 4) % 2 == 0) ? Color3f(0.8f, 0.7f, 0.5f)
                                                                  : Color3f(0.15f, 0.3f, 0.6f);
                image(y, x) = square * (1.0f - 0.8f * (static_cast<float>(x) + 0.5f) / 32.0f);
            }
        image.saveEXR(path);
    };
}

/// A tangent-space normal map of ridges along u, encoded as (n + 1)/2.
FileWriter ridgeNormalMap() {
    return [](const std::string &path) {
        Bitmap image(Eigen::Vector2i(32, 32));
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 32; ++x) {
                const float slope =
                    0.6f * std::sin(2.0f * kPi * (static_cast<float>(x) + 0.5f) / 8.0f);
                const Vector3f n = Vector3f(-slope, 0.0f, 1.0f).normalized();
                image(y, x) =
                    Color3f(0.5f * (n.x() + 1.0f), 0.5f * (n.y() + 1.0f), 0.5f * (n.z() + 1.0f));
            }
        image.saveEXR(path);
    };
}

/// A 16³ density grid over the unit cube: a smooth blob, denser at the centre.
FileWriter blobDensity() {
    return [](const std::string &path) {
        const int n = 16;
        std::vector<float> values;
        for (int z = 0; z < n; ++z)
            for (int y = 0; y < n; ++y)
                for (int x = 0; x < n; ++x) {
                    const Vector3f p = (Vector3f(x, y, z) + Vector3f::Constant(0.5f)) / n -
                                       Vector3f::Constant(0.5f);
                    values.push_back(std::max(0.0f, 1.0f - 3.0f * p.squaredNorm()) +
                                     0.3f * (((x + y + z) % 3) == 0 ? 1.0f : 0.0f));
                }
        VolumeGrid(Vector3i(n, n, n), 1, std::move(values), Transform(), "blob").writeVol(path);
    };
}

/// Tronnier's double-Gauss 50 mm f/2 (W. J. Smith, Modern Lens Design, p. 312; pbrt-v3's
/// tabulation), in pbrt's format: radius, thickness, index, aperture diameter (mm).
FileWriter doubleGaussLens() {
    return textFile(" 29.475 3.76 1.67 25.2\n 84.83 0.12 0 25.2\n 19.275 4.025 1.67 23\n"
                    " 40.77 3.275 1.699 23\n 12.75 5.705 0 18\n 0 4.5 0 17.1\n"
                    "-14.495 1.18 1.603 17\n 40.77 6.065 1.658 20\n-20.385 0.19 0 20\n"
                    " 437.065 3.22 1.717 20\n-39.73 5 0 20\n");
}

std::string perspective(const std::string &origin, const std::string &target, float fov, int size,
                        const std::string &extra = "") {
    return fmt::format(R"(<camera type="perspective"><float name="fov" value="{}"/>
        <integer name="width" value="{}"/><integer name="height" value="{}"/>{}
        <transform name="toWorld"><lookat origin="{}" target="{}" up="0, 1, 0"/></transform>
        </camera>)",
                       fov, size, size, extra, origin, target);
}

std::string mesh(const std::string &file, const std::string &inside) {
    return fmt::format(R"(<mesh type="obj"><string name="filename" value="{}"/>{}</mesh>)", file,
                       inside);
}

std::string diffuse(const std::string &albedo) {
    return fmt::format(R"(<bsdf type="diffuse"><color name="albedo" value="{}"/></bsdf>)", albedo);
}

std::string sphere(const std::string &center, float radius, const std::string &inside) {
    return fmt::format(R"(<mesh type="sphere"><point name="center" value="{}"/>
        <float name="radius" value="{}"/>{}</mesh>)",
                       center, radius, inside);
}

std::string areaLight(const std::string &radiance) {
    return fmt::format(R"(<emitter type="area"><color name="radiance" value="{}"/></emitter>)",
                       radiance);
}

Estimator pathTracer(const std::string &strategy, size_t spp, const std::string &params = "") {
    return {
        strategy,      fmt::format(R"(<integrator type="{}">{}</integrator>)", strategy, params),
        "independent", "",
        spp,           ""};
}

Estimator sampler(const std::string &type, size_t spp) {
    return {"path_mis+" + type, R"(<integrator type="path_mis"/>)", type, "", spp, ""};
}

Estimator adaptive(size_t spp) {
    return {"path_mis+adaptive",
            R"(<integrator type="path_mis"/>)",
            "independent",
            R"(<float name="maxTolerance" value="0.05"/><integer name="minSamples" value="16"/>)",
            spp,
            ""};
}

Estimator lightTracer(size_t spp, const std::string &params = "") {
    return {"lighttracer", fmt::format(R"(<integrator type="lighttracer">{}</integrator>)", params),
            "independent", "",
            spp,           ""};
}

Estimator bidirectional(size_t spp, const std::string &params = "") {
    return {"bdpt",        fmt::format(R"(<integrator type="bdpt">{}</integrator>)", params),
            "independent", "",
            spp,           ""};
}

Estimator progressivePhotons(size_t spp, int photons) {
    return {"sppm",
            fmt::format(R"(<integrator type="progressivephotonmapper">
                <integer name="photonCount" value="{}"/></integrator>)",
                        photons),
            "independent",
            "",
            spp,
            ""};
}

/// The Cornell box of side 2 around the origin, open toward +z, with a square light of
/// side 0.8 under the ceiling, a diffuse sphere and a rough conductor sphere.
AgreementScene cornellBox() {
    AgreementScene scene;
    scene.name = "cornell-box";
    const Vector3f x = Vector3f::UnitX() * 2.0f, y = Vector3f::UnitY() * 2.0f,
                   z = Vector3f::UnitZ() * 2.0f;
    scene.files["floor.obj"] = textFile(quadOBJ({-1, -1, 1}, x, -z));
    scene.files["ceiling.obj"] = textFile(quadOBJ({-1, 1, -1}, x, z));
    scene.files["back.obj"] = textFile(quadOBJ({-1, -1, -1}, x, y));
    scene.files["left.obj"] = textFile(quadOBJ({-1, -1, 1}, -z, y));
    scene.files["right.obj"] = textFile(quadOBJ({1, -1, -1}, z, y));
    scene.files["light.obj"] =
        textFile(quadOBJ({-0.4f, 0.999f, -0.4f}, Vector3f(0.8f, 0, 0), Vector3f(0, 0, 0.8f)));
    scene.body = perspective("0, 0, 3.4", "0, 0, 0", 42, 32) + mesh("floor.obj", diffuse("0.7")) +
                 mesh("ceiling.obj", diffuse("0.7")) + mesh("back.obj", diffuse("0.7")) +
                 mesh("left.obj", diffuse("0.6, 0.1, 0.1")) +
                 mesh("right.obj", diffuse("0.1, 0.6, 0.1")) +
                 mesh("light.obj", diffuse("0") + areaLight("5")) +
                 sphere("-0.4, -0.6, -0.3", 0.4f, diffuse("0.7")) +
                 sphere("0.45, -0.65, 0.3", 0.35f,
                        R"(<bsdf type="roughconductor"><string name="material" value="Al"/>
                           <float name="alpha" value="0.2"/></bsdf>)");
    scene.regions = {{"shadow", 8, 26, 8, 4},
                     {"red-wall", 0, 8, 4, 12},
                     {"wall-edge", 0, 8, 2, 12},
                     {"wall-inner", 2, 8, 3, 12},
                     {"glossy", 17, 19, 6, 6}};
    scene.estimators = {pathTracer("path_mis", 512),
                        pathTracer("path_ems", 512),
                        pathTracer("path_mats", 1024),
                        pathTracer("volpath", 512),
                        sampler("sobol", 512),
                        sampler("stratified", 512),
                        adaptive(768),
                        progressivePhotons(64, 20000),
                        lightTracer(512),
                        bidirectional(256)};
    return scene;
}

/// A floor quad of side 2·half at height 0, facing up, uv over [0, 1]².
std::string floorOBJ(float half) {
    return quadOBJ({-half, 0, half}, Vector3f(2 * half, 0, 0), Vector3f(0, 0, -2 * half));
}

/// Four rough conductor plates of decreasing roughness lit by four spherical lights of
/// increasing size and decreasing radiance (equal power), as Veach's figure 9.2.
AgreementScene glossyPlates() {
    AgreementScene scene;
    scene.name = "glossy-plates";
    std::string plates;
    const float alphas[] = {0.02f, 0.05f, 0.12f, 0.3f};
    for (int i = 0; i < 4; ++i) {
        const float z = 0.9f - 0.6f * static_cast<float>(i), y = -0.9f + 0.25f * i;
        const float tilt = 0.35f - 0.1f * static_cast<float>(i);
        const std::string file = fmt::format("plate{}.obj", i);
        scene.files[file] = textFile(quadOBJ({-1.2f, y - 0.1f, z + tilt}, Vector3f(2.4f, 0, 0),
                                             Vector3f(0, 0.2f, -2.0f * tilt)));
        plates += mesh(file, fmt::format(R"(<bsdf type="roughconductor">
            <string name="material" value="Ag"/><float name="alpha" value="{}"/></bsdf>)",
                                         alphas[i]));
    }
    const float radii[] = {0.03f, 0.1f, 0.2f, 0.4f};
    std::string lights;
    for (int i = 0; i < 4; ++i)
        lights += sphere(fmt::format("{}, 1.6, -1.2", -1.2f + 0.8f * static_cast<float>(i)),
                         radii[i], areaLight(fmt::format("{}", 0.4f / (radii[i] * radii[i]))));
    scene.body = perspective("0, 0.6, 3.2", "0, -0.4, 0", 45, 32) + plates + lights;
    scene.regions = {{"highlights", 2, 14, 28, 6}, {"upper", 2, 8, 28, 5}};
    scene.estimators = {pathTracer("path_mis", 1024),
                        pathTracer("path_ems", 1024),
                        pathTracer("path_mats", 4096),
                        sampler("sobol", 1024),
                        lightTracer(1024),
                        bidirectional(512)};
    scene.estimators[2].powerExemption =
        "BSDF sampling rarely finds the smallest light (radius 0.03) from the sharpest plates: "
        "0.5 % would take far more samples than a test has";
    return scene;
}

/// A sky with a sun (the environment map of skyMap) over a diffuse floor, a rough gold
/// sphere and a glass sphere, whose caustic falls on the floor.
AgreementScene skyWithSun() {
    AgreementScene scene;
    scene.name = "sky-sun";
    scene.files["sky.exr"] = skyMap(60.0f);
    scene.files["floor.obj"] = textFile(floorOBJ(10.0f));
    scene.body = perspective("0, 2.2, 4.5", "0, 0.3, 0", 40, 32) +
                 R"(<emitter type="envmap"><string name="filename" value="sky.exr"/></emitter>)" +
                 mesh("floor.obj", diffuse("0.6")) +
                 sphere("-0.7, 0.5, 0", 0.5f, R"(<bsdf type="roughconductor">
                     <string name="material" value="Au"/><float name="alpha" value="0.15"/></bsdf>)") +
                 sphere("0.7, 0.5, 0", 0.5f, R"(<bsdf type="dielectric"/>)");
    scene.specularInView = true;
    scene.regions = {{"sky", 0, 0, 32, 3},
                     {"conductor", 9, 10, 6, 6},
                     {"glass", 17, 10, 6, 6},
                     {"caustic", 18, 16, 4, 3},
                     {"floor", 0, 24, 32, 8}};
    scene.estimators = {pathTracer("path_mis", 512), pathTracer("path_ems", 512),
                        pathTracer("path_mats", 2048), progressivePhotons(64, 20000),
                        bidirectional(256)};
    scene.estimators[2].powerExemption =
        "BSDF sampling rarely finds the sun (9 texels of the 64x32 map): 0.5 % would take "
        "far more samples than a test has (issue 42 estimates 5e8)";
    return scene;
}

/// A spot and a directional light (delta lights) over a floor and a diffuse sphere,
/// direct light only (maxDepth 1), where every direct-lighting integrator applies.
AgreementScene deltaLights() {
    AgreementScene scene;
    scene.name = "delta-lights";
    scene.files["floor.obj"] = textFile(floorOBJ(3.0f));
    scene.body = perspective("0, 2.5, 4", "0, 0.2, 0", 45, 32) + mesh("floor.obj", diffuse("0.6")) +
                 sphere("0, 0.6, 0", 0.6f, diffuse("0.5, 0.6, 0.7")) +
                 R"(<emitter type="spot"><point name="position" value="1.5, 3, 1"/>
                     <point name="target" value="0, 0, 0"/><color name="intensity" value="12"/>
                     <float name="cutoffAngle" value="30"/><float name="beamWidth" value="20"/></emitter>
                   <emitter type="directional"><vector name="direction" value="-1, -2, -0.5"/>
                     <color name="irradiance" value="1, 0.9, 0.8"/></emitter>)";
    scene.regions = {{"sphere", 12, 7, 8, 7}, {"shadow", 9, 15, 6, 3}};
    const std::string depth1 = R"(<integer name="maxDepth" value="1"/>)";
    scene.estimators = {pathTracer("path_mis", 512, depth1),
                        pathTracer("path_ems", 512, depth1),
                        pathTracer("direct_mis", 512),
                        pathTracer("direct_ems", 512),
                        pathTracer("whitted", 512),
                        pathTracer("direct", 512),
                        lightTracer(512, depth1),
                        bidirectional(256, depth1)};
    return scene;
}

/// The shapes and materials of real scenes (issue 72): a rectangle, a disk and a cylinder
/// as lights over a floor, a plastic, a rough plastic and two coated spheres and a diffuse
/// transmitter, so that the new shapes' light sampling (path_ems) agrees with BSDF sampling
/// hitting them (path_mats), and the coated BSDFs' estimated eval() (light sampling) with
/// their sampled walks (BSDF sampling).
AgreementScene shapeLights() {
    AgreementScene scene;
    scene.name = "shape-lights";
    scene.files["floor.obj"] = textFile(floorOBJ(3.0f));
    scene.body = perspective("0, 1.6, 4", "0, 0.4, 0", 45, 32) + mesh("floor.obj", diffuse("0.6")) +
                 R"(<mesh type="rectangle"><transform name="toWorld"><scale value="0.5, 0.35, 1"/>
               <rotate axis="1, 0, 0" angle="100"/><translate value="-1.2, 1.8, -0.5"/></transform>
               <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
               <emitter type="area"><color name="radiance" value="4, 3.5, 3"/></emitter></mesh>
           <mesh type="disk"><transform name="toWorld"><scale value="0.4"/>
               <rotate axis="1, 0, 0" angle="60"/><translate value="1.2, 1.6, -0.8"/></transform>
               <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
               <emitter type="area"><color name="radiance" value="3, 3.5, 4"/></emitter></mesh>
           <mesh type="cylinder"><point name="p0" value="-0.6, 2.2, -1.5"/>
               <point name="p1" value="0.6, 2.2, -1.5"/><float name="radius" value="0.08"/>
               <bsdf type="diffuse"><color name="albedo" value="0"/></bsdf>
               <emitter type="area"><color name="radiance" value="6"/></emitter></mesh>)" +
                 sphere("-0.6, 0.5, 0", 0.5f, R"(<bsdf type="plastic">
            <color name="diffuseReflectance" value="0.2, 0.4, 0.7"/></bsdf>)") +
                 sphere("0.6, 0.45, 0.1", 0.45f, R"(<bsdf type="roughplastic">
            <float name="alpha" value="0.15"/><color name="diffuseReflectance" value="0.7, 0.5, 0.2"/></bsdf>)") +
                 R"(<mesh type="rectangle"><transform name="toWorld"><scale value="0.4"/>
               <rotate axis="0, 1, 0" angle="20"/><translate value="0, 0.5, -1.2"/></transform>
               <bsdf type="diffusetransmission"/></mesh>)" +
                 sphere("0, 0.25, 0.7", 0.25f, R"(<bsdf type="coatedconductor">
            <float name="interfaceRoughness" value="0.02"/><float name="conductorRoughness" value="0.1"/>
            <string name="material" value="Au"/></bsdf>)") +
                 sphere("-1.3, 0.3, 0.5", 0.3f,
                        R"(<bsdf type="coateddiffuse"><float name="roughness" value="0.05"/>
            <color name="reflectance" value="0.2, 0.5, 0.3"/></bsdf>)");
    scene.regions = {{"floor", 0, 24, 32, 8}, {"spheres", 6, 10, 20, 10}};
    scene.estimators = {pathTracer("path_mis", 512), pathTracer("path_ems", 512),
                        pathTracer("path_mats", 2048)};
    return scene;
}

/// A floor with a checkerboard albedo texture and a normal map of ridges, under a
/// tilted square light.
AgreementScene texturedPlane() {
    AgreementScene scene;
    scene.name = "textured";
    scene.files["floor.obj"] = textFile(floorOBJ(1.5f));
    scene.files["light.obj"] =
        textFile(quadOBJ({-0.5f, 1.5f, 0.5f}, Vector3f(0, 0, -1), Vector3f(1, 0.3f, 0)));
    scene.files["albedo.exr"] = checkerTexture();
    scene.files["normal.exr"] = ridgeNormalMap();
    scene.body = perspective("0, 2.5, 2.5", "0, 0, 0", 40, 32) +
                 mesh("floor.obj", R"(<bsdf type="diffuse"><texture type="image" name="albedo">
                         <string name="filename" value="albedo.exr"/></texture></bsdf>
                     <texture type="image" name="normal"><string name="filename" value="normal.exr"/></texture>)") +
                 mesh("light.obj", diffuse("0") + areaLight("4"));
    scene.regions = {{"centre", 8, 8, 16, 16}};
    scene.estimators = {pathTracer("path_mis", 256),
                        pathTracer("path_ems", 256),
                        pathTracer("path_mats", 512),
                        sampler("sobol", 256),
                        lightTracer(256),
                        bidirectional(128)};
    return scene;
}

/// A homogeneous box (HG g = 0.7) and a heterogeneous one (a blob of density, g = −0.7)
/// on a floor under a square light; volpath with each transmittance estimator.
AgreementScene media() {
    AgreementScene scene;
    scene.name = "media";
    scene.files["floor.obj"] = textFile(floorOBJ(3.0f));
    scene.files["box.obj"] = textFile(boxOBJ(Vector3f::Constant(-0.5f), Vector3f::Constant(0.5f)));
    scene.files["light.obj"] =
        textFile(quadOBJ({-0.6f, 2.5f, -0.6f}, Vector3f(1.2f, 0, 0), Vector3f(0, 0, 1.2f)));
    scene.files["blob.vol"] = blobDensity();
    scene.body =
        perspective("0, 1.8, 4", "0, 0.5, 0", 40, 32) + mesh("floor.obj", diffuse("0.6")) +
        mesh("light.obj", diffuse("0") + areaLight("6")) +
        mesh("box.obj", R"(<transform name="toWorld"><translate value="-0.7, 0.5, 0"/></transform>
                     <medium type="homogeneous" name="interior"><color name="sigmaS" value="1.5, 2, 2.5"/>
                     <color name="sigmaA" value="0.2"/><phase type="hg"><float name="g" value="0.7"/></phase>
                     </medium>)") +
        mesh("box.obj", R"(<transform name="toWorld"><translate value="0.7, 0.5, 0"/></transform>
                     <medium type="heterogeneous" name="interior"><string name="filename" value="blob.vol"/>
                     <float name="scale" value="4"/><color name="albedo" value="0.9, 0.8, 0.7"/>
                     <transform name="toWorld"><translate value="0.2, 0, -0.5"/></transform>
                     <phase type="hg"><float name="g" value="-0.7"/></phase></medium>)");
    scene.regions = {
        {"homogeneous", 4, 10, 8, 10}, {"heterogeneous", 19, 10, 8, 10}, {"floor", 0, 24, 32, 8}};
    const auto volpath = [](const std::string &transmittance, size_t spp) {
        return Estimator{"volpath/" + transmittance,
                         fmt::format(R"(<integrator type="volpath"><string name="transmittance"
                             value="{}"/>{}</integrator>)",
                                     transmittance,
                                     transmittance == "raymarch"
                                         ? R"(<float name="stepSize" value="0.01"/>)"
                                         : ""),
                         "independent",
                         "",
                         spp,
                         ""};
    };
    Estimator sobol = volpath("ratio", 256);
    sobol.label = "volpath+sobol";
    sobol.sampler = "sobol";
    scene.estimators = {volpath("ratio", 256), volpath("delta", 256), volpath("raymarch", 256),
                        sobol};
    return scene;
}

/// A small box mesh placed nine times as instances (tmesh) on a floor.
AgreementScene instances() {
    AgreementScene scene;
    scene.name = "instances";
    scene.files["floor.obj"] = textFile(floorOBJ(3.0f));
    scene.files["box.obj"] =
        textFile(boxOBJ(Vector3f(-0.2f, 0, -0.2f), Vector3f(0.2f, 0.5f, 0.2f)));
    scene.files["light.obj"] =
        textFile(quadOBJ({-0.8f, 2.5f, -0.8f}, Vector3f(1.6f, 0, 0), Vector3f(0, 0, 1.6f)));
    std::string copies;
    for (int i = 0; i < 9; ++i) {
        const int column = i % 3 - 1, row = i / 3 - 1; // a 3×3 grid
        copies +=
            fmt::format(R"(<mesh type="tmesh"><transform name="toWorld">
            <rotate axis="0, 1, 0" angle="{}"/><translate value="{}, 0, {}"/></transform></mesh>)",
                        20 * i, 0.7f * static_cast<float>(column), 0.7f * static_cast<float>(row));
    }
    scene.body = perspective("0, 2.5, 3", "0, 0, 0", 45, 32) + mesh("floor.obj", diffuse("0.6")) +
                 mesh("light.obj", diffuse("0") + areaLight("5")) +
                 mesh("box.obj", diffuse("0.3, 0.5, 0.7") +
                                     R"(<boolean name="visible" value="false"/>)" + copies);
    scene.regions = {{"centre", 10, 10, 12, 12}};
    scene.estimators = {pathTracer("path_mis", 256), pathTracer("path_ems", 256),
                        pathTracer("path_mats", 512), lightTracer(256), bidirectional(128)};
    return scene;
}

/// Three Disney spheres (Burley's defaults; a rough anisotropic metal; sheen, clearcoat
/// and subsurface) on a floor under a square light.
AgreementScene disney() {
    AgreementScene scene;
    scene.name = "disney";
    scene.files["floor.obj"] = textFile(floorOBJ(3.0f));
    scene.files["light.obj"] =
        textFile(quadOBJ({-1.0f, 2.5f, -0.5f}, Vector3f(2.0f, 0, 0), Vector3f(0, 0, 1.0f)));
    scene.body = perspective("0, 1.2, 4", "0, 0.4, 0", 40, 32) + mesh("floor.obj", diffuse("0.5")) +
                 mesh("light.obj", diffuse("0") + areaLight("4")) +
                 sphere("-1.1, 0.5, 0", 0.5f, R"(<bsdf type="disney"/>)") +
                 sphere("0, 0.5, 0", 0.5f,
                        R"(<bsdf type="disney"><color name="baseColor" value="0.9, 0.6, 0.3"/>
            <float name="metallic" value="1"/><float name="roughness" value="0.3"/>
            <float name="anisotropic" value="0.6"/></bsdf>)") +
                 sphere("1.1, 0.5, 0", 0.5f,
                        R"(<bsdf type="disney"><color name="baseColor" value="0.2, 0.4, 0.8"/>
            <float name="roughness" value="0.6"/><float name="sheen" value="1"/>
            <float name="clearcoat" value="1"/><float name="clearcoatGloss" value="0.7"/>
            <float name="subsurface" value="0.5"/></bsdf>)");
    scene.regions = {{"default", 1, 9, 7, 9}, {"metal", 12, 9, 8, 9}, {"coated", 24, 9, 7, 9}};
    // Not the light tracer: it sees the clearcoat's and the anisotropic metal's sharp
    // highlights only through rare connections of large value, so 16 batch means are far
    // from normal and the 4-standard-error rule does not hold for it. Measured (2026-12-04):
    // lighttracer − path_mis on the image +4.13 standard errors at 512 spp (seed 1), but
    // −2.43 at 8 times the samples (same seed, 0.42 % power) and −0.11 with seed 5; +0.92
    // and −0.62 at 512 spp with seeds 2 and 3 (nori-agreement --scene disney --estimator
    // path_mis --estimator lighttracer [--soak] --seed S, with lightTracer(512) added).
    scene.estimators = {pathTracer("path_mis", 512), pathTracer("path_ems", 512),
                        pathTracer("path_mats", 1024), bidirectional(256)};
    return scene;
}

/// Diffuse boxes at several depths seen through a thin lens or the double-Gauss lens.
AgreementScene lensCamera(bool realistic) {
    AgreementScene scene;
    scene.name = realistic ? "realistic-camera" : "thin-lens";
    scene.files["floor.obj"] = textFile(floorOBJ(5.0f));
    scene.files["box.obj"] =
        textFile(boxOBJ(Vector3f(-0.3f, 0, -0.3f), Vector3f(0.3f, 0.8f, 0.3f)));
    scene.files["light.obj"] =
        textFile(quadOBJ({-1.0f, 3.0f, -2.0f}, Vector3f(2.0f, 0, 0), Vector3f(0, 0, 3.0f)));
    scene.files["dgauss.dat"] = doubleGaussLens();
    const std::string lookAt =
        R"(<transform name="toWorld"><lookat origin="0, 1, 4" target="0, 0.4, 0" up="0, 1, 0"/></transform>)";
    const std::string camera =
        realistic
            ? fmt::format(R"(<camera type="realistic"><string name="lensFile" value="dgauss.dat"/>
                         <float name="apertureDiameter" value="12"/><float name="focusDistance" value="4"/>
                         <integer name="width" value="32"/><integer name="height" value="32"/>{}</camera>)",
                          lookAt)
            : perspective(
                  "0, 1, 4", "0, 0.4, 0", 40, 32,
                  R"(<float name="apertureRadius" value="0.1"/><float name="focalDistance" value="4"/>)");
    std::string boxes;
    for (int i = 0; i < 3; ++i)
        boxes +=
            mesh("box.obj", diffuse(i == 1 ? "0.7, 0.3, 0.2" : "0.3, 0.6, 0.3") +
                                fmt::format(R"(<transform name="toWorld">
                                         <translate value="{}, 0, {}"/></transform>)",
                                            0.9f * static_cast<float>(i - 1), 1.5f - 2.0f * i));
    scene.body = camera + mesh("floor.obj", diffuse("0.6")) +
                 mesh("light.obj", diffuse("0") + areaLight("3")) + boxes;
    scene.regions = {{"centre", 8, 8, 16, 16}};
    scene.estimators = {pathTracer("path_mis", 256), pathTracer("path_ems", 256),
                        pathTracer("path_mats", 512)};
    if (!realistic) // a realistic camera cannot be connected to
        scene.estimators.push_back(lightTracer(256));
    if (!realistic)
        scene.estimators.push_back(bidirectional(128));
    return scene;
}

} // namespace

std::vector<AgreementScene> agreementMatrixScenes() {
    return {cornellBox(),      glossyPlates(),   skyWithSun(), deltaLights(),
            texturedPlane(),   media(),          instances(),  disney(),
            lensCamera(false), lensCamera(true), shapeLights()};
}
std::vector<AgreementScene> integratorTestScenes(const std::string &integratorXML, bool withMedia,
                                                 const std::string &referenceType,
                                                 const std::string &referenceParameters,
                                                 bool courseScenes) {
    const Estimator reference = pathTracer(referenceType, 128, referenceParameters);
    const Estimator tested{"tested", integratorXML, "independent", "", 128, ""};
    std::vector<AgreementScene> scenes;

    // Two lights of very unequal power (a small bright sphere and a large dim quad): a
    // light-selection probability left out of a weight shows here, and not with one light.
    AgreementScene lights;
    lights.name = "unequal-lights";
    lights.files["floor.obj"] = textFile(floorOBJ(3.0f));
    lights.files["panel.obj"] =
        textFile(quadOBJ({-1.5f, 2.0f, -1.0f}, Vector3f(3.0f, 0, 0), Vector3f(0, 0, 2.0f)));
    lights.body = perspective("0, 1.5, 4", "0, 0.4, 0", 40, 32) +
                  mesh("floor.obj", diffuse("0.6")) +
                  mesh("panel.obj", diffuse("0") + areaLight("1")) +
                  sphere("1.2, 1.2, 0.5", 0.08f, areaLight("200")) +
                  sphere("-0.6, 0.5, 0", 0.5f, diffuse("0.7, 0.5, 0.3")) +
                  sphere("0.6, 0.4, -0.3", 0.4f, R"(<bsdf type="roughconductor">
                      <string name="material" value="Cu"/><float name="alpha" value="0.2"/></bsdf>)");
    lights.regions = {{"floor", 0, 24, 32, 8}, {"spheres", 6, 10, 20, 10}};
    scenes.push_back(lights);

    if (!courseScenes) {
        AgreementScene delta = deltaLights();
        delta.name = "spot-and-directional";
        scenes.push_back(delta);

        AgreementScene sky = skyWithSun();
        sky.name = "environment-map";
        sky.regions = {{"floor", 0, 24, 32, 8}, {"spheres", 8, 10, 16, 8}};
        scenes.push_back(sky);
    }

    AgreementScene glossy = glossyPlates();
    glossy.name = "glossy";
    scenes.push_back(glossy);

    // Specular chains: a glass and a mirror sphere under a light.
    AgreementScene specular;
    specular.name = "specular";
    specular.files["floor.obj"] = textFile(floorOBJ(3.0f));
    specular.files["light.obj"] =
        textFile(quadOBJ({-0.8f, 2.5f, -0.8f}, Vector3f(1.6f, 0, 0), Vector3f(0, 0, 1.6f)));
    specular.body = perspective("0, 1.5, 4", "0, 0.4, 0", 40, 32) +
                    mesh("floor.obj", diffuse("0.6")) +
                    mesh("light.obj", diffuse("0") + areaLight("5")) +
                    sphere("-0.6, 0.5, 0", 0.5f, R"(<bsdf type="dielectric"/>)") +
                    sphere("0.6, 0.5, 0", 0.5f, R"(<bsdf type="mirror"/>)");
    specular.regions = {
        {"floor", 0, 24, 32, 8}, {"glass", 4, 10, 10, 10}, {"mirror", 18, 10, 10, 10}};
    specular.specularInView = true;
    scenes.push_back(specular);

    for (AgreementScene &scene : scenes)
        scene.estimators = {reference, tested};

    if (withMedia) {
        // Against volpath (ratio tracking), the matrix's reference on this scene.
        AgreementScene volumes = media();
        Estimator volpath = volumes.estimators.front();
        volpath.label = "volpath";
        volpath.samplesPerPixel = 128;
        volumes.estimators = {volpath, tested};
        scenes.push_back(volumes);
    }
    return scenes;
}

} // namespace nori
