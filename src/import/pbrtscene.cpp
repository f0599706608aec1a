// pbrt-v4's graphics state and scene builder (its src/pbrt/scene.cpp, BasicSceneBuilder):
// the transform and attribute directives change the state; the others record an entity
// with the state they were declared in.
#include <nori/common.h>
#include <nori/pbrtscene.h>
#include <nori/strutil.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <set>

namespace nori::pbrt {

const Parameter *Entity::find(const std::string &name) const {
    for (const Parameter &parameter : parameters)
        if (parameter.name == name)
            return &parameter;
    return nullptr;
}

namespace {

/// pbrt-v4's GraphicsState: what AttributeBegin saves and AttributeEnd restores.
struct GraphicsState {
    std::array<Matrix, 2> ctm = {Matrix::Identity(), Matrix::Identity()}; ///< start, end time
    std::array<bool, 2> active = {true, true};
    bool reverseOrientation = false;
    int material = 0; ///< the anonymous material, when `namedMaterial` is empty
    std::string namedMaterial;
    std::string areaLightType;
    std::vector<Parameter> areaLightParameters;
    Location areaLightLocation;
    std::string insideMedium, outsideMedium;
    std::map<std::string, std::vector<Parameter>> attributes; ///< by Attribute target
    std::string colorSpace = "srgb";
    double transformStart = 0.0, transformEnd = 1.0;
};

Matrix translation(double x, double y, double z) {
    Matrix m = Matrix::Identity();
    m(0, 3) = x;
    m(1, 3) = y;
    m(2, 3) = z;
    return m;
}

/// The 16 numbers of Transform and ConcatTransform: pbrt-v4 reads them into a matrix row
/// by row and transposes it, so they are the matrix's columns.
Matrix fromColumns(const std::vector<double> &numbers) {
    Matrix m;
    for (int i = 0; i < 16; ++i)
        m(i % 4, i / 4) = numbers[size_t(i)];
    return m;
}

class Builder {
public:
    explicit Builder(Scene &scene) : m_scene(scene) {
        m_scene.camera.type = "perspective";
        m_scene.film.type = "rgb";
        m_scene.sampler.type = "zsobol";
        m_scene.filter.type = "gaussian";
        m_scene.integrator.type = "volpath";
        m_scene.accelerator.type = "bvh";
        MaterialEntity diffuse;
        diffuse.type = "diffuse";
        m_scene.materials.push_back(diffuse);
    }

    void apply(const Directive &d) {
        const auto it = handlers().find(d.name);
        // The parser knows every directive; each has a handler.
        (this->*(it->second))(d);
    }

    void finish(const Location &end) {
        if (!m_world)
            throw LocatedError(end.str(), "the file ends before WorldBegin");
        if (!m_stack.empty())
            throw LocatedError(m_stack.back().second.str(),
                               m_stack.back().first == 'o'
                                   ? "this ObjectBegin has no ObjectEnd"
                                   : "this AttributeBegin has no AttributeEnd");
        for (const InstanceUse &use : m_scene.instanceUses)
            if (!m_instanceNames.count(use.name))
                throw LocatedError(use.location.str(),
                                   fmt::format("ObjectInstance of '{}', which no ObjectBegin "
                                               "defines",
                                               use.name));
    }

private:
    using Handler = void (Builder::*)(const Directive &);

    static const std::map<std::string, Handler> &handlers() {
        static const std::map<std::string, Handler> table = {
            {"Accelerator", &Builder::options},
            {"ActiveTransform", &Builder::activeTransform},
            {"AreaLightSource", &Builder::areaLightSource},
            {"Attribute", &Builder::attribute},
            {"AttributeBegin", &Builder::attributeBegin},
            {"AttributeEnd", &Builder::attributeEnd},
            {"Camera", &Builder::camera},
            {"ColorSpace", &Builder::colorSpace},
            {"ConcatTransform", &Builder::concatTransform},
            {"CoordSysTransform", &Builder::coordSysTransform},
            {"CoordinateSystem", &Builder::coordinateSystem},
            {"Film", &Builder::options},
            {"Identity", &Builder::identity},
            {"Integrator", &Builder::options},
            {"LightSource", &Builder::lightSource},
            {"LookAt", &Builder::lookAt},
            {"MakeNamedMaterial", &Builder::makeNamedMaterial},
            {"MakeNamedMedium", &Builder::makeNamedMedium},
            {"Material", &Builder::material},
            {"MediumInterface", &Builder::mediumInterface},
            {"NamedMaterial", &Builder::namedMaterial},
            {"ObjectBegin", &Builder::objectBegin},
            {"ObjectEnd", &Builder::objectEnd},
            {"ObjectInstance", &Builder::objectInstance},
            {"Option", &Builder::option},
            {"PixelFilter", &Builder::options},
            {"ReverseOrientation", &Builder::reverseOrientation},
            {"Rotate", &Builder::rotate},
            {"Sampler", &Builder::options},
            {"Scale", &Builder::scale},
            {"Shape", &Builder::shape},
            {"Texture", &Builder::texture},
            {"Transform", &Builder::transform},
            {"TransformBegin", &Builder::transformBegin},
            {"TransformEnd", &Builder::attributeEnd},
            {"TransformTimes", &Builder::transformTimes},
            {"Translate", &Builder::translate},
            {"WorldBegin", &Builder::worldBegin},
            {"WorldEnd", &Builder::worldEnd},
        };
        return table;
    }

    [[noreturn]] static void fail(const Directive &d, const std::string &message) {
        throw LocatedError(d.location.str(), message);
    }
    void warn(const Directive &d, const std::string &message) {
        m_scene.warnings.push_back(fmt::format("{}: {}", d.location.str(), message));
    }
    void requireWorld(const Directive &d) const {
        if (!m_world)
            fail(d,
                 fmt::format("{} belongs after WorldBegin (pbrt-v4's scene description)", d.name));
    }
    void requireOptions(const Directive &d) const {
        if (m_world)
            fail(d,
                 fmt::format("{} belongs before WorldBegin (pbrt-v4's rendering options)", d.name));
    }

    /// The entity of a directive: its type and parameters, with the Attribute defaults of
    /// `target` the directive does not give itself.
    Entity entity(const Directive &d, const char *target = nullptr) const {
        Entity e;
        e.type = d.strings.empty() ? "" : d.strings.front();
        e.parameters = d.parameters;
        e.location = d.location;
        if (target) {
            const auto defaults = m_state.attributes.find(target);
            if (defaults != m_state.attributes.end())
                for (const Parameter &parameter : defaults->second)
                    if (!e.find(parameter.name))
                        e.parameters.push_back(parameter);
        }
        return e;
    }

    /// The entity of MakeNamedMaterial or MakeNamedMedium: its type is its "string type"
    /// parameter (taken out of the list), its name the directive's argument.
    Entity namedEntity(const Directive &d, const char *target) const {
        Entity e = entity(d, target);
        const Parameter *type = e.find("type");
        if (!type || type->type != "string" || type->strings.size() != 1)
            fail(d, fmt::format("{} '{}' needs a \"string type\"", d.name, d.strings[0]));
        e.type = type->strings[0];
        e.parameters.erase(std::remove_if(e.parameters.begin(), e.parameters.end(),
                                          [](const Parameter &p) { return p.name == "type"; }),
                           e.parameters.end());
        return e;
    }

    // ---- Transforms ---------------------------------------------------------------------

    template <typename F> void forActive(F &&change) {
        for (int i = 0; i < 2; ++i)
            if (m_state.active[i])
                m_state.ctm[i] = change(m_state.ctm[i]);
    }

    void identity(const Directive &) {
        forActive([](const Matrix &) { return Matrix::Identity(); });
    }
    void translate(const Directive &d) {
        const Matrix t = translation(d.numbers[0], d.numbers[1], d.numbers[2]);
        forActive([&](const Matrix &m) -> Matrix { return m * t; });
    }
    void scale(const Directive &d) {
        Matrix s = Matrix::Identity();
        s(0, 0) = d.numbers[0];
        s(1, 1) = d.numbers[1];
        s(2, 2) = d.numbers[2];
        forActive([&](const Matrix &m) -> Matrix { return m * s; });
    }
    void rotate(const Directive &d) {
        const Eigen::Vector3d axis(d.numbers[1], d.numbers[2], d.numbers[3]);
        if (axis.norm() == 0.0)
            fail(d, "Rotate needs a non-zero axis");
        Matrix r = Matrix::Identity();
        r.topLeftCorner<3, 3>() =
            Eigen::AngleAxisd(d.numbers[0] * (3.14159265358979323846 / 180.0), axis.normalized())
                .toRotationMatrix();
        forActive([&](const Matrix &m) -> Matrix { return m * r; });
    }
    void lookAt(const Directive &d) {
        // pbrt-v4's LookAt: the camera-from-world matrix of an eye looking at a point,
        // +z toward it, +y up, +x = up × direction (a left-handed camera frame).
        const Eigen::Vector3d eye(d.numbers[0], d.numbers[1], d.numbers[2]),
            target(d.numbers[3], d.numbers[4], d.numbers[5]),
            up(d.numbers[6], d.numbers[7], d.numbers[8]);
        const Eigen::Vector3d direction = target - eye;
        if (direction.norm() == 0.0 || up.norm() == 0.0)
            fail(d, "LookAt needs an eye apart from its target and a non-zero up vector");
        const Eigen::Vector3d dir = direction.normalized();
        const Eigen::Vector3d right = up.normalized().cross(dir);
        if (right.norm() < 1e-12)
            fail(d, "LookAt's up vector and viewing direction point the same way");
        const Eigen::Vector3d rightUnit = right.normalized();
        const Eigen::Vector3d newUp = dir.cross(rightUnit);
        Matrix worldFromCamera = Matrix::Identity();
        worldFromCamera.block<3, 1>(0, 0) = rightUnit;
        worldFromCamera.block<3, 1>(0, 1) = newUp;
        worldFromCamera.block<3, 1>(0, 2) = dir;
        worldFromCamera.block<3, 1>(0, 3) = eye;
        const Matrix cameraFromWorld = worldFromCamera.inverse();
        forActive([&](const Matrix &m) -> Matrix { return m * cameraFromWorld; });
    }
    void transform(const Directive &d) {
        const Matrix m = fromColumns(d.numbers);
        for (size_t i = 0; i < 2; ++i)
            if (m_state.active[i])
                m_state.ctm[i] = m;
    }
    void concatTransform(const Directive &d) {
        const Matrix m = fromColumns(d.numbers);
        forActive([&](const Matrix &current) -> Matrix { return current * m; });
    }
    void coordinateSystem(const Directive &d) {
        m_namedSystems[d.strings[0]] = {m_state.ctm[0], m_state.ctm[1]};
    }
    void coordSysTransform(const Directive &d) {
        const auto it = m_namedSystems.find(d.strings[0]);
        if (it == m_namedSystems.end()) {
            // pbrt-v4 warns and goes on.
            warn(d, fmt::format("no coordinate system named '{}'; the transform is unchanged",
                                d.strings[0]));
            return;
        }
        m_state.ctm[0] = it->second.first;
        m_state.ctm[1] = it->second.second;
    }
    void activeTransform(const Directive &d) {
        const std::string &which = d.strings[0];
        m_state.active[0] = which != "EndTime";
        m_state.active[1] = which != "StartTime";
    }
    void transformTimes(const Directive &d) {
        m_state.transformStart = d.numbers[0];
        m_state.transformEnd = d.numbers[1];
    }

    /// Object to world at the start time; one warning if the CTM moves (motion blur).
    Matrix placement(const Directive &d) {
        if (!m_motionWarned && !m_state.ctm[0].isApprox(m_state.ctm[1], 1e-12)) {
            warn(d, "the transform moves between TransformTimes (motion blur): rendered at "
                    "the start transform");
            m_motionWarned = true;
        }
        return m_state.ctm[0];
    }

    // ---- Blocks and attributes ----------------------------------------------------------

    void options(const Directive &d) {
        requireOptions(d);
        Entity e = entity(d);
        if (d.name == "Film")
            m_scene.film = e;
        else if (d.name == "Sampler")
            m_scene.sampler = e;
        else if (d.name == "PixelFilter")
            m_scene.filter = e;
        else if (d.name == "Integrator")
            m_scene.integrator = e;
        else
            m_scene.accelerator = e;
    }

    void camera(const Directive &d) {
        requireOptions(d);
        CameraEntity camera;
        static_cast<Entity &>(camera) = entity(d);
        const Matrix cameraFromWorld = placement(d);
        camera.toWorld = cameraFromWorld.inverse();
        camera.medium = m_state.outsideMedium;
        m_scene.camera = camera;
        m_namedSystems["camera"] = {m_state.ctm[0].inverse(), m_state.ctm[1].inverse()};
    }

    void colorSpace(const Directive &d) {
        m_state.colorSpace = d.strings[0];
        if (d.strings[0] != "srgb")
            warn(d, fmt::format("colour space '{}': colours are read as sRGB (the only one "
                                "rendered)",
                                d.strings[0]));
    }

    void option(const Directive &d) {
        std::vector<std::string> values = d.strings;
        values.erase(values.begin());
        for (double number : d.numbers)
            values.push_back(fmt::format("{}", number));
        m_scene.options[d.strings[0]] = values;
    }

    void worldBegin(const Directive &d) {
        requireOptions(d);
        m_world = true;
        m_state.ctm[0] = m_state.ctm[1] = Matrix::Identity();
        m_state.active[0] = m_state.active[1] = true;
        m_namedSystems["world"] = {Matrix::Identity(), Matrix::Identity()};
    }

    void worldEnd(const Directive &) {} // pbrt-v3's end marker: nothing to do

    void attributeBegin(const Directive &d) {
        requireWorld(d);
        m_saved.push_back(m_state);
        m_stack.emplace_back('a', d.location);
    }

    void transformBegin(const Directive &d) {
        if (!m_transformBeginWarned) {
            warn(d, "TransformBegin/End are deprecated; read as AttributeBegin/End, as "
                    "pbrt-v4 does");
            m_transformBeginWarned = true;
        }
        attributeBegin(d);
    }

    void attributeEnd(const Directive &d) {
        requireWorld(d);
        if (m_stack.empty())
            fail(d, fmt::format("{} without a matching begin", d.name));
        if (m_stack.back().first == 'o')
            fail(d, fmt::format("{} inside the ObjectBegin at {}", d.name,
                                m_stack.back().second.str()));
        m_state = std::move(m_saved.back());
        m_saved.pop_back();
        m_stack.pop_back();
    }

    void attribute(const Directive &d) {
        static const std::set<std::string> kTargets = {"shape", "light", "material", "medium",
                                                       "texture"};
        const std::string &target = d.strings[0];
        if (!kTargets.count(target))
            fail(d, fmt::format("unknown Attribute target '{}'{} (shape, light, material, "
                                "medium or texture)",
                                target,
                                didYouMean(target, std::vector<std::string>(kTargets.begin(),
                                                                            kTargets.end()))));
        std::vector<Parameter> &defaults = m_state.attributes[target];
        for (const Parameter &parameter : d.parameters) {
            defaults.erase(
                std::remove_if(defaults.begin(), defaults.end(),
                               [&](const Parameter &p) { return p.name == parameter.name; }),
                defaults.end());
            defaults.push_back(parameter);
        }
    }

    void reverseOrientation(const Directive &d) {
        requireWorld(d);
        m_state.reverseOrientation = !m_state.reverseOrientation;
    }

    // ---- Materials, textures, media -----------------------------------------------------

    void material(const Directive &d) {
        requireWorld(d);
        MaterialEntity material;
        static_cast<Entity &>(material) = entity(d, "material");
        m_scene.materials.push_back(material);
        m_state.material = int(m_scene.materials.size()) - 1;
        m_state.namedMaterial.clear();
    }

    void makeNamedMaterial(const Directive &d) {
        requireWorld(d);
        const std::string &name = d.strings[0];
        if (m_scene.namedMaterials.count(name))
            fail(d, fmt::format("named material '{}' is defined twice", name));
        MaterialEntity material;
        static_cast<Entity &>(material) = namedEntity(d, "material");
        material.name = name;
        m_scene.namedMaterials.emplace(name, std::move(material));
    }

    void namedMaterial(const Directive &d) {
        requireWorld(d);
        m_state.namedMaterial = d.strings[0];
        // pbrt-v4 checks the name when the scene is created: a material may be defined
        // after it is selected, in an Import.
        m_namedMaterialUses.emplace_back(d.strings[0], d.location);
    }

    void texture(const Directive &d) {
        requireWorld(d);
        TextureEntity texture;
        static_cast<Entity &>(texture) = entity(d, "texture");
        texture.name = d.strings[0];
        texture.valueType = d.strings[1];
        texture.type = d.strings[2];
        if (texture.valueType != "float" && texture.valueType != "spectrum")
            fail(d, fmt::format("texture '{}' has type '{}': \"float\" or \"spectrum\"",
                                texture.name, texture.valueType));
        for (const TextureEntity &other : m_scene.textures)
            if (other.name == texture.name && other.valueType == texture.valueType) {
                warn(d, fmt::format("{} texture '{}' is defined again; the first definition "
                                    "is kept, as pbrt-v4 does",
                                    texture.valueType, texture.name));
                return;
            }
        texture.toWorld = placement(d);
        m_scene.textures.push_back(std::move(texture));
    }

    void makeNamedMedium(const Directive &d) {
        const std::string &name = d.strings[0];
        for (const MediumEntity &other : m_scene.media)
            if (other.name == name)
                fail(d, fmt::format("named medium '{}' is defined twice", name));
        MediumEntity medium;
        static_cast<Entity &>(medium) = namedEntity(d, "medium");
        medium.name = name;
        medium.toWorld = placement(d);
        m_scene.media.push_back(std::move(medium));
    }

    void mediumInterface(const Directive &d) {
        m_state.insideMedium = d.strings[0];
        m_state.outsideMedium = d.strings.size() > 1 ? d.strings[1] : d.strings[0];
    }

    // ---- Lights and shapes --------------------------------------------------------------

    void lightSource(const Directive &d) {
        requireWorld(d);
        LightEntity light;
        static_cast<Entity &>(light) = entity(d, "light");
        light.toWorld = placement(d);
        light.medium = m_state.outsideMedium;
        m_scene.lights.push_back(std::move(light));
    }

    void areaLightSource(const Directive &d) {
        requireWorld(d);
        const Entity light = entity(d, "light");
        m_state.areaLightType = light.type;
        m_state.areaLightParameters = light.parameters;
        m_state.areaLightLocation = light.location;
    }

    void shape(const Directive &d) {
        requireWorld(d);
        ShapeEntity shape;
        static_cast<Entity &>(shape) = entity(d, "shape");
        shape.toWorld = placement(d);
        shape.reverseOrientation = m_state.reverseOrientation;
        if (m_state.namedMaterial.empty())
            shape.material = m_state.material;
        else
            shape.namedMaterial = m_state.namedMaterial;
        shape.insideMedium = m_state.insideMedium;
        shape.outsideMedium = m_state.outsideMedium;
        if (!m_state.areaLightType.empty()) {
            if (m_instance) {
                warn(d, "an area light inside ObjectBegin does not emit (pbrt-v4 ignores it "
                        "too)");
            } else {
                Entity light;
                light.type = m_state.areaLightType;
                light.parameters = m_state.areaLightParameters;
                light.location = m_state.areaLightLocation;
                m_scene.areaLights.push_back(std::move(light));
                shape.areaLight = int(m_scene.areaLights.size()) - 1;
            }
        }
        if (m_instance)
            m_instance->shapes.push_back(std::move(shape));
        else
            m_scene.shapes.push_back(std::move(shape));
    }

    // ---- Instancing ---------------------------------------------------------------------

    void objectBegin(const Directive &d) {
        requireWorld(d);
        if (m_instance)
            fail(d, fmt::format("ObjectBegin '{}' inside the ObjectBegin of '{}'", d.strings[0],
                                m_instance->name));
        if (m_instanceNames.count(d.strings[0]))
            fail(d, fmt::format("object '{}' is defined twice", d.strings[0]));
        m_instanceNames.insert(d.strings[0]);
        m_saved.push_back(m_state);
        m_stack.emplace_back('o', d.location);
        m_scene.instances.push_back({d.strings[0], {}, d.location});
        m_instance = &m_scene.instances.back();
    }

    void objectEnd(const Directive &d) {
        requireWorld(d);
        if (!m_instance || m_stack.empty())
            fail(d, "ObjectEnd without an ObjectBegin");
        if (m_stack.back().first != 'o')
            fail(d, fmt::format("ObjectEnd inside the AttributeBegin at {}",
                                m_stack.back().second.str()));
        m_state = std::move(m_saved.back());
        m_saved.pop_back();
        m_stack.pop_back();
        m_instance = nullptr;
    }

    void objectInstance(const Directive &d) {
        requireWorld(d);
        if (m_instance)
            fail(d, fmt::format("ObjectInstance inside the ObjectBegin of '{}'", m_instance->name));
        m_scene.instanceUses.push_back({d.strings[0], placement(d), d.location});
    }

public:
    /// Named materials selected but never defined (checked at the end, as pbrt-v4 does).
    void checkNamedMaterials() const {
        for (const auto &[name, location] : m_namedMaterialUses)
            if (!m_scene.namedMaterials.count(name)) {
                std::vector<std::string> names;
                for (const auto &entry : m_scene.namedMaterials)
                    names.push_back(entry.first);
                throw LocatedError(location.str(),
                                   fmt::format("NamedMaterial '{}' is never defined{}", name,
                                               didYouMean(name, names)));
            }
    }

private:
    Scene &m_scene;
    GraphicsState m_state;
    std::vector<GraphicsState> m_saved;
    std::vector<std::pair<char, Location>> m_stack; ///< 'a'ttribute or 'o'bject, and where
    std::map<std::string, std::pair<Matrix, Matrix>> m_namedSystems;
    std::set<std::string> m_instanceNames;
    std::vector<std::pair<std::string, Location>> m_namedMaterialUses;
    InstanceDefinition *m_instance = nullptr; ///< points into m_scene.instances
    bool m_world = false;
    bool m_motionWarned = false, m_transformBeginWarned = false;
};

template <typename Parse> Scene build(Parse &&parse, const std::string &name) {
    Scene scene;
    Builder builder(scene);
    Location last{name, 1, 1};
    parse([&](const Directive &d) {
        last = d.location;
        builder.apply(d);
    });
    builder.finish(last);
    builder.checkNamedMaterials();
    return scene;
}

} // namespace

Scene readScene(const std::string &path) {
    return build([&](const auto &visit) { parseFile(path, visit); }, path);
}

Scene readSceneString(std::string_view text, const std::string &name) {
    return build([&](const auto &visit) { parseString(text, name, visit); }, name);
}

} // namespace nori::pbrt
