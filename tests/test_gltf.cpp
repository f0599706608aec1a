// glTF 2.0 assets (gltffile.h and the `gltf` shape): assets written here by hand — as
// .gltf with an embedded or external buffer and as .glb — read to the same triangles,
// placed by their node transforms; their materials, textures, emission and alpha mapped
// onto our plugins (checked against the same plugins written in XML, and by renders);
// what they hold that is not rendered, named; malformed ones, errors naming the file.
#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/frame.h>
#include <nori/gltffile.h>
#include <nori/mesh.h>
#include <nori/render.h>
#include <nori/scene.h>

#include "testutil.h"

#include <catch2/catch.hpp>
#include <stb_image_write.h>

#include <cstring>

using namespace nori;
using namespace nori::testing;
using Catch::Contains;

namespace {

/// A glTF asset built by hand: a binary buffer of accessors and the JSON around it.
class AssetWriter {
public:
    /// Appends `bytes` as a buffer view (4-byte aligned); returns its index.
    int view(const std::string &bytes, int stride = 0) {
        while (m_bin.size() % 4 != 0)
            m_bin.push_back('\0');
        m_views.push_back(fmt::format(R"({{"buffer":0,"byteOffset":{},"byteLength":{}{}}})",
                                      m_bin.size(), bytes.size(),
                                      stride ? fmt::format(R"(,"byteStride":{})", stride) : ""));
        m_bin += bytes;
        return int(m_views.size()) - 1;
    }
    /// An accessor over a new view of `values`; returns its index.
    template <typename T>
    int accessor(const std::vector<T> &values, int componentType, const char *type, int count,
                 const std::string &extra = "") {
        std::string bytes(values.size() * sizeof(T), '\0');
        std::memcpy(bytes.data(), values.data(), bytes.size());
        const int index = view(bytes);
        return rawAccessor(
            fmt::format(R"("bufferView":{},"componentType":{},"count":{},"type":"{}"{})", index,
                        componentType, count, type, extra));
    }
    int rawView(const std::string &fields) {
        m_views.push_back("{" + fields + "}");
        return int(m_views.size()) - 1;
    }
    int rawAccessor(const std::string &fields) {
        m_accessors.push_back("{" + fields + "}");
        return int(m_accessors.size()) - 1;
    }
    int floats(const std::vector<float> &values, const char *type, int components) {
        return accessor(values, 5126, type, int(values.size()) / components);
    }
    /// The JSON of the asset with `rest` (meshes, nodes, …) and the buffer at `uri`
    /// ("" for a GLB's own buffer).
    std::string json(const std::string &rest, const std::string &uri) const {
        return fmt::format(
            R"({{"asset":{{"version":"2.0"}},"buffers":[{{"byteLength":{}{}}}],"bufferViews":[{}],"accessors":[{}]{}}})",
            m_bin.size(), uri.empty() ? "" : fmt::format(R"(,"uri":"{}")", uri),
            fmt::join(m_views, ","), fmt::join(m_accessors, ","), rest.empty() ? "" : "," + rest);
    }
    /// A .gltf with the buffer embedded as a base64 data URI.
    std::string embedded(const std::string &rest) const {
        return json(rest, "data:application/octet-stream;base64," + base64(m_bin));
    }
    /// A .glb: the JSON chunk and the binary chunk, each padded to 4 bytes.
    std::string glb(const std::string &rest) const {
        std::string text = json(rest, "");
        while (text.size() % 4 != 0)
            text.push_back(' ');
        std::string bin = m_bin;
        while (bin.size() % 4 != 0)
            bin.push_back('\0');
        std::string out = "glTF";
        const auto u32 = [&](uint32_t value) {
            out.append(reinterpret_cast<const char *>(&value), 4);
        };
        u32(2);
        u32(uint32_t(12 + 8 + text.size() + 8 + bin.size()));
        u32(uint32_t(text.size()));
        out += "JSON";
        out += text;
        u32(uint32_t(bin.size()));
        out.append("BIN\0", 4);
        out += bin;
        return out;
    }
    const std::string &bin() const { return m_bin; }

private:
    static std::string base64(const std::string &bytes) {
        static const char *kAlphabet =
            "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        std::string out;
        for (size_t i = 0; i < bytes.size(); i += 3) {
            uint32_t chunk = uint32_t(uint8_t(bytes[i])) << 16;
            if (i + 1 < bytes.size())
                chunk |= uint32_t(uint8_t(bytes[i + 1])) << 8;
            if (i + 2 < bytes.size())
                chunk |= uint32_t(uint8_t(bytes[i + 2]));
            out += kAlphabet[(chunk >> 18) & 63];
            out += kAlphabet[(chunk >> 12) & 63];
            out += i + 1 < bytes.size() ? kAlphabet[(chunk >> 6) & 63] : '=';
            out += i + 2 < bytes.size() ? kAlphabet[chunk & 63] : '=';
        }
        return out;
    }

    std::string m_bin;
    std::vector<std::string> m_views, m_accessors;
};

/// The unit quad [−1, 1]² at z = 0 facing +z, uv (glTF's, origin top-left) (0, 0) at its
/// top-left corner (−1, 1): POSITION, NORMAL and TEXCOORD_0 accessors 0–2, indices 3.
AssetWriter quadAsset() {
    AssetWriter asset;
    asset.floats({-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0}, "VEC3", 3);
    asset.floats({0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1}, "VEC3", 3);
    asset.floats({0, 1, 1, 1, 1, 0, 0, 0}, "VEC2", 2);
    asset.accessor(std::vector<uint16_t>{0, 1, 2, 0, 2, 3}, 5123, "SCALAR", 6);
    return asset;
}

/// Meshes and nodes placing the quad once (with `material`, −1 for none) at the root.
std::string quadScene(int material, const std::string &node = "") {
    return fmt::format(
        R"("meshes":[{{"name":"quad","primitives":[{{"attributes":{{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2}},"indices":3{}}}]}}],"nodes":[{{"mesh":0{}}}],"scenes":[{{"nodes":[0]}}],"scene":0)",
        material >= 0 ? fmt::format(R"(,"material":{})", material) : "", node);
}

/// A PNG of `width` × `height` RGBA pixels.
std::string pngBytes(int width, int height, const std::vector<uint8_t> &rgba) {
    std::string bytes;
    stbi_write_png_to_func(
        [](void *context, void *data, int size) {
            static_cast<std::string *>(context)->append(static_cast<const char *>(data),
                                                        size_t(size));
        },
        &bytes, width, height, 4, rgba.data(), width * 4);
    return bytes;
}

/// A scene of `meshes` seen by a camera at z = 1 looking down −z with a 90° field of
/// view, so that the quad fills a square image exactly (its top-left corner top-left).
std::string frontView(const std::string &meshes, const std::string &integrator = "path_mis",
                      int size = 2, int spp = 4) {
    return fmt::format(R"(<scene>
    <integrator type="{}"/>
    <sampler type="independent"><integer name="sampleCount" value="{}"/></sampler>
    <camera type="perspective"><float name="fov" value="90"/>
        <integer name="width" value="{}"/><integer name="height" value="{}"/>
        <rfilter type="box"/>
        <transform name="toWorld"><lookat origin="0,0,1" target="0,0,0" up="0,1,0"/></transform>
    </camera>
    {}
</scene>)",
                       integrator, spp, size, size, meshes);
}

/// The front view of the asset `file` in `folder`, the gltf shape given `parameters`.
std::shared_ptr<Scene> gltfScene(const TempDir &folder, const std::string &file,
                                 const std::string &parameters = "") {
    return loadScene(
        frontView(fmt::format(R"(<mesh type="gltf"><string name="filename" value="{}"/>{}</mesh>)",
                              file, parameters)),
        folder.path().string());
}

const Mesh &onlyPart(const Scene &scene) {
    REQUIRE(scene.getShapes().size() == 1);
    const auto *mesh = dynamic_cast<const Mesh *>(scene.getShapes().front().get());
    REQUIRE(mesh != nullptr);
    return *mesh;
}

} // namespace

TEST_CASE("A glTF asset reads the same as .gltf (embedded or external buffer) and .glb",
          "[shape][gltf]") {
    TempDir folder;
    const AssetWriter asset = quadAsset();
    // A parent node (translate 1, 2, 3; 90° about z; scale 2) with the quad on a child
    // node one unit up its z axis.
    const std::string nodes =
        R"("meshes":[{"name":"quad","primitives":[{"attributes":{"POSITION":0,"NORMAL":1,"TEXCOORD_0":2},"indices":3}]}],"nodes":[{"name":"parent","translation":[1,2,3],"rotation":[0,0,0.70710678,0.70710678],"scale":[2,2,2],"children":[1]},{"mesh":0,"translation":[0,0,1]}],"scenes":[{"nodes":[0]}])";
    folder.write("embedded.gltf", asset.embedded(nodes));
    folder.write("external.gltf", asset.json(nodes, "quad.bin"));
    folder.write("quad.bin", asset.bin());
    folder.write("binary.glb", asset.glb(nodes));
    std::vector<GltfAsset> read;
    for (const char *name : {"embedded.gltf", "external.gltf", "binary.glb"}) {
        INFO(name);
        read.push_back(readGltf((folder.path() / name).string()));
        const GltfAsset &gltf = read.back();
        REQUIRE(gltf.primitives.size() == 1);
        const GltfPrimitive &quad = gltf.primitives.front();
        CHECK(quad.name == "quad[0]");
        CHECK(quad.mesh.triangles.size() == 2);
        CHECK(quad.mesh.normals.size() == 4);
        // glTF's uv (0, 0) at the top-left corner is (0, 1) in OBJ's convention.
        CHECK(quad.mesh.texCoords[3].isApprox(Point2f(0.0f, 1.0f)));
        // The child's origin: parent · (0, 0, 1) = translate + R(scale · (0, 0, 1)).
        CHECK((quad.toWorld * Point3f(0, 0, 0)).isApprox(Point3f(1, 2, 5), 1e-5f));
        // (1, 0, 0) scaled to (2, 0, 0), turned to (0, 2, 0), moved: (1, 4, 5).
        CHECK((quad.toWorld * Point3f(1, 0, 0)).isApprox(Point3f(1, 4, 5), 1e-5f));
        CHECK(gltf.dropped.empty());
    }
    for (size_t i = 1; i < read.size(); ++i) {
        CHECK(read[i].primitives[0].mesh.positions == read[0].primitives[0].mesh.positions);
        CHECK(read[i].primitives[0].mesh.triangles == read[0].primitives[0].mesh.triangles);
    }
}

TEST_CASE("glTF primitives: strips, fans, index types, sparse and quantised accessors",
          "[shape][gltf]") {
    TempDir folder;
    AssetWriter asset;
    asset.floats({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0}, "VEC3", 3);        // 0
    asset.accessor(std::vector<uint8_t>{0, 1, 2, 3}, 5121, "SCALAR", 4);  // 1
    asset.accessor(std::vector<uint32_t>{0, 1, 3, 2}, 5125, "SCALAR", 4); // 2
    // A sparse POSITION: the four vertices above with vertex 2 moved to (5, 5, 5).
    const int sparseIndices = asset.view(std::string("\x02\x00", 2));
    std::string moved(12, '\0');
    const float five[3] = {5, 5, 5};
    std::memcpy(moved.data(), five, 12);
    const int sparseValues = asset.view(moved);
    asset.rawAccessor(fmt::format(
        R"("bufferView":0,"componentType":5126,"count":4,"type":"VEC3","sparse":{{"count":1,"indices":{{"bufferView":{},"componentType":5123}},"values":{{"bufferView":{}}}}})",
        sparseIndices, sparseValues)); // 3
    // KHR_mesh_quantization: positions as normalised unsigned shorts.
    asset.accessor(std::vector<uint16_t>{0, 0, 0, 65535, 0, 0, 0, 65535, 0}, 5123, "VEC3", 3,
                   R"(,"normalized":true)"); // 4
    const std::string rest =
        R"("extensionsUsed":["KHR_mesh_quantization"],"meshes":[{"name":"m","primitives":[
        {"attributes":{"POSITION":0},"indices":1,"mode":5},
        {"attributes":{"POSITION":0},"indices":2,"mode":6},
        {"attributes":{"POSITION":3},"mode":5},
        {"attributes":{"POSITION":4}},
        {"attributes":{"POSITION":0},"mode":1}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])";
    const GltfAsset gltf = readGltf(folder.write("modes.gltf", asset.embedded(rest)));
    REQUIRE(gltf.primitives.size() == 4);
    // Strip 0 1 2 3: (0, 1, 2), then (1, 3, 2): every other one turned so both face +z.
    CHECK(gltf.primitives[0].mesh.triangles == std::vector<Vector3i>{{0, 1, 2}, {1, 3, 2}});
    // Fan over 0 1 3 2: (1, 3, 0), (3, 2, 0).
    CHECK(gltf.primitives[1].mesh.triangles == std::vector<Vector3i>{{1, 3, 0}, {3, 2, 0}});
    CHECK(gltf.primitives[2].mesh.positions[2].isApprox(Point3f(5, 5, 5)));
    CHECK(gltf.primitives[2].mesh.positions[1].isApprox(Point3f(1, 0, 0)));
    CHECK(gltf.primitives[2].mesh.triangles.size() == 2); // a strip of 4 vertices, no indices
    CHECK(gltf.primitives[3].mesh.positions[1].isApprox(Point3f(1, 0, 0)));
    // The line primitive is named among what is not rendered.
    CHECK(std::find(gltf.dropped.begin(), gltf.dropped.end(), "points and lines of mesh 'm'") !=
          gltf.dropped.end());
}

TEST_CASE("glTF materials become the disney BSDF the same parameters give in XML",
          "[shape][gltf][bsdf]") {
    TempDir folder;
    AssetWriter asset = quadAsset();
    // A 1×1 metallicRoughness image: roughness (G) 128, metallic (B) 64.
    const std::string png = pngBytes(1, 1, {0, 128, 64, 255});
    const int imageView = asset.view(png);
    const std::string materials = fmt::format(
        R"("materials":[
        {{"name":"plain","pbrMetallicRoughness":{{"baseColorFactor":[0.8,0.3,0.2,1],"metallicFactor":0.25,"roughnessFactor":0.4}}}},
        {{"name":"textured","pbrMetallicRoughness":{{"metallicFactor":0.5,"roughnessFactor":0.9,"metallicRoughnessTexture":{{"index":0}}}}}},
        {{"name":"both sides","doubleSided":true,"pbrMetallicRoughness":{{"baseColorFactor":[0.8,0.3,0.2,1],"metallicFactor":0.25,"roughnessFactor":0.4}}}}],
        "images":[{{"bufferView":{},"mimeType":"image/png"}}],"textures":[{{"source":0}}])",
        imageView);
    const auto bsdfOf = [&](int material) {
        folder.write("m.glb", asset.glb(quadScene(material) + "," + materials));
        return onlyPart(*gltfScene(folder, "m.glb")).getBSDFPtr();
    };
    const auto disney = [&](const std::string &parameters) {
        const auto scene = loadScene(frontView(fmt::format(
            R"(<mesh type="rectangle"><bsdf type="disney"><float name="specular" value="0.5"/>{}</bsdf></mesh>)",
            parameters)));
        return scene->getShapes().front()->getBSDFPtr();
    };
    const auto compare = [](const BSDF &gltf, const BSDF &xml, bool backToo) {
        for (float theta : {10.0f, 40.0f, 75.0f})
            for (float thetaOut : {0.0f, 30.0f, 60.0f}) {
                BSDFQueryRecord rec(incidentDirection(theta), incidentDirection(thetaOut, 2.0f),
                                    ESolidAngle);
                rec.uv = Point2f(0.3f, 0.6f);
                CAPTURE(theta, thetaOut);
                const Color3f expected = xml.eval(rec);
                CHECK(gltf.eval(rec).isApprox(expected, 1e-5f));
                CHECK(gltf.pdf(rec) == Approx(xml.pdf(rec)).epsilon(1e-5));
                BSDFQueryRecord back(-rec.wi, -rec.wo, ESolidAngle);
                back.uv = rec.uv;
                if (backToo) // twosided: the back reflects as the front
                    CHECK(gltf.eval(back).isApprox(expected, 1e-5f));
                else
                    CHECK(gltf.eval(back).isZero());
            }
    };
    const std::string plain = R"(<color name="baseColor" value="0.8, 0.3, 0.2"/>
        <float name="metallic" value="0.25"/><float name="roughness" value="0.4"/>)";
    compare(*bsdfOf(0), *disney(plain), false);
    compare(*bsdfOf(1),
            *disney(fmt::format(R"(<color name="baseColor" value="1"/>
        <float name="metallic" value="{}"/><float name="roughness" value="{}"/>)",
                                0.5f * 64.0f / 255.0f, 0.9f * 128.0f / 255.0f)),
            false);
    compare(*bsdfOf(2), *disney(plain), true);
    // No material: glTF's default (white, metallic 1, roughness 1).
    compare(*bsdfOf(-1), *disney(R"(<color name="baseColor" value="1"/>
        <float name="metallic" value="1"/><float name="roughness" value="1"/>)"),
            false);
}

TEST_CASE("glTF emission is an area light, its textures keep their orientation and sRGB",
          "[shape][gltf][render]") {
    TempDir folder;
    AssetWriter asset = quadAsset();
    // 2×2 texels: red, green / blue, white (top row first, as glTF's uv (0, 0) is top-left).
    const std::string png =
        pngBytes(2, 2, {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255});
    const int imageView = asset.view(png);
    const std::string rest =
        quadScene(0) + fmt::format(R"(,"materials":[{{"emissiveFactor":[1,0.5,0.25],
        "emissiveTexture":{{"index":0}},"extensions":{{"KHR_materials_emissive_strength":{{"emissiveStrength":4}}}},
        "pbrMetallicRoughness":{{"baseColorFactor":[0,0,0,1]}}}}],
        "extensionsUsed":["KHR_materials_emissive_strength"],
        "images":[{{"bufferView":{}}}],"samplers":[{{"magFilter":9728,"minFilter":9728}}],
        "textures":[{{"source":0,"sampler":0}}])",
                                   imageView);
    folder.write("light.glb", asset.glb(rest));
    const auto scene = gltfScene(folder, "light.glb");
    REQUIRE(scene->getEmitters().size() == 1);
    const Bitmap image = renderScene(*scene, quietOptions(2)).image;
    // Each pixel sees one texel (nearest) through a black, non-reflecting surface: its
    // emission exactly, factor × strength.
    const Color3f scale(4.0f, 2.0f, 1.0f);
    CHECK(image(0, 0).isApprox(Color3f(1, 0, 0) * scale, 1e-4f));
    CHECK(image(0, 1).isApprox(Color3f(0, 1, 0) * scale, 1e-4f));
    CHECK(image(1, 0).isApprox(Color3f(0, 0, 1) * scale, 1e-4f));
    CHECK(image(1, 1).isApprox(Color3f(1, 1, 1) * scale, 1e-4f));
    // emissionScale 0 turns the light off.
    const auto dark = gltfScene(folder, "light.glb", R"(<float name="emissionScale" value="0"/>)");
    CHECK(dark->getEmitters().empty());
}

TEST_CASE("glTF alpha: MASK cuts at alphaCutoff, BLEND is the alpha itself",
          "[shape][gltf][alpha]") {
    TempDir folder;
    AssetWriter asset = quadAsset();
    // Alphas 255, 0 / 255, 128 (top row first).
    const std::string png =
        pngBytes(2, 2, {10, 20, 30, 255, 10, 20, 30, 0, 10, 20, 30, 255, 10, 20, 30, 128});
    const int imageView = asset.view(png);
    const auto opacityOf = [&](const std::string &mode) {
        const std::string rest =
            quadScene(0) + fmt::format(R"(,"materials":[{{{},"pbrMetallicRoughness":{{
            "baseColorTexture":{{"index":0}}}}}}],"images":[{{"bufferView":{}}}],
            "samplers":[{{"magFilter":9728}}],"textures":[{{"source":0,"sampler":0}}])",
                                       mode, imageView);
        folder.write("alpha.glb", asset.glb(rest));
        const auto scene = gltfScene(folder, "alpha.glb");
        const Mesh &mesh = onlyPart(*scene);
        std::vector<float> opacity;
        // Texel centres in our uv (origin bottom-left): top-left, top-right, bottom-left,
        // bottom-right.
        for (const Point2f &uv : {Point2f(0.25f, 0.75f), Point2f(0.75f, 0.75f),
                                  Point2f(0.25f, 0.25f), Point2f(0.75f, 0.25f)})
            opacity.push_back(mesh.getOpacity() ? mesh.getOpacity()->opacityAt(uv, Point3f(0, 0, 0))
                                                : 1.0f);
        return opacity;
    };
    CHECK(opacityOf(R"("alphaMode":"OPAQUE")") == std::vector<float>{1, 1, 1, 1});
    CHECK(opacityOf(R"("alphaMode":"MASK","alphaCutoff":0.6)") == std::vector<float>{1, 0, 1, 0});
    CHECK(opacityOf(R"("alphaMode":"MASK","alphaCutoff":0.4)") == std::vector<float>{1, 0, 1, 1});
    const std::vector<float> blend = opacityOf(R"("alphaMode":"BLEND")");
    CHECK(blend[0] == 1.0f);
    CHECK(blend[1] == 0.0f);
    CHECK(blend[3] == Approx(128.0f / 255.0f));
}

TEST_CASE("A glTF mesh renders bit for bit as the same mesh and material in XML",
          "[shape][gltf][render]") {
    TempDir folder;
    const AssetWriter asset = quadAsset();
    const std::string material =
        R"("materials":[{"pbrMetallicRoughness":{"baseColorFactor":[0.7,0.6,0.5,1],"metallicFactor":0,"roughnessFactor":0.5}}])";
    // The quad moved back by its node, lit by a point light off its axis.
    folder.write("quad.gltf",
                 asset.embedded(quadScene(0, R"(,"translation":[0,0,-0.5])") + "," + material));
    const char *light = R"(<emitter type="point"><point name="position" value="0.5,0.5,2"/>
        <color name="power" value="20"/></emitter>)";
    const auto render = [&](const std::string &mesh) {
        const auto scene =
            loadScene(frontView(mesh + light, "path_mis", 16, 4), folder.path().string());
        return renderScene(*scene, quietOptions(2)).image;
    };
    const Bitmap gltf =
        render(R"(<mesh type="gltf"><string name="filename" value="quad.gltf"/></mesh>)");
    // The same quad as an OBJ (uv in OBJ's convention), moved alike.
    folder.write("quad.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                             "vt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1\nf 1/1/1 3/3/1 4/4/1\n");
    const Bitmap obj = render(R"(<mesh type="obj"><string name="filename" value="quad.obj"/>
        <transform name="toWorld"><translate value="0,0,-0.5"/></transform>
        <bsdf type="disney"><color name="baseColor" value="0.7, 0.6, 0.5"/>
            <float name="metallic" value="0"/><float name="roughness" value="0.5"/>
            <float name="specular" value="0.5"/></bsdf></mesh>)");
    CHECK(gltf(8, 8).getLuminance() > 0.0f);
    CHECK(identicalImages(gltf, obj));
}

TEST_CASE("What a glTF asset holds but does not render is named in a warning",
          "[shape][gltf][cli]") {
    TempDir folder;
    const AssetWriter asset = quadAsset();
    const std::string rest =
        quadScene(-1, R"(,"camera":0,"extensions":{"KHR_lights_punctual":{"light":0}})") +
        R"(,"cameras":[{"name":"Cam","type":"perspective","perspective":{"yfov":0.8,"znear":0.1}}],
        "animations":[{"name":"Spin","channels":[],"samplers":[]}],
        "extensionsUsed":["KHR_lights_punctual","KHR_materials_clearcoat"],
        "extensions":{"KHR_lights_punctual":{"lights":[{"type":"point"}]}})";
    folder.write("extras.gltf", asset.embedded(rest));
    const std::string scene = folder.write(
        "scene.xml",
        frontView(R"(<mesh type="gltf"><string name="filename" value="extras.gltf"/></mesh>)",
                  "normals", 4, 1));
    const ProcessResult result = runNori({"--no-progress", scene});
    INFO(result.output);
    CHECK(result.exitCode == 0);
    CHECK_THAT(result.output, Contains("Warning: glTF file") && Contains("extras.gltf") &&
                                  Contains("camera 'Cam'") && Contains("animation 'Spin'") &&
                                  Contains("extension KHR_lights_punctual") &&
                                  Contains("extension KHR_materials_clearcoat"));
}

TEST_CASE("A malformed glTF file is an error naming the file and what is wrong",
          "[shape][gltf][errors]") {
    TempDir folder;
    const AssetWriter asset = quadAsset();
    const std::string mesh =
        R"("meshes":[{"name":"quad","primitives":[{"attributes":{"POSITION":%P},"indices":%I}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])";
    const auto withMesh = [&](const std::string &position, const std::string &indices,
                              const std::string &more = "") {
        std::string text = mesh;
        text.replace(text.find("%P"), 2, position);
        text.replace(text.find("%I"), 2, indices);
        return asset.embedded(text + more);
    };
    // An index accessor over the positions' view: 48 bytes as 24 ushorts, names vertex 0x3f80.
    AssetWriter wrongIndex = quadAsset();
    wrongIndex.rawAccessor(R"("bufferView":0,"componentType":5123,"count":24,"type":"SCALAR")");
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"{ not json", "cannot be read"},
        {withMesh("0", "9"), "accessor out of bounds"}, // tinygltf's own check
        {withMesh("2", "3"), "has quad[0]'s POSITION with 2 components per element, not 3"},
        {asset.json(
             R"("meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"nodes":[{"mesh":0}])",
             "missing.bin"),
         "cannot be read"},
        {withMesh("0", "3", R"(,"extensionsRequired":["KHR_draco_mesh_compression"])"),
         "requires the extension KHR_draco_mesh_compression"},
        {wrongIndex.embedded(
             R"("meshes":[{"name":"quad","primitives":[{"attributes":{"POSITION":0},"indices":4}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])"),
         "beyond its 4 vertices"},
        {asset.embedded(
             R"("meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":3}]}],"nodes":[{"mesh":0,"children":[1]},{"children":[0]}],"scenes":[{"nodes":[0]}])"),
         "has a cycle of nodes"},
        {asset.embedded(R"("nodes":[{}],"scenes":[{"nodes":[0]}])"), "has no triangles"},
    };
    for (size_t i = 0; i < cases.size(); ++i) {
        const std::string path = folder.write(fmt::format("bad{}.gltf", i), cases[i].first);
        INFO(cases[i].first);
        CHECK_THAT(errorOf([&] { readGltf(path); }), Contains(path) && Contains(cases[i].second));
    }
    // An accessor reaching past its buffer view, in a GLB.
    AssetWriter shortView;
    shortView.floats({0, 0, 0, 1, 0, 0}, "VEC3", 3);
    shortView.rawAccessor(R"("bufferView":0,"componentType":5126,"count":3,"type":"VEC3")");
    const std::string path = folder.write(
        "short.glb",
        shortView.glb(
            R"("meshes":[{"name":"m","primitives":[{"attributes":{"POSITION":1}}]}],"nodes":[{"mesh":0}],"scenes":[{"nodes":[0]}])"));
    CHECK_THAT(errorOf([&] { readGltf(path); }),
               Contains("short.glb") &&
                   Contains("3 elements reaching beyond its buffer view of 24 bytes"));
    // An image in a buffer view past the end of its buffer (tinygltf hands such bytes to
    // the image callback unchecked).
    AssetWriter farImage = quadAsset();
    const int farView = farImage.rawView(R"("buffer":0,"byteOffset":100000,"byteLength":12)");
    const std::string farPath = folder.write(
        "far-image.gltf",
        farImage.embedded(
            quadScene(0) +
            fmt::format(
                R"(,"materials":[{{"pbrMetallicRoughness":{{"baseColorTexture":{{"index":0}}}}}}],
        "images":[{{"bufferView":{},"mimeType":"image/png"}}],"textures":[{{"source":0}}])",
                farView)));
    CHECK_THAT(errorOf([&] { readGltf(farPath); }),
               Contains("far-image.gltf") &&
                   Contains(fmt::format("has buffer view {} (bytes 100000 to 100012) beyond its "
                                        "buffer of {} bytes",
                                        farView, farImage.bin().size())));
    // Truncated GLB.
    const std::string glb = quadAsset().glb(quadScene(-1));
    const std::string truncated = folder.write("truncated.glb", glb.substr(0, glb.size() / 2));
    CHECK_THAT(errorOf([&] { readGltf(truncated); }), Contains("truncated.glb"));
}
