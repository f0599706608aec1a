// What a pbrt-v4 scene file describes, before any of it is mapped onto our plugins: the
// entities pbrt-v4's BasicSceneBuilder collects (src/pbrt/scene.cpp), each with its type,
// its parameters (the graphics state's `Attribute` defaults merged in), where it was
// declared, and the graphics state it was declared in: the current transformation
// matrix, ReverseOrientation, the material, the area light, the media. The directives of
// transforms and attributes are applied here with pbrt-v4's semantics; what they mean to
// a renderer is the importer's business.
#pragma once

#include <nori/pbrtparser.h>

#include <Eigen/Core>

#include <map>
#include <string>
#include <vector>

namespace nori::pbrt {

using Matrix = Eigen::Matrix4d;

/// A directive's plugin type and parameters, and where it stands.
struct Entity {
    std::string type;
    std::vector<Parameter> parameters;
    Location location;
    /// The parameter called `name`, or nullptr.
    const Parameter *find(const std::string &name) const;
};

/// An entity placed by the current transformation matrix: object to world.
struct PlacedEntity : Entity {
    Matrix toWorld = Matrix::Identity();
};

struct CameraEntity : Entity {
    Matrix toWorld = Matrix::Identity(); ///< camera to world: the inverse of the CTM at Camera
    std::string medium;                  ///< the outside medium where the camera is
};

/// A material: anonymous (Material) or named (MakeNamedMaterial, its type in the
/// "string type" parameter, which is removed from `parameters`).
struct MaterialEntity : Entity {
    std::string name; ///< "" for an anonymous one
};

struct TextureEntity : PlacedEntity {
    std::string name;
    std::string valueType; ///< "float" or "spectrum"
};

struct MediumEntity : PlacedEntity {
    std::string name;
};

struct LightEntity : PlacedEntity {
    std::string medium; ///< the outside medium where the light is
};

struct ShapeEntity : PlacedEntity {
    bool reverseOrientation = false;
    int material = -1;         ///< index into Scene::materials (the anonymous ones), or −1
    std::string namedMaterial; ///< a named material, when that was the current one
    int areaLight = -1;        ///< index into Scene::areaLights, or −1
    std::string insideMedium, outsideMedium;
};

/// ObjectBegin … ObjectEnd: shapes placed relative to the instance.
struct InstanceDefinition {
    std::string name;
    std::vector<ShapeEntity> shapes;
    Location location;
};

/// ObjectInstance: a definition placed by the CTM.
struct InstanceUse {
    std::string name;
    Matrix toWorld = Matrix::Identity();
    Location location;
};

/// Everything a pbrt-v4 scene file describes.
struct Scene {
    /// pbrt-v4's defaults when the file names none: perspective camera, rgb film, zsobol
    /// sampler, gaussian filter, volpath integrator (their `type`s; no parameters).
    CameraEntity camera;
    Entity film, sampler, filter, integrator, accelerator;
    std::string colorSpace = "srgb";
    std::map<std::string, std::vector<std::string>> options; ///< Option "type name" value
    /// Anonymous materials in order; the first is pbrt-v4's default, a diffuse one.
    std::vector<MaterialEntity> materials;
    std::map<std::string, MaterialEntity> namedMaterials;
    std::vector<TextureEntity> textures;
    std::vector<MediumEntity> media;
    std::vector<ShapeEntity> shapes;
    std::vector<LightEntity> lights;
    std::vector<Entity> areaLights;
    std::vector<InstanceDefinition> instances;
    std::vector<InstanceUse> instanceUses;
    /// One line per feature the file uses that is read but not rendered as pbrt-v4 would
    /// (motion blur, another colour space, TransformBegin's deprecation, …), with where.
    std::vector<std::string> warnings;
};

/// Applies the directives of one file (and its Includes) with pbrt-v4's semantics. Throws
/// LocatedError for what pbrt-v4 rejects: a directive in the wrong block (a Shape before
/// WorldBegin, a Camera after it), an unmatched AttributeEnd or ObjectEnd, a redefined
/// named material, medium or object, an instance used but never defined, a LookAt whose
/// up vector is parallel to its direction, an unknown Attribute target, a file that ends
/// before WorldBegin or inside an AttributeBegin.
Scene readScene(const std::string &path);
/// As readScene, from text (Include and Import refused).
Scene readSceneString(std::string_view text, const std::string &name);

} // namespace nori::pbrt
