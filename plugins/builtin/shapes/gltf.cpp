/*
 * gltf — the surfaces of a glTF 2.0 asset (.gltf or .glb, read by gltffile.h): every
 * triangle primitive of its default scene, placed by its nodes' transforms and then by
 * `toWorld`, each a mesh of its own with its material mapped onto ours.
 *
 * The mapping:
 *   - metallic-roughness (glTF 2.0 §3.9.2) onto `disney`: baseColor = baseColorFactor ×
 *     baseColorTexture (sRGB), metallic and roughness = their factors × the B and G
 *     channels of metallicRoughnessTexture, specular 0.5 (F0 = 0.04, glTF's dielectric
 *     reflectance). glTF's reference BRDF has a Lambertian base where Burley's diffuse
 *     lobe brightens at grazing angles: the one difference a side-by-side shows.
 *   - doubleSided materials wrapped in `twosided`;
 *   - normalTexture as the mesh's tangent-space normal map, its scale applied to x and y;
 *   - emissiveFactor × emissiveTexture × KHR_materials_emissive_strength × emissionScale
 *     as an `area` light on the primitive;
 *   - alphaMode MASK (opacity 1 where alpha ≥ alphaCutoff, else 0) and BLEND (opacity =
 *     alpha, stochastic as pbrt-v4's alpha) as the mesh's alpha mask, alpha being
 *     baseColorFactor's times the base colour image's (PNG alpha).
 * Textures follow their samplers' wrap modes (per axis) and magnification filter
 * (nearest, else trilinear MIP mapping) and KHR_texture_transform. What the asset holds
 * that is not rendered is named in one warning: cameras, animations, skins, morph
 * targets, vertex colours, occlusion maps, punctual lights, second uv sets and
 * extensions other than KHR_materials_emissive_strength, KHR_texture_transform and
 * KHR_mesh_quantization. An asset that needs Draco, meshopt or Basis decompression is an
 * error. A nested <bsdf> replaces every material's BSDF (alpha and emission stay).
 *
 * Parameters:
 *   filename       string     (required)  .gltf or .glb file, relative to the XML file
 *   toWorld        transform  identity    applied after the asset's node transforms
 *   emissionScale  float      1           scales the emission (0: no area lights)
 *   faceNormals    boolean    false       ignore the asset's vertex normals
 *
 *   <mesh type="gltf">
 *       <string name="filename" value="tests/data/meshes/quad.gltf"/>
 *   </mesh>
 */
#include <nori/bsdf.h>
#include <nori/emitter.h>
#include <nori/gltffile.h>
#include <nori/imagefile.h>
#include <nori/instance.h>
#include <nori/mesh.h>
#include <nori/mipmap.h>
#include <nori/proplist.h>
#include <nori/shading.h>
#include <nori/texture.h>

#include <cmath>
#include <iostream>
#include <map>

namespace nori {
namespace {

/// A texture slot of a glTF material: one channel of an image (or its colour) times a
/// factor, looked up through the sampler's wrap modes and KHR_texture_transform.
class GltfTexture : public Texture {
public:
    struct Options {
        int channel = -1; ///< −1: the colour; 0, 1, 2: that channel, as a grey
        Color3f factor = Color3f(1.0f);
        float cutoff = -1.0f;     ///< ≥ 0: 1 where the value reaches it, else 0 (MASK)
        float normalScale = 1.0f; ///< a normal map's xy scale (applied when ≠ 1)
        bool normalMap = false;
    };

    GltfTexture(std::shared_ptr<const MIPMap> image, const GltfTextureRef &ref,
                const Options &options)
        : m_image(std::move(image)), m_ref(ref), m_options(options) {
        const float c = std::cos(ref.rotation), s = std::sin(ref.rotation);
        // KHR_texture_transform: st = offset + R · (scale ⊙ uv), R a rotation by −rotation
        // as the extension writes it (x' = c·x + s·y, y' = −s·x + c·y).
        m_linear << c * ref.scale.x(), s * ref.scale.y(), -s * ref.scale.x(), c * ref.scale.y();
        m_uniformWrap = ref.wrapS == ref.wrapT;
    }

    Color3f eval(const TextureQuery &q) const override {
        Color3f value(1.0f);
        if (m_image) {
            // Our uv has OBJ's origin (bottom-left); glTF's uv, the image's st, the top-left.
            const Point2f gltfUV(q.uv.x(), 1.0f - q.uv.y());
            Point2f st = m_ref.offset + m_linear * gltfUV;
            const Vector2f dstdx = m_linear * Vector2f(q.dudx, -q.dvdx);
            const Vector2f dstdy = m_linear * Vector2f(q.dudy, -q.dvdy);
            MIPMap::Wrap wrap = toMIPMapWrap(m_ref.wrapS);
            if (!m_uniformWrap) { // wrap each axis here; the lookup then only clamps
                st = Point2f(wrapCoordinate(st.x(), m_ref.wrapS),
                             wrapCoordinate(st.y(), m_ref.wrapT));
                wrap = MIPMap::Wrap::Clamp;
            }
            value = m_ref.nearest ? m_image->nearest(st, wrap)
                                  : m_image->trilinear(st, dstdx, dstdy, wrap);
        }
        return finish(value);
    }

    float evalFloat(const TextureQuery &q) const override { return eval(q).r(); }

    Color3f average() const override {
        return finish(m_image ? m_image->average() : Color3f(1.0f));
    }

    float mipLevel(const TextureQuery &q) const override {
        if (!m_image || m_ref.nearest)
            return m_image ? 0.0f : -1.0f;
        return m_image->trilinearLevel(m_linear * Vector2f(q.dudx, -q.dvdx),
                                       m_linear * Vector2f(q.dudy, -q.dvdy));
    }

    bool usesFootprint() const override { return m_image && !m_ref.nearest; }
    bool isConstant() const override { return !m_image; }

    std::string toString() const override {
        return fmt::format("GltfTexture[image={}, channel={}, factor=({}, {}, {})]", m_ref.image,
                           m_options.channel, m_options.factor.r(), m_options.factor.g(),
                           m_options.factor.b());
    }

private:
    Color3f finish(Color3f value) const {
        if (m_options.channel >= 0)
            value = Color3f(value[m_options.channel]);
        value = value * m_options.factor;
        if (m_options.cutoff >= 0.0f)
            value = Color3f(value.r() >= m_options.cutoff ? 1.0f : 0.0f);
        if (m_options.normalMap && m_options.normalScale != 1.0f) {
            // Decoded n = 2c − 1; scale x and y, encode again.
            Color3f n = 2.0f * value - Color3f(1.0f);
            n.r() *= m_options.normalScale;
            n.g() *= m_options.normalScale;
            value = 0.5f * (n + Color3f(1.0f));
        }
        return value;
    }

    static MIPMap::Wrap toMIPMapWrap(GltfWrap wrap) {
        switch (wrap) {
        case GltfWrap::Clamp:
            return MIPMap::Wrap::Clamp;
        case GltfWrap::Mirror:
            return MIPMap::Wrap::Mirror;
        default:
            return MIPMap::Wrap::Repeat;
        }
    }

    static float wrapCoordinate(float x, GltfWrap wrap) {
        switch (wrap) {
        case GltfWrap::Clamp:
            return std::clamp(x, 0.0f, 1.0f);
        case GltfWrap::Mirror: {
            const float period = x - 2.0f * std::floor(0.5f * x); // in [0, 2)
            return period <= 1.0f ? period : 2.0f - period;
        }
        default:
            return x - std::floor(x);
        }
    }

    std::shared_ptr<const MIPMap> m_image; ///< nullptr: the factor alone
    GltfTextureRef m_ref;
    Options m_options;
    Eigen::Matrix2f m_linear;
    bool m_uniformWrap = true;
};

/// One primitive of the asset: a triangle mesh in world space with its surface maps.
class GltfPart : public Mesh {
public:
    GltfPart(GltfPrimitive &&primitive, const Transform &toWorld, const PropertyList &surface,
             bool faceNormals, const std::string &file) {
        m_name = fmt::format("{} {}", file, primitive.name);
        readSurfaceParameters(*this, surface);
        takeMeshData(std::move(primitive.mesh), faceNormals, false);
        finishLoading(toWorld * primitive.toWorld);
    }
};

class GltfShape : public CompoundShape {
public:
    explicit GltfShape(const PropertyList &props) {
        m_filename = props.getPath("filename");
        m_toWorld = props.getTransform("toWorld", Transform());
        m_emissionScale = props.getFloat("emissionScale", 1.0f);
        m_faceNormals = props.getBoolean("faceNormals", false);
        if (!(m_emissionScale >= 0.0f && std::isfinite(m_emissionScale)))
            throw NoriException("gltf: 'emissionScale' must be finite and ≥ 0, got {}",
                                m_emissionScale);
        m_asset = readGltf(m_filename);
        if (!m_asset.dropped.empty()) {
            std::string list;
            for (const std::string &what : m_asset.dropped)
                list += (list.empty() ? "" : ", ") + what;
            std::cerr << fmt::format("Warning: glTF file '{}': not rendered: {}\n", m_filename,
                                     list);
        }
    }

    void addChild(const std::shared_ptr<NoriObject> &child, const std::string &name) override {
        if (child->getClassType() != EBSDF) {
            NoriObject::addChild(child, name);
            return;
        }
        if (m_override)
            throw NoriException("gltf: takes only one <bsdf> (it replaces every material)");
        m_override = std::static_pointer_cast<BSDF>(child);
    }

    void activate() override {
        std::vector<std::shared_ptr<BSDF>> materials(m_asset.materials.size());
        std::shared_ptr<BSDF> defaultMaterial;
        for (GltfPrimitive &primitive : m_asset.primitives) {
            const int materialIndex = primitive.material;
            const GltfMaterial material =
                materialIndex >= 0 ? m_asset.materials[size_t(materialIndex)] : GltfMaterial();
            PropertyList surface;
            if (material.normalTexture.valid()) {
                GltfTexture::Options options;
                options.normalMap = true;
                options.normalScale = material.normalScale;
                surface.set("normal", texture(material.normalTexture, Encoding::Data, options));
            }
            if (auto opacity = alphaTexture(material))
                surface.set("alpha", opacity);
            auto part = std::make_shared<GltfPart>(std::move(primitive), m_toWorld, surface,
                                                   m_faceNormals, m_filename);
            std::shared_ptr<BSDF> bsdf = m_override;
            if (!bsdf) {
                std::shared_ptr<BSDF> &slot =
                    materialIndex >= 0 ? materials[size_t(materialIndex)] : defaultMaterial;
                if (!slot)
                    slot = makeBSDF(material);
                bsdf = slot;
            }
            attach(*part, bsdf);
            if (auto light = makeLight(material))
                attach(*part, light);
            part->activate();
            m_parts.push_back(std::move(part));
        }
        m_asset = GltfAsset(); // the parts own their arrays now; images are decoded
        m_images.clear();
    }

    const std::vector<std::shared_ptr<Shape>> &parts() const override { return m_parts; }

    std::string toString() const override {
        return fmt::format("GltfShape[filename=\"{}\", {} parts]", m_filename, m_parts.size());
    }

private:
    enum class Encoding { Color, Data, Alpha };

    /// Adds `child` to `parent` as the XML parser does.
    static void attach(NoriObject &parent, const std::shared_ptr<NoriObject> &child) {
        parent.addChild(child, "");
        child->setParent(&parent);
    }

    static std::shared_ptr<NoriObject>
    create(const std::string &plugin, NoriObject::EClassType type, const PropertyList &props) {
        return NoriObjectFactory::createInstance(plugin, type, props);
    }

    /// The decoded image `index` in an encoding: sRGB colour decoded to linear, data as
    /// stored, or the alpha channel (nullptr when the image has none). Once per asset.
    std::shared_ptr<const MIPMap> image(int index, Encoding encoding) {
        const auto key = std::make_pair(index, encoding);
        if (const auto it = m_images.find(key); it != m_images.end())
            return it->second;
        const GltfImage &source = m_asset.images[size_t(index)];
        const std::string name = fmt::format("{} ({})", source.name, m_filename);
        ImageFile file = decodeImageFile(source.bytes, name);
        std::shared_ptr<const MIPMap> mipmap;
        if (encoding == Encoding::Alpha) {
            if (file.alpha.size() > 0)
                mipmap = std::make_shared<MIPMap>(std::move(file.alpha));
        } else {
            if (encoding == Encoding::Color && file.integerEncoded)
                for (Eigen::Index y = 0; y < file.pixels.rows(); ++y)
                    for (Eigen::Index x = 0; x < file.pixels.cols(); ++x)
                        file.pixels(y, x) = file.pixels(y, x).toLinearRGB();
            mipmap = std::make_shared<MIPMap>(std::move(file.pixels));
        }
        m_images.emplace(key, mipmap);
        return mipmap;
    }

    std::shared_ptr<NoriObject> texture(const GltfTextureRef &ref, Encoding encoding,
                                        const GltfTexture::Options &options) {
        auto result = std::make_shared<GltfTexture>(
            ref.valid() ? image(ref.image, encoding) : nullptr, ref, options);
        result->activate();
        return result;
    }

    /// The opacity of a MASK or BLEND material, or nullptr for an opaque one.
    std::shared_ptr<NoriObject> alphaTexture(const GltfMaterial &material) {
        if (material.alphaMode == GltfMaterial::AlphaMode::Opaque)
            return nullptr;
        GltfTexture::Options options;
        options.factor = Color3f(material.baseAlphaFactor);
        if (material.alphaMode == GltfMaterial::AlphaMode::Mask)
            options.cutoff = material.alphaCutoff;
        std::shared_ptr<const MIPMap> alpha;
        if (material.baseColorTexture.valid())
            alpha = image(material.baseColorTexture.image, Encoding::Alpha);
        auto result = std::make_shared<GltfTexture>(alpha, material.baseColorTexture, options);
        if (!alpha) { // a constant opacity: opaque needs no mask
            const float value = result->average().r();
            if (value >= 1.0f)
                return nullptr;
        }
        return result;
    }

    std::shared_ptr<BSDF> makeBSDF(const GltfMaterial &material) {
        PropertyList props;
        if (material.baseColorTexture.valid()) {
            GltfTexture::Options options;
            options.factor = material.baseColorFactor;
            props.set("baseColor", texture(material.baseColorTexture, Encoding::Color, options));
        } else {
            props.setColor("baseColor", material.baseColorFactor);
        }
        const auto channel = [&](const char *name, float factor, int index) {
            if (material.metallicRoughnessTexture.valid()) {
                GltfTexture::Options options;
                options.channel = index;
                options.factor = Color3f(factor);
                props.set(name,
                          texture(material.metallicRoughnessTexture, Encoding::Data, options));
            } else {
                props.setFloat(name, factor);
            }
        };
        channel("metallic", material.metallicFactor, 2);
        channel("roughness", material.roughnessFactor, 1);
        props.setFloat("specular", 0.5f);
        auto disney = std::static_pointer_cast<BSDF>(create("disney", EBSDF, props));
        disney->activate();
        if (!material.doubleSided)
            return disney;
        auto twoSided = std::static_pointer_cast<BSDF>(create("twosided", EBSDF, PropertyList()));
        attach(*twoSided, disney);
        twoSided->activate();
        return twoSided;
    }

    std::shared_ptr<Emitter> makeLight(const GltfMaterial &material) {
        const Color3f scale =
            material.emissiveFactor * (material.emissiveStrength * m_emissionScale);
        if (scale.maxCoeff() <= 0.0f)
            return nullptr;
        PropertyList props;
        if (material.emissiveTexture.valid()) {
            GltfTexture::Options options;
            options.factor = scale;
            props.set("radiance", texture(material.emissiveTexture, Encoding::Color, options));
        } else {
            props.setColor("radiance", scale);
        }
        auto light = std::static_pointer_cast<Emitter>(create("area", EEmitter, props));
        light->activate();
        return light;
    }

    std::string m_filename;
    Transform m_toWorld;
    float m_emissionScale = 1.0f;
    bool m_faceNormals = false;
    GltfAsset m_asset;
    std::shared_ptr<BSDF> m_override;
    std::map<std::pair<int, Encoding>, std::shared_ptr<const MIPMap>> m_images;
    std::vector<std::shared_ptr<Shape>> m_parts;
};

NORI_REGISTER_CLASS(GltfShape, "gltf");

} // namespace
} // namespace nori
