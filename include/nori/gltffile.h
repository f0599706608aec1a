// glTF 2.0 assets (Khronos, "glTF 2.0 Specification"), `.gltf` (JSON with external or
// embedded buffers) and `.glb` (binary container), read through Debian's tinygltf into what
// a renderer of surfaces needs: the triangles of every mesh primitive placed by its node's
// world transform, the metallic-roughness materials with their textures' images (still
// encoded: the `gltf` shape decodes them), and a list of what the asset holds that is not
// rendered (cameras, animations, skins, unknown extensions), by name, for warnings.
#pragma once

#include <nori/color.h>
#include <nori/meshdata.h>
#include <nori/transform.h>

#include <string>
#include <string_view>
#include <vector>

namespace nori {

/// How a glTF texture repeats outside [0, 1] along one axis (its sampler's wrapS/wrapT).
enum class GltfWrap { Repeat, Clamp, Mirror };

/// A material's reference to a texture: which image, which uv set and how it is sampled.
struct GltfTextureRef {
    int image = -1; ///< index into GltfAsset::images, −1: no texture
    GltfWrap wrapS = GltfWrap::Repeat, wrapT = GltfWrap::Repeat;
    bool nearest = false; ///< the sampler asks for nearest-neighbour magnification
    /// KHR_texture_transform: uv' = offset + R(rotation) · (scale ⊙ uv), in glTF's uv
    /// space (origin at the image's top-left corner).
    Vector2f offset = Vector2f(0.0f, 0.0f), scale = Vector2f(1.0f, 1.0f);
    float rotation = 0.0f;
    bool valid() const { return image >= 0; }
};

/// A metallic-roughness material (glTF 2.0 §3.9) and the extensions mapped onto it.
struct GltfMaterial {
    enum class AlphaMode { Opaque, Mask, Blend };

    std::string name;
    Color3f baseColorFactor = Color3f(1.0f);
    float baseAlphaFactor = 1.0f;
    GltfTextureRef baseColorTexture; ///< sRGB colour, linear alpha
    float metallicFactor = 1.0f, roughnessFactor = 1.0f;
    GltfTextureRef metallicRoughnessTexture; ///< roughness in G, metallic in B (linear)
    GltfTextureRef normalTexture;            ///< tangent space, linear
    float normalScale = 1.0f;
    Color3f emissiveFactor = Color3f(0.0f);
    GltfTextureRef emissiveTexture; ///< sRGB
    float emissiveStrength = 1.0f;  ///< KHR_materials_emissive_strength
    AlphaMode alphaMode = AlphaMode::Opaque;
    float alphaCutoff = 0.5f;
    bool doubleSided = false;
};

/// The triangles of one mesh primitive, in the mesh's frame, placed by `toWorld`.
struct GltfPrimitive {
    std::string name;  ///< "mesh name[primitive index]" (for messages)
    MeshData mesh;     ///< uvs (set 0) with v flipped to OBJ's convention (origin bottom-left)
    int material = -1; ///< index into GltfAsset::materials, −1: glTF's default material
    Transform toWorld;
};

/// An image a texture reads: its encoded bytes (PNG or JPEG) and where it came from.
struct GltfImage {
    std::string name;     ///< the file's uri or "image N" (for messages)
    std::string mimeType; ///< "image/png", "image/jpeg", or what the asset names
    std::string bytes;
};

/// What a glTF asset renders as surfaces, and what it holds that does not.
struct GltfAsset {
    std::vector<GltfPrimitive> primitives;
    std::vector<GltfMaterial> materials;
    std::vector<GltfImage> images;
    /// "camera 'Camera'", "animation 'Walk'", "extension KHR_lights_punctual", … (each
    /// once): what the asset holds that these surfaces leave out.
    std::vector<std::string> dropped;
};

/// Reads the glTF (JSON) or GLB (binary, recognised by its magic "glTF") file at `path`;
/// external buffers and images are read relative to its folder. Throws NoriException
/// naming the file and what is malformed: JSON errors, buffers or images that cannot be
/// read, accessors or indices out of range, extensions the asset requires but that are
/// not supported (Draco, meshopt and Basis compression).
GltfAsset readGltf(const std::string &path);

/// As readGltf, from the file's bytes; external files are refused (for the fuzz target).
GltfAsset parseGltf(std::string_view bytes, const std::string &name);

} // namespace nori
