// glTF 2.0 through tinygltf: tinygltf parses the JSON (or the GLB container) and fetches
// buffers and images; everything read from them afterwards — accessors, indices, node
// transforms, materials — is checked here against the glTF 2.0 specification's rules
// (§3.6 binary data, §3.7 geometry, §3.9 materials), so that a malformed file is an
// error naming it, never an out-of-bounds read.
#include <nori/filesystem.h>
#include <nori/gltffile.h>

#include <tiny_gltf.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <set>

namespace nori {
namespace {

/// Largest element count of an accessor that has no buffer view (all zeros, or sparse):
/// such an accessor costs memory without costing file size.
constexpr size_t kMaxViewlessCount = size_t(1) << 24;
/// Deepest node hierarchy followed (a cycle is an error before that).
constexpr int kMaxNodeDepth = 256;

/// The extensions read here; any other the asset uses is reported as dropped.
const std::set<std::string> kMappedExtensions = {"KHR_materials_emissive_strength",
                                                 "KHR_texture_transform", "KHR_mesh_quantization"};
/// Extensions without which the asset's geometry or images cannot be read at all.
const std::set<std::string> kUnreadableExtensions = {"KHR_draco_mesh_compression",
                                                     "EXT_meshopt_compression",
                                                     "KHR_texture_basisu", "EXT_texture_webp"};

/// The state of one read: the model, the file's name for messages, what is dropped.
class GltfReader {
public:
    GltfReader(const tinygltf::Model &model, std::string name)
        : m_model(model), m_name(std::move(name)) {}

    GltfAsset read() {
        for (const std::string &extension : m_model.extensionsRequired)
            if (kUnreadableExtensions.count(extension))
                fail("requires the extension {}, which is not supported (re-export the asset "
                     "without compression)",
                     extension);
        for (const std::string &extension : m_model.extensionsUsed)
            if (!kMappedExtensions.count(extension))
                drop(fmt::format("extension {}", extension));
        for (const auto &camera : m_model.cameras)
            drop(fmt::format("camera '{}'", camera.name));
        for (const auto &animation : m_model.animations)
            drop(fmt::format("animation '{}'", animation.name));
        readImages();
        for (size_t i = 0; i < m_model.materials.size(); ++i)
            m_asset.materials.push_back(readMaterial(m_model.materials[i], int(i)));
        readScene();
        return std::move(m_asset);
    }

private:
    template <typename... Args>
    [[noreturn]] void fail(const char *format, const Args &...args) const {
        throw NoriException("glTF file '{}' {}", m_name, fmt::format(format, args...));
    }

    void drop(const std::string &what) {
        if (std::find(m_asset.dropped.begin(), m_asset.dropped.end(), what) ==
            m_asset.dropped.end())
            m_asset.dropped.push_back(what);
    }

    template <typename T>
    const T &element(const std::vector<T> &array, int index, const char *what) const {
        if (index < 0 || size_t(index) >= array.size())
            fail("refers to {} {}, but has {}", what, index, array.size());
        return array[size_t(index)];
    }

    // ---- Images -------------------------------------------------------------------------

    void readImages() {
        for (size_t i = 0; i < m_model.images.size(); ++i) {
            const tinygltf::Image &image = m_model.images[i];
            GltfImage out;
            out.name = !image.uri.empty() && image.uri.rfind("data:", 0) != 0
                           ? image.uri
                           : fmt::format("image {}{}", i,
                                         image.name.empty() ? "" : " '" + image.name + "'");
            out.mimeType = image.mimeType;
            if (image.bufferView >= 0) {
                // keepEncodedImage left these bytes to us: tinygltf hands over a buffer
                // view's bytes without checking the view against its buffer.
                const unsigned char *bytes =
                    bufferView(image.bufferView, 0, 0, 1, "an image").first;
                const size_t size = m_model.bufferViews[size_t(image.bufferView)].byteLength;
                out.bytes.assign(bytes, bytes + size);
            } else {
                out.bytes.assign(image.image.begin(), image.image.end());
            }
            m_asset.images.push_back(std::move(out));
        }
    }

    // ---- Materials ----------------------------------------------------------------------

    static GltfWrap wrapOf(int mode) {
        switch (mode) {
        case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
            return GltfWrap::Clamp;
        case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
            return GltfWrap::Mirror;
        default:
            return GltfWrap::Repeat;
        }
    }

    /// A texture reference from a material's textureInfo (index, texCoord, extensions).
    GltfTextureRef textureRef(int textureIndex, int texCoord,
                              const tinygltf::ExtensionMap &extensions, const char *slot,
                              const std::string &material) {
        GltfTextureRef ref;
        if (textureIndex < 0)
            return ref;
        const tinygltf::Texture &texture = element(m_model.textures, textureIndex, "texture");
        if (texture.source < 0) {
            // Only an extension's image (Basis, WebP) and no fallback: nothing to read.
            drop(fmt::format("{} of material '{}' (its image is in an extension's format)", slot,
                             material));
            return ref;
        }
        element(m_model.images, texture.source, "image");
        if (m_asset.images[size_t(texture.source)].bytes.empty())
            fail("has {} '{}', which could not be read", "image",
                 m_asset.images[size_t(texture.source)].name);
        ref.image = texture.source;
        if (texture.sampler >= 0) {
            const tinygltf::Sampler &sampler =
                element(m_model.samplers, texture.sampler, "sampler");
            ref.wrapS = wrapOf(sampler.wrapS);
            ref.wrapT = wrapOf(sampler.wrapT);
            ref.nearest = sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
        }
        const auto transform = extensions.find("KHR_texture_transform");
        if (transform != extensions.end()) {
            const tinygltf::Value &value = transform->second;
            ref.offset = vector2(value, "offset", ref.offset);
            ref.scale = vector2(value, "scale", ref.scale);
            ref.rotation = number(value, "rotation", 0.0f);
            if (value.Has("texCoord"))
                texCoord = int(number(value, "texCoord", 0.0f));
        }
        if (texCoord != 0)
            drop(fmt::format("uv set TEXCOORD_{} of the {} of material '{}' (TEXCOORD_0 is read)",
                             texCoord, slot, material));
        return ref;
    }

    float number(const tinygltf::Value &object, const char *key, float fallback) const {
        if (!object.IsObject() || !object.Has(key))
            return fallback;
        const tinygltf::Value &value = object.Get(key);
        if (!value.IsNumber())
            fail("has a non-numeric '{}'", key);
        const double number = value.GetNumberAsDouble();
        if (!std::isfinite(number))
            fail("has a non-finite '{}'", key);
        return float(number);
    }

    Vector2f vector2(const tinygltf::Value &object, const char *key, Vector2f fallback) const {
        if (!object.IsObject() || !object.Has(key))
            return fallback;
        const tinygltf::Value &value = object.Get(key);
        if (!value.IsArray() || value.ArrayLen() != 2 || !value.Get(0).IsNumber() ||
            !value.Get(1).IsNumber())
            fail("has a '{}' that is not two numbers", key);
        return Vector2f(float(value.Get(0).GetNumberAsDouble()),
                        float(value.Get(1).GetNumberAsDouble()));
    }

    template <size_t N>
    std::array<float, N> factors(const std::vector<double> &values, const char *what,
                                 const std::string &material) const {
        if (values.size() != N)
            fail("material '{}' has a {} of {} numbers, not {}", material, what, values.size(), N);
        std::array<float, N> out{};
        for (size_t i = 0; i < N; ++i) {
            if (!std::isfinite(values[i]))
                fail("material '{}' has a non-finite {}", material, what);
            out[i] = float(values[i]);
        }
        return out;
    }

    GltfMaterial readMaterial(const tinygltf::Material &source, int index) {
        GltfMaterial material;
        material.name = source.name.empty() ? fmt::format("material {}", index) : source.name;
        const std::string &name = material.name;
        const tinygltf::PbrMetallicRoughness &pbr = source.pbrMetallicRoughness;
        const auto base = factors<4>(pbr.baseColorFactor, "baseColorFactor", name);
        material.baseColorFactor = Color3f(base[0], base[1], base[2]);
        material.baseAlphaFactor = base[3];
        material.baseColorTexture =
            textureRef(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord,
                       pbr.baseColorTexture.extensions, "baseColorTexture", name);
        material.metallicFactor = float(pbr.metallicFactor);
        material.roughnessFactor = float(pbr.roughnessFactor);
        material.metallicRoughnessTexture =
            textureRef(pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
                       pbr.metallicRoughnessTexture.extensions, "metallicRoughnessTexture", name);
        material.normalTexture =
            textureRef(source.normalTexture.index, source.normalTexture.texCoord,
                       source.normalTexture.extensions, "normalTexture", name);
        material.normalScale = float(source.normalTexture.scale);
        const auto emissive = factors<3>(source.emissiveFactor, "emissiveFactor", name);
        material.emissiveFactor = Color3f(emissive[0], emissive[1], emissive[2]);
        material.emissiveTexture =
            textureRef(source.emissiveTexture.index, source.emissiveTexture.texCoord,
                       source.emissiveTexture.extensions, "emissiveTexture", name);
        if (source.occlusionTexture.index >= 0)
            drop(fmt::format("occlusionTexture of material '{}' (a path tracer computes "
                             "occlusion)",
                             name));
        const auto strength = source.extensions.find("KHR_materials_emissive_strength");
        if (strength != source.extensions.end())
            material.emissiveStrength = number(strength->second, "emissiveStrength", 1.0f);
        for (const auto &extension : source.extensions)
            if (!kMappedExtensions.count(extension.first))
                drop(fmt::format("extension {}", extension.first));
        if (source.alphaMode == "MASK")
            material.alphaMode = GltfMaterial::AlphaMode::Mask;
        else if (source.alphaMode == "BLEND")
            material.alphaMode = GltfMaterial::AlphaMode::Blend;
        else if (source.alphaMode != "OPAQUE")
            fail("material '{}' has alphaMode '{}' (use OPAQUE, MASK or BLEND)", name,
                 source.alphaMode);
        material.alphaCutoff = float(source.alphaCutoff);
        material.doubleSided = source.doubleSided;
        const float numbers[] = {material.metallicFactor, material.roughnessFactor,
                                 material.normalScale,    material.emissiveStrength,
                                 material.alphaCutoff,    material.baseAlphaFactor};
        for (float value : numbers)
            if (!std::isfinite(value))
                fail("material '{}' has a non-finite factor", name);
        return material;
    }

    // ---- Accessors ----------------------------------------------------------------------

    static int componentCount(int type) {
        switch (type) {
        case TINYGLTF_TYPE_SCALAR:
            return 1;
        case TINYGLTF_TYPE_VEC2:
            return 2;
        case TINYGLTF_TYPE_VEC3:
            return 3;
        case TINYGLTF_TYPE_VEC4:
            return 4;
        default:
            return 0;
        }
    }

    static size_t componentSize(int componentType) {
        switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_BYTE:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
            return 1;
        case TINYGLTF_COMPONENT_TYPE_SHORT:
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
            return 2;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return 4;
        default:
            return 0;
        }
    }

    /// One component at `data` as a float: floats as they are, integers normalised to
    /// [0, 1] or [−1, 1] when `normalized` (glTF 2.0 §3.11), else converted.
    static float decodeComponent(const unsigned char *data, int componentType, bool normalized) {
        auto read = [&](auto value) {
            std::memcpy(&value, data, sizeof(value)); // glTF is little-endian, as is the machine
            return value;
        };
        switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
            return read(float());
        case TINYGLTF_COMPONENT_TYPE_BYTE: {
            const float v = read(int8_t());
            return normalized ? std::max(v / 127.0f, -1.0f) : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
            const float v = read(uint8_t());
            return normalized ? v / 255.0f : v;
        }
        case TINYGLTF_COMPONENT_TYPE_SHORT: {
            const float v = read(int16_t());
            return normalized ? std::max(v / 32767.0f, -1.0f) : v;
        }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
            const float v = read(uint16_t());
            return normalized ? v / 65535.0f : v;
        }
        default: // UNSIGNED_INT, only for indices
            return float(read(uint32_t()));
        }
    }

    /// The bytes of buffer view `index` and its stride for elements of `elementSize`.
    std::pair<const unsigned char *, size_t> bufferView(int index, size_t offset, size_t count,
                                                        size_t elementSize,
                                                        const std::string &what) const {
        const tinygltf::BufferView &view = element(m_model.bufferViews, index, "buffer view");
        const tinygltf::Buffer &buffer = element(m_model.buffers, view.buffer, "buffer");
        if (view.byteOffset > buffer.data.size() ||
            view.byteLength > buffer.data.size() - view.byteOffset)
            fail("has buffer view {} (bytes {} to {}) beyond its buffer of {} bytes", index,
                 view.byteOffset, view.byteOffset + view.byteLength, buffer.data.size());
        const size_t stride = view.byteStride ? view.byteStride : elementSize;
        if (stride < elementSize)
            fail("has {} with a byte stride {} below its element size {}", what, stride,
                 elementSize);
        if (count > 0) {
            const size_t span = view.byteLength;
            // offset + stride·(count − 1) + elementSize ≤ span, without overflow.
            if (offset > span || elementSize > span - offset ||
                (count - 1) > (span - offset - elementSize) / stride)
                fail("has {} of {} elements reaching beyond its buffer view of {} bytes", what,
                     count, span);
        }
        return {buffer.data.data() + view.byteOffset + offset, stride};
    }

    /// Accessor `index` as `components` floats per element (sparse substitutions applied).
    std::vector<float> readFloats(int index, int components, const std::string &what) const {
        const tinygltf::Accessor &accessor = element(m_model.accessors, index, "accessor");
        if (componentCount(accessor.type) != components)
            fail("has {} with {} components per element, not {}", what,
                 componentCount(accessor.type), components);
        const size_t size = componentSize(accessor.componentType);
        if (size == 0 || accessor.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
            fail("has {} of component type {}", what, accessor.componentType);
        const size_t count = accessor.count;
        if (accessor.bufferView < 0 && count > kMaxViewlessCount)
            fail("has {} of {} elements without a buffer view", what, count);
        std::vector<float> values(count * size_t(components), 0.0f);
        const size_t elementSize = size * size_t(components);
        if (accessor.bufferView >= 0) {
            const auto [data, stride] =
                bufferView(accessor.bufferView, accessor.byteOffset, count, elementSize, what);
            for (size_t i = 0; i < count; ++i)
                for (int c = 0; c < components; ++c)
                    values[i * size_t(components) + size_t(c)] =
                        decodeComponent(data + i * stride + size_t(c) * size,
                                        accessor.componentType, accessor.normalized);
        }
        if (accessor.sparse.isSparse) {
            const auto &sparse = accessor.sparse;
            if (sparse.count < 0 || size_t(sparse.count) > count)
                fail("has {} with {} sparse substitutions for {} elements", what, sparse.count,
                     count);
            const std::vector<uint32_t> targets = readIndexArray(
                sparse.indices.bufferView, size_t(std::max(0, sparse.indices.byteOffset)),
                size_t(sparse.count), sparse.indices.componentType, what + "'s sparse indices");
            const auto [data, stride] =
                bufferView(sparse.values.bufferView, size_t(std::max(0, sparse.values.byteOffset)),
                           size_t(sparse.count), elementSize, what + "'s sparse values");
            (void)stride; // sparse values are tightly packed
            for (size_t i = 0; i < targets.size(); ++i) {
                if (targets[i] >= count)
                    fail("has {} with a sparse index {} beyond its {} elements", what, targets[i],
                         count);
                for (int c = 0; c < components; ++c)
                    values[targets[i] * size_t(components) + size_t(c)] =
                        decodeComponent(data + i * elementSize + size_t(c) * size,
                                        accessor.componentType, accessor.normalized);
            }
        }
        for (float value : values)
            if (!std::isfinite(value))
                fail("has {} holding a non-finite number", what);
        return values;
    }

    std::vector<uint32_t> readIndexArray(int view, size_t offset, size_t count, int componentType,
                                         const std::string &what) const {
        const size_t size = componentSize(componentType);
        if (componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
            componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
            fail("has {} of component type {} (indices are unsigned integers)", what,
                 componentType);
        const auto [data, stride] = bufferView(view, offset, count, size, what);
        std::vector<uint32_t> indices(count);
        for (size_t i = 0; i < count; ++i) {
            const unsigned char *p = data + i * stride;
            if (size == 1) {
                indices[i] = *p;
            } else if (size == 2) {
                uint16_t value;
                std::memcpy(&value, p, 2);
                indices[i] = value;
            } else {
                std::memcpy(&indices[i], p, 4);
            }
        }
        return indices;
    }

    std::vector<uint32_t> readIndices(int index, const std::string &what) const {
        const tinygltf::Accessor &accessor = element(m_model.accessors, index, "accessor");
        if (accessor.type != TINYGLTF_TYPE_SCALAR || accessor.bufferView < 0 ||
            accessor.sparse.isSparse)
            fail("has {} that is not a plain array of scalars", what);
        return readIndexArray(accessor.bufferView, accessor.byteOffset, accessor.count,
                              accessor.componentType, what);
    }

    // ---- Geometry -----------------------------------------------------------------------

    /// Triangles of a primitive from its (possibly implicit) vertex list by its mode.
    std::vector<Vector3i> triangles(const std::vector<uint32_t> &order, int mode,
                                    size_t vertexCount, const std::string &what) const {
        for (uint32_t index : order)
            if (index >= vertexCount)
                fail("has {} with vertex index {} beyond its {} vertices", what, index,
                     vertexCount);
        std::vector<Vector3i> faces;
        auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
            if (a != b && b != c && a != c)
                faces.emplace_back(int(a), int(b), int(c));
        };
        const size_t n = order.size();
        switch (mode) {
        case TINYGLTF_MODE_TRIANGLES:
            if (n % 3 != 0)
                fail("has {} of {} indices, not a multiple of 3", what, n);
            for (size_t i = 0; i + 2 < n; i += 3)
                add(order[i], order[i + 1], order[i + 2]);
            break;
        case TINYGLTF_MODE_TRIANGLE_STRIP: // glTF 2.0 §3.7.2.1: every other one reversed
            for (size_t i = 0; i + 2 < n; ++i)
                add(order[i], order[i + 1 + i % 2], order[i + 2 - i % 2]);
            break;
        case TINYGLTF_MODE_TRIANGLE_FAN:
            for (size_t i = 0; i + 2 < n; ++i)
                add(order[i + 1], order[i + 2], order[0]);
            break;
        default:
            break;
        }
        return faces;
    }

    void readPrimitive(const tinygltf::Mesh &mesh, int meshIndex, size_t primitiveIndex,
                       const Transform &toWorld) {
        const tinygltf::Primitive &primitive = mesh.primitives[primitiveIndex];
        const std::string meshName =
            mesh.name.empty() ? fmt::format("mesh {}", meshIndex) : mesh.name;
        const std::string what = fmt::format("{}[{}]", meshName, primitiveIndex);
        if (primitive.mode != TINYGLTF_MODE_TRIANGLES &&
            primitive.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
            primitive.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
            drop(fmt::format("points and lines of mesh '{}'", meshName));
            return;
        }
        const auto attribute = [&](const char *name) {
            const auto it = primitive.attributes.find(name);
            return it == primitive.attributes.end() ? -1 : it->second;
        };
        const int positionAccessor = attribute("POSITION");
        if (positionAccessor < 0)
            fail("has {} without POSITION", what);
        GltfPrimitive out;
        out.name = what;
        out.material = primitive.material;
        out.toWorld = toWorld;
        if (out.material >= int(m_model.materials.size()))
            fail("has {} with material {} of {}", what, out.material, m_model.materials.size());
        const std::vector<float> positions = readFloats(positionAccessor, 3, what + "'s POSITION");
        const size_t vertexCount = positions.size() / 3;
        if (vertexCount > size_t(std::numeric_limits<int>::max()))
            fail("has {} of too many vertices", what);
        out.mesh.positions.resize(vertexCount);
        for (size_t i = 0; i < vertexCount; ++i)
            out.mesh.positions[i] =
                Point3f(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
        if (const int normals = attribute("NORMAL"); normals >= 0) {
            const std::vector<float> values = readFloats(normals, 3, what + "'s NORMAL");
            if (values.size() != positions.size())
                fail("has {} with {} normals for {} vertices", what, values.size() / 3,
                     vertexCount);
            out.mesh.normals.resize(vertexCount);
            for (size_t i = 0; i < vertexCount; ++i)
                out.mesh.normals[i] = Normal3f(values[3 * i], values[3 * i + 1], values[3 * i + 2]);
        }
        // glTF's uv origin is the image's top-left corner; ours (OBJ's) the bottom-left.
        const auto readUVs = [&](const char *name, std::vector<Point2f> &uvs) {
            const int accessor = attribute(name);
            if (accessor < 0)
                return;
            const std::vector<float> values = readFloats(accessor, 2, what + "'s " + name);
            if (values.size() != 2 * vertexCount)
                fail("has {} with {} {} for {} vertices", what, values.size() / 2, name,
                     vertexCount);
            uvs.resize(vertexCount);
            for (size_t i = 0; i < vertexCount; ++i)
                uvs[i] = Point2f(values[2 * i], 1.0f - values[2 * i + 1]);
        };
        readUVs("TEXCOORD_0", out.mesh.texCoords);
        if (attribute("COLOR_0") >= 0)
            drop(fmt::format("vertex colours of mesh '{}'", meshName));
        if (attribute("JOINTS_0") >= 0)
            drop(fmt::format("skinning of mesh '{}' (its rest pose is rendered)", meshName));
        if (!primitive.targets.empty())
            drop(fmt::format("morph targets of mesh '{}' (its base shape is rendered)", meshName));
        std::vector<uint32_t> order;
        if (primitive.indices >= 0) {
            order = readIndices(primitive.indices, what + "'s indices");
        } else {
            order.resize(vertexCount);
            for (size_t i = 0; i < vertexCount; ++i)
                order[i] = uint32_t(i);
        }
        out.mesh.triangles = triangles(order, primitive.mode, vertexCount, what);
        m_asset.primitives.push_back(std::move(out));
    }

    /// A node's local transform: its matrix, or translation · rotation · scale.
    Eigen::Matrix4f localTransform(const tinygltf::Node &node) const {
        Eigen::Matrix4f matrix = Eigen::Matrix4f::Identity();
        auto finite = [&](const std::vector<double> &values) {
            for (double value : values)
                if (!std::isfinite(value))
                    fail("has node '{}' with a non-finite transform", node.name);
        };
        finite(node.matrix);
        finite(node.translation);
        finite(node.rotation);
        finite(node.scale);
        if (node.matrix.size() == 16) {
            for (int i = 0; i < 16; ++i) // column-major
                matrix(i % 4, i / 4) = float(node.matrix[size_t(i)]);
            return matrix;
        }
        if (!node.matrix.empty() || (!node.translation.empty() && node.translation.size() != 3) ||
            (!node.rotation.empty() && node.rotation.size() != 4) ||
            (!node.scale.empty() && node.scale.size() != 3))
            fail("has node '{}' with a malformed transform", node.name);
        Eigen::Affine3f affine = Eigen::Affine3f::Identity();
        if (!node.translation.empty())
            affine.translate(Vector3f(float(node.translation[0]), float(node.translation[1]),
                                      float(node.translation[2])));
        if (!node.rotation.empty()) {
            // (x, y, z, w), normalised as the specification requires of unit quaternions.
            Eigen::Quaternionf q(float(node.rotation[3]), float(node.rotation[0]),
                                 float(node.rotation[1]), float(node.rotation[2]));
            if (q.norm() == 0.0f)
                fail("has node '{}' with a zero rotation quaternion", node.name);
            affine.rotate(q.normalized());
        }
        if (!node.scale.empty())
            affine.scale(
                Vector3f(float(node.scale[0]), float(node.scale[1]), float(node.scale[2])));
        return affine.matrix();
    }

    void visitNode(int index, const Eigen::Matrix4f &parent, std::vector<int> &path) {
        const tinygltf::Node &node = element(m_model.nodes, index, "node");
        if (std::find(path.begin(), path.end(), index) != path.end())
            fail("has a cycle of nodes through node {}", index);
        if (int(path.size()) >= kMaxNodeDepth)
            fail("nests nodes deeper than {} levels", kMaxNodeDepth);
        path.push_back(index);
        const Eigen::Matrix4f toWorld = parent * localTransform(node);
        if (node.mesh >= 0) {
            const tinygltf::Mesh &mesh = element(m_model.meshes, node.mesh, "mesh");
            for (size_t i = 0; i < mesh.primitives.size(); ++i)
                readPrimitive(mesh, node.mesh, i, Transform(toWorld));
        }
        if (node.skin >= 0)
            drop(fmt::format("skin of node '{}'", node.name));
        for (const auto &extension : node.extensions)
            if (extension.first == "KHR_lights_punctual")
                drop(fmt::format("light of node '{}' (KHR_lights_punctual)", node.name));
        for (int child : node.children)
            visitNode(child, toWorld, path);
        path.pop_back();
    }

    void readScene() {
        std::vector<int> roots;
        if (!m_model.scenes.empty()) {
            const int scene = m_model.defaultScene >= 0 ? m_model.defaultScene : 0;
            roots = element(m_model.scenes, scene, "scene").nodes;
        } else {
            // No scene: every node that is no other node's child is a root.
            std::vector<bool> isChild(m_model.nodes.size(), false);
            for (const auto &node : m_model.nodes)
                for (int child : node.children)
                    if (child >= 0 && size_t(child) < isChild.size())
                        isChild[size_t(child)] = true;
            for (size_t i = 0; i < m_model.nodes.size(); ++i)
                if (!isChild[i])
                    roots.push_back(int(i));
        }
        std::vector<int> path;
        for (int root : roots)
            visitNode(root, Eigen::Matrix4f::Identity(), path);
        if (m_asset.primitives.empty())
            fail("has no triangles in its scene");
    }

    const tinygltf::Model &m_model;
    std::string m_name;
    GltfAsset m_asset;
};

/// tinygltf's image callback: keep the encoded bytes, the `gltf` shape decodes them. An
/// image in a buffer view is left to GltfReader::readImages: tinygltf (before its 2025
/// fix, syoyo/tinygltf#512) passes such bytes unchecked, possibly past its buffer's end.
bool keepEncodedImage(tinygltf::Image *image, const int, std::string *, std::string *, int, int,
                      const unsigned char *bytes, int size, void *) {
    if (image->bufferView < 0)
        image->image.assign(bytes, bytes + size);
    image->as_is = true;
    return true;
}

/// File access for tinygltf: plain reads relative to the asset (no shell expansion of
/// names, which tinygltf's default does with wordexp), or none at all.
tinygltf::FsCallbacks fileCallbacks(bool allowFiles) {
    static bool allowed = true; // its address, as user_data, says files may be read
    tinygltf::FsCallbacks callbacks{};
    callbacks.user_data = allowFiles ? &allowed : nullptr;
    callbacks.FileExists = [](const std::string &path, void *allow) {
        std::error_code error;
        return allow != nullptr && std::filesystem::is_regular_file(path, error);
    };
    callbacks.ExpandFilePath = [](const std::string &path, void *) { return path; };
    callbacks.ReadWholeFile = [](std::vector<unsigned char> *out, std::string *err,
                                 const std::string &path, void *allow) {
        if (allow == nullptr) {
            *err += "external files are not read here: " + path + "\n";
            return false;
        }
        try {
            const std::string bytes = readBinaryFile(path, "glTF resource");
            out->assign(bytes.begin(), bytes.end());
            return true;
        } catch (const NoriException &error) {
            *err += std::string(error.what()) + "\n";
            return false;
        }
    };
    callbacks.WriteWholeFile = [](std::string *err, const std::string &,
                                  const std::vector<unsigned char> &, void *) {
        *err += "glTF files are only read here\n";
        return false;
    };
    return callbacks;
}

GltfAsset load(std::string_view bytes, const std::string &name, const std::string &folder,
               bool allowFiles) {
    tinygltf::TinyGLTF loader;
    loader.SetImageLoader(keepEncodedImage, nullptr);
    loader.SetFsCallbacks(fileCallbacks(allowFiles));
    tinygltf::Model model;
    std::string error, warning;
    if (bytes.size() > size_t(std::numeric_limits<unsigned int>::max()))
        throw NoriException("glTF file '{}' is larger than 4 GiB", name);
    const auto *data = reinterpret_cast<const unsigned char *>(bytes.data());
    const bool binary = bytes.size() >= 4 && bytes.substr(0, 4) == "glTF";
    const bool ok =
        binary ? loader.LoadBinaryFromMemory(&model, &error, &warning, data,
                                             static_cast<unsigned int>(bytes.size()), folder)
               : loader.LoadASCIIFromString(&model, &error, &warning, bytes.data(),
                                            static_cast<unsigned int>(bytes.size()), folder);
    if (!ok) {
        while (!error.empty() && error.back() == '\n')
            error.pop_back();
        throw NoriException("glTF file '{}' cannot be read: {}", name,
                            error.empty() ? "malformed" : error);
    }
    // tinygltf reports an image it could not fetch as a warning; the textures that use
    // it make that an error (GltfReader::textureRef).
    return GltfReader(model, name).read();
}

} // namespace

GltfAsset readGltf(const std::string &path) {
    const std::string bytes = readBinaryFile(path, "glTF file");
    const std::string folder = std::filesystem::path(path).parent_path().string();
    return load(bytes, path, folder.empty() ? "." : folder, true);
}

GltfAsset parseGltf(std::string_view bytes, const std::string &name) {
    return load(bytes, name, ".", false);
}

} // namespace nori
