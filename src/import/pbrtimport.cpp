// pbrt-v4's entities onto our plugins, written as our XML (see pbrtimport.h). pbrt-v4's
// own reading of each parameter (its materials.cpp, lights.cpp, shapes.cpp, textures.cpp,
// media.cpp, cameras.cpp, film.cpp) is the specification of what is mapped; the table is
// docs/pbrt-scenes.md.
#include <nori/pbrtimport.h>

#include "import/pbrtgeometry.h"
#include "import/pbrtparams.h"
#include "import/xmlwriter.h"

#include <nori/plyfile.h>
#include <nori/strutil.h>
#include <nori/volumegrid.h>

#include <Eigen/Geometry>
#include <pugixml.hpp>

#include <array>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

namespace nori::pbrt {

namespace fs = std::filesystem;
using namespace importxml;

namespace {

// ---- pbrt-v4's parameter names, by entity and type ---------------------------------

using Names = std::vector<std::string>;

Names join(Names a, const Names &b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

const Names kMaterialCommon = {"displacement", "normalmap"};
const Names kRoughness = {"roughness", "uroughness", "vroughness", "remaproughness"};
const Names kLayered = {"thickness", "maxdepth", "nsamples", "g", "albedo"};
const std::map<std::string, Names> &materialNames() {
    static const std::map<std::string, Names> table = {
        {"diffuse", join(kMaterialCommon, {"reflectance", "sigma"})},
        {"coateddiffuse", join(join(join(kMaterialCommon, kRoughness), kLayered),
                               {"reflectance", "eta", "twosided"})},
        {"coatedconductor", join(join(kMaterialCommon, kLayered),
                                 {"interface.roughness", "interface.uroughness",
                                  "interface.vroughness", "interface.eta", "conductor.roughness",
                                  "conductor.uroughness", "conductor.vroughness", "conductor.eta",
                                  "conductor.k", "reflectance", "remaproughness"})},
        {"conductor", join(join(kMaterialCommon, kRoughness), {"eta", "k", "reflectance"})},
        {"dielectric", join(join(kMaterialCommon, kRoughness), {"eta"})},
        {"thindielectric", join(kMaterialCommon, {"eta"})},
        {"diffusetransmission", join(kMaterialCommon, {"reflectance", "transmittance", "scale"})},
        {"mix", join(kMaterialCommon, {"materials", "amount"})},
        {"interface", kMaterialCommon},
        {"measured", join(kMaterialCommon, {"filename"})},
        {"subsurface",
         join(join(kMaterialCommon, kRoughness),
              {"mfp", "sigma_a", "sigma_s", "reflectance", "name", "scale", "eta", "g"})},
        {"hair", join(kMaterialCommon, {"sigma_a", "color", "eumelanin", "pheomelanin", "eta",
                                        "beta_m", "beta_n", "alpha"})},
    };
    return table;
}

const Names kTextureMapping = {"mapping", "uscale", "vscale", "udelta", "vdelta", "v1", "v2"};
const std::map<std::string, Names> &textureNames() {
    static const std::map<std::string, Names> table = {
        {"imagemap", join(kTextureMapping, {"filename", "encoding", "invert", "scale", "filter",
                                            "maxanisotropy", "wrap"})},
        {"checkerboard", join(kTextureMapping, {"tex1", "tex2", "dimension"})},
        {"scale", {"tex", "scale"}},
        {"mix", {"tex1", "tex2", "amount"}},
        {"directionmix", {"tex1", "tex2", "dir"}},
        {"constant", {"value"}},
        {"bilerp", join(kTextureMapping, {"v00", "v01", "v10", "v11"})},
        {"dots", join(kTextureMapping, {"inside", "outside"})},
        {"fbm", {"octaves", "roughness"}},
        {"wrinkled", {"octaves", "roughness"}},
        {"windy", {}},
        {"marble", {"octaves", "roughness", "scale", "variation"}},
        {"ptex", {"filename", "encoding", "scale"}},
    };
    return table;
}

const std::map<std::string, Names> &lightNames() {
    static const std::map<std::string, Names> table = {
        {"point", {"I", "scale", "power", "from"}},
        {"spot", {"I", "scale", "power", "from", "to", "coneangle", "conedeltaangle"}},
        {"goniometric", {"I", "scale", "power", "filename"}},
        {"projection", {"I", "scale", "power", "filename", "fov"}},
        {"distant", {"L", "scale", "from", "to", "illuminance"}},
        {"infinite", {"L", "scale", "filename", "portal", "illuminance"}},
    };
    return table;
}

const Names kShapeCommon = {"alpha", "emissionfilename"};
const std::map<std::string, Names> &shapeNames() {
    static const std::map<std::string, Names> table = {
        {"sphere", join(kShapeCommon, {"radius", "zmin", "zmax", "phimax"})},
        {"disk", join(kShapeCommon, {"height", "radius", "innerradius", "phimax"})},
        {"cylinder", join(kShapeCommon, {"radius", "zmin", "zmax", "phimax"})},
        {"trianglemesh", join(kShapeCommon, {"indices", "P", "N", "S", "uv", "faceIndices"})},
        {"plymesh", join(kShapeCommon, {"filename", "displacement", "edgelength"})},
        {"bilinearmesh", join(kShapeCommon, {"indices", "P", "N", "uv", "faceIndices"})},
        {"loopsubdiv", join(kShapeCommon, {"levels", "indices", "P"})},
        {"curve", join(kShapeCommon, {"P", "basis", "degree", "type", "N", "width", "width0",
                                      "width1", "splitdepth"})},
    };
    return table;
}

const Names kMediumCommon = {"sigma_a", "sigma_s", "scale", "g", "Le", "Lescale", "preset"};
const std::map<std::string, Names> &mediumNames() {
    static const std::map<std::string, Names> table = {
        {"homogeneous", kMediumCommon},
        {"uniformgrid", join(kMediumCommon, {"density", "nx", "ny", "nz", "p0", "p1", "temperature",
                                             "temperaturecutoff", "temperaturescale"})},
        {"nanovdb", join(kMediumCommon, {"filename", "temperaturecutoff", "temperaturescale"})},
        {"rgbgrid", join(kMediumCommon, {"nx", "ny", "nz", "p0", "p1"})},
        {"cloud",
         {"density", "g", "sigma_a", "sigma_s", "wispiness", "frequency", "scale", "Le", "Lescale",
          "p0", "p1"}},
    };
    return table;
}

const std::map<std::string, Names> &cameraNames() {
    static const Names projective = {"shutteropen",  "shutterclose", "frameaspectratio",
                                     "screenwindow", "lensradius",   "focaldistance"};
    static const std::map<std::string, Names> table = {
        {"perspective", join(projective, {"fov"})},
        {"orthographic", projective},
        {"realistic",
         {"shutteropen", "shutterclose", "lensfile", "aperturediameter", "focusdistance",
          "aperture"}},
        {"spherical", {"shutteropen", "shutterclose", "mapping"}},
    };
    return table;
}

const Names kFilmNames = {"xresolution",  "yresolution",  "cropwindow", "pixelbounds",
                          "diagonal",     "filename",     "savefp16",   "iso",
                          "exposuretime", "whitebalance", "sensor",     "maxcomponentvalue",
                          "writefp16"};
const std::map<std::string, Names> &filmNames() {
    static const std::map<std::string, Names> table = {
        {"rgb", kFilmNames},
        {"gbuffer", join(kFilmNames, {"coordinatesystem"})},
        {"spectral", join(kFilmNames, {"nbuckets", "lambdamin", "lambdamax"})},
    };
    return table;
}

const std::map<std::string, Names> &filterNames() {
    static const std::map<std::string, Names> table = {
        {"box", {"xradius", "yradius"}},
        {"gaussian", {"xradius", "yradius", "sigma"}},
        {"mitchell", {"xradius", "yradius", "B", "C"}},
        {"sinc", {"xradius", "yradius", "tau"}},
        {"triangle", {"xradius", "yradius"}},
    };
    return table;
}

const std::map<std::string, Names> &samplerNames() {
    static const Names common = {"pixelsamples", "seed", "randomization"};
    static const std::map<std::string, Names> table = {
        {"zsobol", common},
        {"sobol", common},
        {"paddedsobol", common},
        {"halton", common},
        {"pmj02bn", common},
        {"independent", common},
        {"stratified", join(common, {"jitter", "xsamples", "ysamples"})},
    };
    return table;
}

const std::map<std::string, Names> &integratorNames() {
    static const Names common = {"maxdepth", "regularize", "lightsampler"};
    static const std::map<std::string, Names> table = {
        {"path", common},
        {"volpath", common},
        {"simplepath", {"maxdepth", "samplelights", "samplebsdf"}},
        {"simplevolpath", {"maxdepth"}},
        {"bdpt", join(common, {"visualizestrategies", "visualizeweights"})},
        {"lightpath", {"maxdepth"}},
        {"sppm", {"maxdepth", "photonsperiteration", "radius", "seed", "regularize"}},
        {"mlt",
         {"maxdepth", "bootstrapsamples", "chains", "mutationsperpixel", "largestepprobability",
          "sigma", "regularize"}},
        {"ambientocclusion", {"maxdistance", "cossample"}},
        {"randomwalk", {"maxdepth"}},
        {"aov", {"maxdistance", "cossample"}},
    };
    return table;
}

/// The parameters of `entity`, its type looked up in `table` (an unknown type is an error
/// with a suggestion).
Parameters checked(const Entity &entity, const std::string &kind,
                   const std::map<std::string, Names> &table) {
    const auto it = table.find(entity.type);
    if (it == table.end()) {
        Names types;
        for (const auto &entry : table)
            types.push_back(entry.first);
        throw LocatedError(entity.location.str(),
                           fmt::format("unknown {} type '{}'{}", kind, entity.type,
                                       didYouMean(entity.type, types)));
    }
    return Parameters(entity, fmt::format("{} '{}'", kind, entity.type), it->second);
}

// ---- XML writing (import/xmlwriter.h) -----------------------------------------------

/// Numbers of an inline mesh, written so that strtof reads back the same floats.
template <typename Values> std::string numberList(const Values &values, int perVertex) {
    std::string text;
    text.reserve(values.size() * 10);
    for (size_t i = 0; i < values.size(); ++i) {
        if (i > 0)
            text += (i % size_t(perVertex) == 0) ? ", " : " ";
        text += fmt::format("{}", values[i]);
    }
    return text;
}

Vector3f transformPoint(const Matrix &m, const Vector3f &p) {
    return (m * Eigen::Vector4d(p.x(), p.y(), p.z(), 1.0)).head<3>().cast<float>();
}
Vector3f transformVector(const Matrix &m, const Vector3f &v) {
    return (m.topLeftCorner<3, 3>() * v.cast<double>()).cast<float>();
}

// ---- The converter ------------------------------------------------------------------

class Converter {
public:
    Converter(const Scene &scene, const ConvertOptions &options)
        : m_scene(scene), m_options(options) {
        for (size_t i = 0; i < scene.textures.size(); ++i)
            m_textures.emplace(std::make_pair(scene.textures[i].valueType, scene.textures[i].name),
                               i);
        for (size_t i = 0; i < scene.media.size(); ++i)
            m_media.emplace(scene.media[i].name, i);
        for (const std::string &line : scene.warnings)
            m_result.warnings.push_back(line);
        for (const auto &[name, values] : scene.options)
            m_result.warnings.push_back(fmt::format(
                "Option \"{}\": not applied (pbrt-v4's command-line options do not carry over)",
                name));
    }

    Conversion run() {
        m_root = m_document.append_child("scene");
        m_scratch = m_document.append_child("scratch");
        // Declarations (textures, BSDFs, media) go before this mark, so that they come
        // before everything that refers to them, the camera's medium included.
        m_bodyStart = m_root.append_child(pugi::node_comment);
        m_bodyStart.set_value(" the scene ");
        readFilm();
        writeIntegrator();
        writeSampler();
        writeCamera();
        for (const InstanceDefinition &definition : m_scene.instances)
            writeInstanceDefinition(definition);
        for (const InstanceUse &use : m_scene.instanceUses)
            writeInstanceUse(use);
        for (const ShapeEntity &shape : m_scene.shapes)
            writeShape(m_root, shape, true);
        for (const LightEntity &light : m_scene.lights)
            writeLight(light);

        m_document.remove_child(m_scratch);
        std::ostringstream text;
        m_document.save(text, "    ", pugi::format_default, pugi::encoding_utf8);
        m_result.xml = text.str();
        for (const std::string &line : m_warnings.lines())
            m_result.warnings.push_back(line);
        return std::move(m_result);
    }

private:
    /// A new declaration (a texture, a BSDF, a medium), made aside until finished.
    pugi::xml_node declare(const char *tag) { return m_scratch.append_child(tag); }
    /// Moves a finished declaration into the scene: after every declaration finished
    /// before it (which includes the ones it refers to), before the camera and shapes.
    void publish(pugi::xml_node node) { m_root.insert_move_before(node, m_bodyStart); }

    void warn(const Location &where, const std::string &feature, const std::string &message) {
        m_warnings.add(where, feature, message);
    }

    /// A file name of the pbrt-v4 file as the XML must write it: resolved against the
    /// scene's folder, then relative to the XML's.
    std::string resolvePath(const std::string &name) const {
        fs::path path(name);
        if (path.is_relative())
            path = fs::path(m_options.sceneDirectory) / path;
        path = path.lexically_normal();
        const fs::path xmlDirectory = fs::absolute(m_options.xmlDirectory).lexically_normal();
        const fs::path relative =
            fs::absolute(path).lexically_normal().lexically_relative(xmlDirectory);
        return relative.empty() ? path.string() : relative.generic_string();
    }

    /// A new file in the side-file folder, and its name as the XML writes it.
    std::pair<std::string, std::string> sideFile(const std::string &stem,
                                                 const std::string &extension) {
        if (m_options.sideFileDirectory.empty())
            throw NoriException("the pbrt-v4 importer needs a folder for the mesh and grid files "
                                "it writes");
        fs::create_directories(m_options.sideFileDirectory);
        const fs::path path = fs::path(m_options.sideFileDirectory) /
                              fmt::format("{}{:04d}{}", stem, m_sideFiles++, extension);
        m_result.sideFiles.push_back(path.string());
        const fs::path xmlDirectory = fs::absolute(m_options.xmlDirectory).lexically_normal();
        return {path.string(), fs::absolute(path)
                                   .lexically_normal()
                                   .lexically_relative(xmlDirectory)
                                   .generic_string()};
    }

    // ---- film, camera, sampler, integrator ----

    void readFilm() {
        const Parameters film = checked(m_scene.film, "film", filmNames());
        if (m_scene.film.type == "spectral")
            warn(m_scene.film.location, "film", "film 'spectral' is written as an RGB film (ours)");
        if (m_scene.film.type == "gbuffer")
            warn(m_scene.film.location, "film",
                 "film 'gbuffer': the image is rendered; for its layers give nori --aovs "
                 "albedo,normal,depth,position");
        m_width = film.getInt("xresolution", 1280);
        m_height = film.getInt("yresolution", 720);
        if (m_width <= 0 || m_height <= 0)
            throw LocatedError(
                m_scene.film.location.str(),
                fmt::format("film resolution {} × {} is not positive", m_width, m_height));
        m_result.outputName = film.getString("filename", "");
        m_filmDiagonal = film.getFloat("diagonal", 35.0f);
        readCrop(film);
        const std::string sensor = film.getString("sensor", "cie1931");
        if (sensor != "cie1931")
            warn(m_scene.film.location, "sensor",
                 fmt::format("film sensor '{}': rendered with the CIE 1931 observer (sRGB)",
                             sensor));
        // pbrt-v4 balances a cie1931 sensor only when asked (other sensors, at 6500 K by
        // default, are our cie1931 stand-in, for which 6500 K is nearly no balance).
        m_whiteBalance = film.getFloat("whitebalance", 0.0f);
        if (m_whiteBalance < 0.0f || !std::isfinite(m_whiteBalance))
            film.fail(*film.find("whitebalance"),
                      fmt::format("film whitebalance {} K is not a temperature", m_whiteBalance));
        // pbrt-v4's imaging ratio (its PixelSensor): exposure time × ISO/100 scales the
        // image, the exposure time being the shutter's (close − open) unless the film gives
        // one; transport is linear, so the lights are scaled instead.
        const Parameters camera = checked(m_scene.camera, "camera", cameraNames());
        const float shutter =
            camera.getFloat("shutterclose", 1.0f) - camera.getFloat("shutteropen", 0.0f);
        m_imagingRatio =
            film.getFloat("exposuretime", shutter) * film.getFloat("iso", 100.0f) / 100.0f;
    }

    /// The pixels pbrt-v4 renders (its FilmBaseParameters): `cropwindow`, a fraction of
    /// the image clamped to [0, 1] and rounded up to pixels, wins over `pixelbounds`,
    /// which is clamped to the image.
    void readCrop(const Parameters &film) {
        m_crop = Eigen::AlignedBox2i(Eigen::Vector2i(0, 0), Eigen::Vector2i(m_width, m_height));
        if (film.has("cropwindow")) {
            const std::vector<float> window = film.getFloats("cropwindow");
            if (window.size() != 4)
                film.fail(*film.find("cropwindow"),
                          fmt::format("film cropwindow takes 4 values, got {}", window.size()));
            auto pixel = [](float fraction, int resolution) {
                return int(std::ceil(float(resolution) * std::clamp(fraction, 0.0f, 1.0f)));
            };
            m_crop = Eigen::AlignedBox2i(
                Eigen::Vector2i(pixel(std::min(window[0], window[1]), m_width),
                                pixel(std::min(window[2], window[3]), m_height)),
                Eigen::Vector2i(pixel(std::max(window[0], window[1]), m_width),
                                pixel(std::max(window[2], window[3]), m_height)));
        } else if (film.has("pixelbounds")) {
            const std::vector<int> bounds = film.getInts("pixelbounds");
            if (bounds.size() != 4)
                film.fail(*film.find("pixelbounds"),
                          fmt::format("film pixelbounds takes 4 values, got {}", bounds.size()));
            m_crop = m_crop.intersection(Eigen::AlignedBox2i(
                Eigen::Vector2i(bounds[0], bounds[2]), Eigen::Vector2i(bounds[1], bounds[3])));
        }
        const Eigen::Vector2i size = m_crop.max() - m_crop.min();
        if (!(size.x() > 0 && size.y() > 0))
            throw LocatedError(m_scene.film.location.str(),
                               fmt::format("film crop of {} x {} pixels at ({}, {}) is empty",
                                           std::max(size.x(), 0), std::max(size.y(), 0),
                                           m_crop.min().x(), m_crop.min().y()));
    }

    void writeIntegrator() {
        const Entity &entity = m_scene.integrator;
        const Parameters params = checked(entity, "integrator", integratorNames());
        const int maxDepth = params.getInt("maxdepth", 5);
        const std::string &type = entity.type;
        pugi::xml_node node;
        if (type == "ambientocclusion" || type == "aov") {
            node = addObject(m_root, "integrator", "ao");
            if (params.has("maxdistance"))
                addFloat(node, "length", params.getFloat("maxdistance", 0.0f));
            if (type == "aov")
                warn(entity.location, "integrator", "integrator 'aov' is rendered as 'ao'");
            return;
        }
        std::string ours = "path";
        if (type == "volpath" || type == "simplevolpath" || type == "randomwalk")
            ours = "volpath";
        else if (type == "bdpt")
            ours = "bdpt";
        else if (type == "lightpath")
            ours = "lighttracer";
        else if (type == "sppm")
            ours = "progressivephotonmapper";
        if (type == "simplepath" || type == "simplevolpath" || type == "mlt" ||
            type == "randomwalk")
            warn(
                entity.location, "integrator",
                fmt::format("integrator '{}' is rendered by our '{}' (the same image, other noise)",
                            type, ours));
        if (params.getBool("regularize", false))
            warn(entity.location, "regularize", "integrator regularize: not applied");
        if (params.getBool("visualizestrategies", false) ||
            params.getBool("visualizeweights", false))
            warn(entity.location, "visualize",
                 "bdpt visualizestrategies/visualizeweights: give bdpt's `strategies` instead");
        node = addObject(m_root, "integrator", ours);
        if (ours == "progressivephotonmapper") {
            if (params.has("photonsperiteration"))
                addInteger(node, "photonCount", params.getInt("photonsperiteration", -1));
            if (params.has("radius"))
                addFloat(node, "photonRadius", params.getFloat("radius", 1.0f));
            if (params.has("maxdepth"))
                warn(entity.location, "sppm-maxdepth",
                     "sppm maxdepth: our photon mapper follows "
                     "paths until Russian roulette ends them");
            return;
        }
        // pbrt-v4's maxdepth counts scattering events, as our maxDepth does.
        addInteger(node, "maxDepth", maxDepth);
    }

    void writeSampler() {
        const Entity &entity = m_scene.sampler;
        const Parameters params = checked(entity, "sampler", samplerNames());
        std::string ours = "sobol";
        int samples = params.getInt("pixelsamples", 16);
        if (entity.type == "independent") {
            ours = "independent";
        } else if (entity.type == "stratified") {
            ours = "stratified";
            const int x = params.getInt("xsamples", 4), y = params.getInt("ysamples", 4);
            samples = x * y;
        } else if (entity.type != "sobol") {
            warn(entity.location, "sampler",
                 fmt::format("sampler '{}' is our 'sobol' (the nearest of ours)", entity.type));
        }
        pugi::xml_node node = addObject(m_root, "sampler", ours);
        addInteger(node, "sampleCount", std::max(1, samples));
        if (params.has("seed"))
            addInteger(node, "seed", params.getInt("seed", 0));
    }

    void writeCamera() {
        const CameraEntity &camera = m_scene.camera;
        const Parameters params = checked(camera, "camera", cameraNames());
        pugi::xml_node node;
        if (camera.type == "realistic") {
            node = addObject(m_root, "camera", "realistic");
            addString(node, "lensFile", resolvePath(params.getString("lensfile", "")));
            if (params.has("aperturediameter"))
                addFloat(node, "apertureDiameter", params.getFloat("aperturediameter", 1.0f));
            addFloat(node, "focusDistance", params.getFloat("focusdistance", 10.0f));
            addFloat(node, "filmDiagonal", m_filmDiagonal);
            if (params.has("aperture"))
                warn(camera.location, "aperture",
                     "realistic camera: the aperture image is not "
                     "used (a circular aperture is)");
        } else {
            if (camera.type != "perspective")
                warn(camera.location, "camera",
                     fmt::format("camera '{}' is rendered as a perspective camera", camera.type));
            node = addObject(m_root, "camera", "perspective");
            writePerspective(node, params);
        }
        addInteger(node, "width", m_width);
        addInteger(node, "height", m_height);
        if (m_crop.min() != Eigen::Vector2i(0, 0) ||
            m_crop.max() != Eigen::Vector2i(m_width, m_height)) {
            addInteger(node, "cropOffsetX", m_crop.min().x());
            addInteger(node, "cropOffsetY", m_crop.min().y());
            addInteger(node, "cropWidth", m_crop.max().x() - m_crop.min().x());
            addInteger(node, "cropHeight", m_crop.max().y() - m_crop.min().y());
        }
        if (m_whiteBalance != 0.0f)
            addFloat(node, "whiteBalance", m_whiteBalance);
        // pbrt-v4's camera space has +x to the image's right: our "eth" convention.
        addString(node, "convention", "eth");
        // pbrt-v4 samples each pixel from its whole filter, past the image's edge.
        addBoolean(node, "sampleBorder", true);
        addTransform(node, "toWorld", camera.toWorld);
        writeFilter(node);
        if (!camera.medium.empty())
            addRef(node, mediumId(camera.medium, camera.location));
    }

    void writePerspective(pugi::xml_node node, const Parameters &params) {
        // pbrt-v4's screen window (PBR 4th ed. §5.1.3): [−a, a] × [−1, 1] for a wide image
        // of aspect a, [−1, 1] × [−1/a, 1/a] for a tall one, in units of tan(fov/2).
        const float aspect = params.getFloat("frameaspectratio", float(m_width) / float(m_height));
        if (!(aspect > 0.0f) || !std::isfinite(aspect))
            params.fail(*params.find("frameaspectratio"),
                        fmt::format("camera frameaspectratio {} is not positive", aspect));
        std::vector<float> window =
            aspect > 1.0f ? std::vector<float>{-aspect, aspect, -1.0f, 1.0f}
                          : std::vector<float>{-1.0f, 1.0f, -1.0f / aspect, 1.0f / aspect};
        if (params.has("screenwindow")) {
            window = params.getFloats("screenwindow");
            if (window.size() != 4)
                params.fail(*params.find("screenwindow"), "camera: \"float screenwindow\" takes "
                                                          "four numbers");
        }
        const float halfWidth = 0.5f * (window[1] - window[0]);
        const float halfHeight = 0.5f * (window[3] - window[2]);
        if (!(halfWidth > 0.0f && halfHeight > 0.0f))
            params.fail(*params.find("screenwindow"),
                        "camera: \"float screenwindow\" needs xmin < xmax and ymin < ymax");
        const double fov = params.getFloat("fov", 90.0f);
        if (!(fov > 0.0 && fov < 180.0))
            params.fail(*params.find("fov"), fmt::format("camera fov {} is not in (0, 180)", fov));
        const bool centred = std::abs(window[0] + window[1]) <= 1e-6f * halfWidth &&
                             std::abs(window[2] + window[3]) <= 1e-6f * halfHeight;
        const float imageAspect = float(m_width) / float(m_height);
        const bool squarePixels =
            std::abs(halfWidth / halfHeight - imageAspect) <= 1e-4f * imageAspect;
        if (centred && squarePixels) {
            // The common case, written as our fov on the image's width.
            const double horizontal =
                2.0 * std::atan(std::tan(fov * 3.14159265358979323846 / 360.0) * halfWidth) *
                180.0 / 3.14159265358979323846;
            addFloat(node, "fov", float(horizontal));
        } else {
            // Off-centre, or pixels that are not square: pbrt-v4's window as it is, in
            // the same units of tan(fov/2).
            addFloat(node, "fov", float(fov));
            addString(node, "screenWindow",
                      fmt::format("{} {} {} {}", window[0], window[1], window[2], window[3]));
        }
        addFloat(node, "farClip", 1e30f);
        if (params.getFloat("lensradius", 0.0f) > 0.0f) {
            addFloat(node, "lensRadius", params.getFloat("lensradius", 0.0f));
            addFloat(node, "focalDistance", params.getFloat("focaldistance", 1e6f));
        }
    }

    void writeFilter(pugi::xml_node camera) {
        const Entity &entity = m_scene.filter;
        const Parameters params = checked(entity, "filter", filterNames());
        const std::map<std::string, float> defaultRadius = {{"box", 0.5f},
                                                            {"gaussian", 1.5f},
                                                            {"mitchell", 2.0f},
                                                            {"sinc", 4.0f},
                                                            {"triangle", 2.0f}};
        const float xRadius = params.getFloat("xradius", defaultRadius.at(entity.type));
        const float yRadius = params.getFloat("yradius", defaultRadius.at(entity.type));
        if (xRadius != yRadius)
            warn(entity.location, "filter-radius",
                 fmt::format("filter radii {} and {}: ours are round, of radius {}", xRadius,
                             yRadius, xRadius));
        std::string ours = entity.type == "triangle" ? "tent" : entity.type;
        if (entity.type == "sinc") {
            warn(entity.location, "filter", "filter 'sinc' is our 'mitchell' (the nearest)");
            ours = "mitchell";
        }
        pugi::xml_node node = addObject(camera, "rfilter", ours);
        addFloat(node, "radius", xRadius);
        if (entity.type == "gaussian")
            addFloat(node, "stddev", params.getFloat("sigma", 0.5f));
        if (entity.type == "mitchell") {
            addFloat(node, "B", params.getFloat("B", 1.0f / 3.0f));
            addFloat(node, "C", params.getFloat("C", 1.0f / 3.0f));
        }
    }

    // ---- textures ----

    /// pbrt-v4's `encoding` of an image texture: "sRGB" (the default for PNG files),
    /// "linear" (for every other format), "gamma G". It decodes 8-bit images only:
    /// float formats (EXR, PFM, HDR) are linear whatever it says.
    void writeEncoding(pugi::xml_node image, const Parameters &params,
                       const std::string &filename) {
        const std::string extension = toLower(fs::path(filename).extension().string());
        const std::string encoding =
            params.getString("encoding", extension == ".png" ? "sRGB" : "linear");
        float gamma = 0.0f;
        if (encoding != "sRGB" && encoding != "linear") {
            std::istringstream words(encoding);
            std::string keyword, extra;
            if (!(words >> keyword >> gamma) || keyword != "gamma" || (words >> extra) ||
                !(gamma > 0.0f && gamma <= 16.0f))
                params.fail(*params.find("encoding"),
                            fmt::format("image encoding '{}' is not \"sRGB\", \"linear\" or "
                                        "\"gamma G\" with G in (0, 16]",
                                        encoding));
        }
        if (extension == ".exr" || extension == ".pfm" || extension == ".hdr")
            addString(image, "colorSpace", "linear");
        else if (gamma > 0.0f)
            addFloat(image, "gamma", gamma);
        else
            addString(image, "colorSpace", encoding == "sRGB" ? "srgb" : "linear");
    }

    /// The id of the declared texture `name` of `valueType`, declared on first use.
    std::string textureId(const std::string &name, const std::string &valueType,
                          const Location &where, int depth = 0) {
        const auto it = m_textures.find({valueType, name});
        if (it == m_textures.end()) {
            std::vector<std::string> known;
            for (const auto &entry : m_textures)
                if (entry.first.first == valueType)
                    known.push_back(entry.first.second);
            throw LocatedError(where.str(), fmt::format("no {} texture named '{}'{}", valueType,
                                                        name, didYouMean(name, known)));
        }
        std::string id = fmt::format("{}texture:{}", valueType == "float" ? "float" : "", name);
        if (m_declaredTextures.count(id))
            return id;
        if (depth > 64)
            throw LocatedError(where.str(), fmt::format("texture '{}' refers to itself", name));
        m_declaredTextures.insert(id);
        pugi::xml_node node = writeTexture(m_scene.textures[it->second], depth + 1);
        node.append_attribute("id") = id.c_str();
        publish(node);
        return id;
    }

    /// Writes a colour or float parameter: a <color>, or a <ref> to a declared texture.
    void addTextureValue(pugi::xml_node parent, const std::string &name, const TextureValue &value,
                         const std::string &valueType, const Location &where, int depth = 0) {
        if (value.isTexture())
            addRef(parent, textureId(value.texture, valueType, where, depth), name);
        else
            addColor(parent, name, value.constant);
    }

    void addSpectrum(pugi::xml_node parent, const std::string &ours, const Parameters &params,
                     const std::string &name, SpectrumKind kind, const Color3f &defaultValue,
                     int depth = 0) {
        addTextureValue(parent, ours,
                        params.getSpectrum(name, kind, defaultValue, m_options.sceneDirectory),
                        "spectrum", locationOf(params, name), depth);
    }

    void addFloatTexture(pugi::xml_node parent, const std::string &ours, const Parameters &params,
                         const std::string &name, float defaultValue, int depth = 0) {
        const TextureValue value = params.getFloatTexture(name, defaultValue);
        if (value.isTexture())
            addRef(parent, textureId(value.texture, "float", locationOf(params, name), depth),
                   ours);
        else
            addFloat(parent, ours, value.constant.r());
    }

    static Location locationOf(const Parameters &params, const std::string &name) {
        const Parameter *parameter = params.find(name);
        return parameter ? parameter->location : params.entity().location;
    }

    /// A texture's value parameter (tex1, tex2, tex, value, ...): float or spectrum as the
    /// texture is.
    void addTextureInput(pugi::xml_node parent, const std::string &ours, const Parameters &params,
                         const std::string &name, const TextureEntity &texture, float defaultValue,
                         int depth) {
        if (texture.valueType == "float")
            addFloatTexture(parent, ours, params, name, defaultValue, depth);
        else
            addSpectrum(parent, ours, params, name, SpectrumKind::Unbounded, Color3f(defaultValue),
                        depth);
    }

    pugi::xml_node writeTexture(const TextureEntity &texture, int depth) {
        const Parameters params = checked(texture, "texture", textureNames());
        const std::string mapping = params.getString("mapping", "uv");
        if (mapping != "uv")
            warn(texture.location, "mapping-" + mapping,
                 fmt::format("texture mapping '{}': the shape's uv are used instead", mapping));
        const std::string &type = texture.type;
        if (type == "imagemap")
            return writeImageTexture(texture, params);
        if (type == "checkerboard") {
            if (params.getInt("dimension", 2) != 2)
                warn(texture.location, "checkerboard3d",
                     "3D checkerboard: rendered as the 2D one over uv");
            // mix(tex1, tex2) by a 0/1 checkerboard over s = uscale·u + udelta, t likewise:
            // even cells (⌊s⌋ + ⌊t⌋ even) are tex1, as pbrt-v4's.
            pugi::xml_node node = declare("texture");
            node.append_attribute("type") = "mix";
            addTextureInput(node, "tex1", params, "tex1", texture, 1.0f, depth);
            addTextureInput(node, "tex2", params, "tex2", texture, 0.0f, depth);
            pugi::xml_node amount = addObject(node, "texture", "checkerboard_float", "amount");
            addFloat(amount, "value1", 0.0f);
            addFloat(amount, "value2", 1.0f);
            const float uScale = params.getFloat("uscale", 1.0f),
                        vScale = params.getFloat("vscale", 1.0f);
            child(amount, "vector", "scale", fmt::format("{}, {}", 1.0f / uScale, 1.0f / vScale));
            child(amount, "point", "delta",
                  fmt::format("{}, {}", -params.getFloat("udelta", 0.0f),
                              -params.getFloat("vdelta", 0.0f)));
            return node;
        }
        if (type == "scale") {
            pugi::xml_node node = declare("texture");
            node.append_attribute("type") = "scale";
            addTextureInput(node, "tex", params, "tex", texture, 1.0f, depth);
            addFloatTexture(node, "scale", params, "scale", 1.0f, depth);
            return node;
        }
        if (type == "mix" || type == "directionmix") {
            pugi::xml_node node = declare("texture");
            node.append_attribute("type") = "mix";
            addTextureInput(node, "tex1", params, "tex1", texture, 0.0f, depth);
            addTextureInput(node, "tex2", params, "tex2", texture, 1.0f, depth);
            if (type == "mix") {
                addFloatTexture(node, "amount", params, "amount", 0.5f, depth);
            } else {
                warn(texture.location, "directionmix",
                     "texture 'directionmix': an even mix of tex1 and tex2 stands in for it");
                addFloat(node, "amount", 0.5f);
            }
            return node;
        }
        if (type == "constant") {
            pugi::xml_node node = declare("texture");
            node.append_attribute("type") = "constant";
            addTextureInput(node, "value", params, "value", texture, 1.0f, depth);
            return node;
        }
        warn(texture.location, "texture-" + type,
             fmt::format("texture '{}' is not supported: a constant 0.5 stands in for it", type));
        pugi::xml_node node = declare("texture");
        node.append_attribute("type") = "constant";
        addFloat(node, "value", 0.5f);
        return node;
    }

    pugi::xml_node writeImageTexture(const TextureEntity &texture, const Parameters &params) {
        const std::string filename = params.getString("filename", "");
        if (filename.empty())
            throw LocatedError(texture.location.str(),
                               "texture 'imagemap' needs a \"string filename\"");
        pugi::xml_node image = declare("texture");
        image.append_attribute("type") = "image";
        addString(image, "filename", resolvePath(filename));
        writeEncoding(image, params, filename);
        const std::string wrap = params.getString("wrap", "repeat");
        if (wrap == "repeat" || wrap == "clamp") {
            addString(image, "wrap", wrap);
        } else {
            warn(texture.location, "wrap-" + wrap,
                 fmt::format("image wrap mode '{}': clamped instead", wrap));
            addString(image, "wrap", "clamp");
        }
        const std::string filter = params.getString("filter", "bilinear");
        const std::map<std::string, std::string> filters = {{"point", "nearest"},
                                                            {"bilinear", "bilinear"},
                                                            {"trilinear", "trilinear"},
                                                            {"ewa", "ewa"}};
        const auto ourFilter = filters.find(filter);
        if (ourFilter == filters.end())
            params.fail(*params.find("filter"),
                        fmt::format("texture 'imagemap': unknown filter '{}'{}", filter,
                                    didYouMean(filter, {"point", "bilinear", "trilinear", "ewa"})));
        addString(image, "filter", ourFilter->second);
        if (params.has("maxanisotropy"))
            addFloat(image, "maxAnisotropy", params.getFloat("maxanisotropy", 8.0f));
        child(image, "vector", "uvScale",
              fmt::format("{}, {}", params.getFloat("uscale", 1.0f),
                          params.getFloat("vscale", 1.0f)));
        child(image, "vector", "uvOffset",
              fmt::format("{}, {}", params.getFloat("udelta", 0.0f),
                          params.getFloat("vdelta", 0.0f)));
        const bool invert = params.getBool("invert", false);
        const float scale = params.getFloat("scale", 1.0f);
        if (scale == 1.0f && !invert)
            return image;
        // scale(image): the image is declared first, with an id of its own.
        const std::string imageId = fmt::format("image:{}", m_images++);
        image.append_attribute("id") = imageId.c_str();
        publish(image);
        // pbrt-v4: scale · value, then 1 − that when inverted.
        pugi::xml_node scaled = declare("texture");
        scaled.append_attribute("type") = "scale";
        addRef(scaled, imageId, "tex");
        addFloat(scaled, "scale", scale);
        if (!invert)
            return scaled;
        const std::string scaledId = imageId + ":scaled";
        scaled.append_attribute("id") = scaledId.c_str();
        publish(scaled);
        // 1 − x as mix(1, 0; x): exact for a float texture; a colour one is mixed by its
        // luminance (the mix texture's amount), which only a grey image keeps exact.
        if (texture.valueType != "float")
            warn(texture.location, "invert-colour",
                 "image texture 'invert' of a colour image: inverted by its luminance");
        pugi::xml_node inverted = declare("texture");
        inverted.append_attribute("type") = "mix";
        addFloat(inverted, "tex1", 1.0f);
        addFloat(inverted, "tex2", 0.0f);
        addRef(inverted, scaledId, "amount");
        return inverted;
    }

    // ---- materials ----

    /// What a shape takes from its material besides the BSDF: pbrt-v4 keeps bump and
    /// normal maps on the material, we on the shape.
    struct MaterialRef {
        std::string bsdfId; ///< "" for `interface`: no BSDF (a medium boundary)
        const MaterialEntity *entity = nullptr;
    };

    const MaterialEntity &namedMaterial(const std::string &name, const Location &where) const {
        const auto it = m_scene.namedMaterials.find(name);
        if (it == m_scene.namedMaterials.end()) {
            std::vector<std::string> known;
            for (const auto &entry : m_scene.namedMaterials)
                known.push_back(entry.first);
            throw LocatedError(where.str(), fmt::format("no material named '{}'{}", name,
                                                        didYouMean(name, known)));
        }
        return it->second;
    }

    MaterialRef materialOf(const ShapeEntity &shape) {
        if (!shape.namedMaterial.empty())
            return materialRef(namedMaterial(shape.namedMaterial, shape.location),
                               "material:" + shape.namedMaterial, 0);
        const int index = std::max(shape.material, 0);
        return materialRef(m_scene.materials[size_t(index)], fmt::format("material-{}", index), 0);
    }

    MaterialRef materialRef(const MaterialEntity &material, const std::string &id, int depth) {
        MaterialRef ref;
        ref.entity = &material;
        if (material.type == "interface" || material.type == "none" || material.type.empty())
            return ref;
        ref.bsdfId = id;
        if (m_declaredMaterials.insert(id).second) {
            if (depth > 32)
                throw LocatedError(material.location.str(),
                                   "mix materials nest too deep (a cycle?)");
            pugi::xml_node node = writeMaterial(material, depth);
            node.append_attribute("id") = id.c_str();
            publish(node);
        }
        return ref;
    }

    /// Wraps a one-sided reflecting BSDF so that it reflects on both sides, as pbrt-v4's do.
    pugi::xml_node twoSided() {
        pugi::xml_node node = declare("bsdf");
        node.append_attribute("type") = "twosided";
        return node;
    }

    /// pbrt-v4's roughness parameters as one α (`remaproughness`: α = √r): constant
    /// isotropic or anisotropic values, or a texture.
    struct Roughness {
        TextureValue u, v;
        bool remap = true;
        float alphaU() const {
            return remap ? std::sqrt(std::max(u.constant.r(), 0.0f)) : u.constant.r();
        }
        float alphaV() const {
            return remap ? std::sqrt(std::max(v.constant.r(), 0.0f)) : v.constant.r();
        }
        bool textured() const { return u.isTexture() || v.isTexture(); }
        /// pbrt-v4's EffectivelySmooth: both α below 10⁻³.
        bool smooth() const { return !textured() && std::max(alphaU(), alphaV()) < 1e-3f; }
    };

    static Roughness roughnessOf(const Parameters &params, const std::string &prefix = "") {
        Roughness r;
        const TextureValue both = params.getFloatTexture(prefix + "roughness", 0.0f);
        r.u = params.has(prefix + "uroughness")
                  ? params.getFloatTexture(prefix + "uroughness", 0.0f)
                  : both;
        r.v = params.has(prefix + "vroughness")
                  ? params.getFloatTexture(prefix + "vroughness", 0.0f)
                  : both;
        r.remap = params.getBool("remaproughness", true);
        return r;
    }

    /// A microfacet BSDF's roughness from pbrt-v4's: `alpha`, or `alphaU` and `alphaV`
    /// when anisotropic; constants remapped here (α = √r), textures by `remapRoughness`.
    void addAlpha(pugi::xml_node node, const Roughness &r, const Parameters &params) {
        const Location &where = params.entity().location;
        // With a texture, our plugin remaps every value, constants included.
        const bool pluginRemaps = r.textured() && r.remap;
        auto add = [&](const char *name, const TextureValue &value, float alpha) {
            if (value.isTexture())
                addRef(node, textureId(value.texture, "float", where), name);
            else
                addFloat(node, name, pluginRemaps ? value.constant.r() : alpha);
        };
        const bool isotropic = r.u.isTexture() ? r.v.isTexture() && r.u.texture == r.v.texture
                                               : !r.v.isTexture() && r.alphaU() == r.alphaV();
        if (isotropic) {
            add("alpha", r.u, r.alphaU());
        } else {
            add("alphaU", r.u, r.alphaU());
            add("alphaV", r.v, r.alphaV());
        }
        if (pluginRemaps)
            addBoolean(node, "remapRoughness", true);
    }

    pugi::xml_node writeMaterial(const MaterialEntity &material, int depth) {
        const Parameters params = checked(material, "material", materialNames());
        const std::string &type = material.type;
        const std::string &dir = m_options.sceneDirectory;
        if (type == "diffuse") {
            if (params.getFloatTexture("sigma", 0.0f).constant.r() != 0.0f || params.has("sigma"))
                warn(material.location, "sigma", "diffuse sigma (Oren–Nayar): rendered Lambertian");
            pugi::xml_node wrapper = twoSided();
            pugi::xml_node node = addObject(wrapper, "bsdf", "diffuse");
            addSpectrum(node, "albedo", params, "reflectance", SpectrumKind::Reflectance,
                        Color3f(0.5f));
            return wrapper;
        }
        if (type == "coateddiffuse") {
            pugi::xml_node node = declare("bsdf");
            node.append_attribute("type") = "coateddiffuse";
            addSpectrum(node, "reflectance", params, "reflectance", SpectrumKind::Reflectance,
                        Color3f(0.5f));
            writeLayerRoughness(node, params, "", "roughness", "uRoughness", "vRoughness");
            addBoolean(node, "remapRoughness", params.getBool("remaproughness", true));
            addFloat(node, "eta", constantFloat(params, "eta", 1.5f));
            writeLayerMedium(node, params);
            if (!params.getBool("twosided", true))
                warn(material.location, "coated-onesided",
                     "coateddiffuse twosided false: rendered two-sided");
            return node;
        }
        if (type == "coatedconductor") {
            pugi::xml_node node = declare("bsdf");
            node.append_attribute("type") = "coatedconductor";
            writeLayerRoughness(node, params, "interface.", "interfaceRoughness",
                                "interfaceURoughness", "interfaceVRoughness");
            writeLayerRoughness(node, params, "conductor.", "conductorRoughness",
                                "conductorURoughness", "conductorVRoughness");
            addFloat(node, "interfaceEta", constantFloat(params, "interface.eta", 1.5f));
            if (params.has("reflectance")) {
                addSpectrum(node, "reflectance", params, "reflectance", SpectrumKind::Reflectance,
                            Color3f(0.0f));
            } else {
                addSpectrum(node, "conductorEta", params, "conductor.eta", SpectrumKind::Unbounded,
                            namedRGB("metal-Cu-eta"));
                addSpectrum(node, "conductorK", params, "conductor.k", SpectrumKind::Unbounded,
                            namedRGB("metal-Cu-k"));
            }
            addBoolean(node, "remapRoughness", params.getBool("remaproughness", true));
            writeLayerMedium(node, params);
            return node;
        }
        if (type == "conductor") {
            const Roughness roughness = roughnessOf(params);
            pugi::xml_node wrapper = twoSided();
            pugi::xml_node node =
                addObject(wrapper, "bsdf", roughness.smooth() ? "conductor" : "roughconductor");
            if (!roughness.smooth()) {
                addString(node, "distribution", "ggx");
                addAlpha(node, roughness, params);
            }
            if (params.has("reflectance")) {
                // pbrt-v4: η = 1 and k = 2√r/√(1 − r), the index whose normal-incidence
                // Fresnel reflectance is r.
                const TextureValue r = params.getSpectrum("reflectance", SpectrumKind::Reflectance,
                                                          Color3f(0.0f), dir);
                if (r.isTexture())
                    params.fail(*params.find("reflectance"),
                                "conductor: a reflectance texture is supported on "
                                "coatedconductor only; give a colour");
                const Color3f c = r.constant.min(0.9999f).max(0.0f);
                addColor(node, "eta", Color3f(1.0f));
                addColor(node, "k", Color3f(2.0f * c.sqrt() / (Color3f(1.0f) - c).sqrt()));
            } else {
                addSpectrum(node, "eta", params, "eta", SpectrumKind::Unbounded,
                            namedRGB("metal-Cu-eta"));
                addSpectrum(node, "k", params, "k", SpectrumKind::Unbounded,
                            namedRGB("metal-Cu-k"));
            }
            addFloat(node, "extIOR", 1.0f);
            return wrapper;
        }
        if (type == "dielectric" || type == "thindielectric") {
            const float eta = etaOf(params);
            const Roughness roughness = type == "dielectric" ? roughnessOf(params) : Roughness{};
            const char *ours = type == "thindielectric" ? "thindielectric"
                               : roughness.smooth()     ? "dielectric"
                                                        : "roughdielectric";
            pugi::xml_node node = declare("bsdf");
            node.append_attribute("type") = ours;
            addFloat(node, "intIOR", eta);
            addFloat(node, "extIOR", 1.0f);
            if (std::string(ours) == "roughdielectric") {
                addString(node, "distribution", "ggx");
                addAlpha(node, roughness, params);
            }
            return node;
        }
        if (type == "diffusetransmission") {
            pugi::xml_node node = declare("bsdf");
            node.append_attribute("type") = "diffusetransmission";
            addSpectrum(node, "reflectance", params, "reflectance", SpectrumKind::Reflectance,
                        Color3f(0.25f));
            addSpectrum(node, "transmittance", params, "transmittance", SpectrumKind::Reflectance,
                        Color3f(0.25f));
            addFloat(node, "scale", params.getFloat("scale", 1.0f));
            return node;
        }
        if (type == "mix") {
            const std::vector<std::string> names = params.getStrings("materials");
            if (names.size() != 2)
                throw LocatedError(material.location.str(),
                                   fmt::format("material 'mix' needs two names in \"string "
                                               "materials\", got {}",
                                               names.size()));
            std::array<MaterialRef, 2> parts;
            for (size_t i = 0; i < 2; ++i)
                parts[i] = materialRef(namedMaterial(names[i], material.location),
                                       "material:" + names[i], depth + 1);
            pugi::xml_node node = declare("bsdf");
            node.append_attribute("type") = "mix";
            addFloatTexture(node, "amount", params, "amount", 0.5f);
            for (const MaterialRef &part : parts) {
                if (part.bsdfId.empty())
                    addObject(node, "bsdf", "null");
                else
                    addRef(node, part.bsdfId);
            }
            return node;
        }
        // measured, subsurface, hair: a diffuse stand-in.
        const TextureValue reflectance =
            type == "subsurface" && params.has("reflectance")
                ? params.getSpectrum("reflectance", SpectrumKind::Reflectance, Color3f(0.5f), dir)
                : TextureValue{Color3f(0.5f), ""};
        warn(material.location, "material-" + type,
             fmt::format("material '{}' is not supported: a diffuse {} stands in for it", type,
                         reflectance.isTexture() ? "of its reflectance" : "grey of 0.5"));
        pugi::xml_node wrapper = twoSided();
        pugi::xml_node node = addObject(wrapper, "bsdf", "diffuse");
        addTextureValue(node, "albedo", reflectance, "spectrum", material.location);
        return wrapper;
    }

    static Color3f namedRGB(const std::string &name) {
        Parameter p;
        p.type = "spectrum";
        p.strings = {name};
        return spectrumToRGB(p, SpectrumKind::Unbounded, ".");
    }

    float etaOf(const Parameters &params) {
        const Parameter *eta = params.find("eta");
        if (!eta)
            return 1.5f;
        if (eta->type == "float" || eta->type == "texture")
            return constantFloat(params, "eta", 1.5f);
        if (eta->type != "spectrum")
            params.fail(*eta, fmt::format("{}: \"{} eta\" has the wrong type; expected \"float "
                                          "eta\" or \"spectrum eta\"",
                                          params.what(), eta->type));
        warn(eta->location, "dispersion",
             fmt::format("{}: the index of a spectral eta is taken at 550 nm (no dispersion)",
                         params.what()));
        return spectrumAt550(*eta, m_options.sceneDirectory);
    }

    /// A float parameter ours takes only as a number: a texture warns and gives its
    /// default.
    float constantFloat(const Parameters &params, const std::string &name, float defaultValue) {
        const TextureValue value = params.getFloatTexture(name, defaultValue);
        if (!value.isTexture())
            return value.constant.r();
        warn(params.entity().location, "constant-" + name,
             fmt::format("{}: \"texture {}\" is used as its default, {}", params.what(), name,
                         defaultValue));
        return defaultValue;
    }

    void writeLayerRoughness(pugi::xml_node node, const Parameters &params,
                             const std::string &prefix, const char *both, const char *u,
                             const char *v) {
        if (params.has(prefix + "roughness"))
            addFloatTexture(node, both, params, prefix + "roughness", 0.0f);
        if (params.has(prefix + "uroughness"))
            addFloatTexture(node, u, params, prefix + "uroughness", 0.0f);
        if (params.has(prefix + "vroughness"))
            addFloatTexture(node, v, params, prefix + "vroughness", 0.0f);
    }

    void writeLayerMedium(pugi::xml_node node, const Parameters &params) {
        addFloat(node, "thickness", constantFloat(params, "thickness", 0.01f));
        const TextureValue albedo = params.getSpectrum("albedo", SpectrumKind::Reflectance,
                                                       Color3f(0.0f), m_options.sceneDirectory);
        if (albedo.isTexture())
            warn(params.entity().location, "albedo-texture",
                 fmt::format("{}: an albedo texture is used as 0", params.what()));
        else
            addColor(node, "albedo", albedo.constant);
        addFloat(node, "g", constantFloat(params, "g", 0.0f));
        addInteger(node, "maxDepth", params.getInt("maxdepth", 10));
        addInteger(node, "nSamples", params.getInt("nsamples", 1));
    }

    // ---- media ----

    std::string mediumId(const std::string &name, const Location &where) {
        const auto it = m_media.find(name);
        if (it == m_media.end()) {
            std::vector<std::string> known;
            for (const auto &entry : m_media)
                known.push_back(entry.first);
            throw LocatedError(
                where.str(), fmt::format("no medium named '{}'{}", name, didYouMean(name, known)));
        }
        std::string id = "medium:" + name;
        if (m_declaredMedia.insert(id).second) {
            pugi::xml_node node = writeMedium(m_scene.media[it->second]);
            node.append_attribute("id") = id.c_str();
            publish(node);
        }
        return id;
    }

    pugi::xml_node writeMedium(const MediumEntity &medium) {
        const Parameters params = checked(medium, "medium", mediumNames());
        const std::string &dir = m_options.sceneDirectory;
        if (params.has("preset"))
            warn(medium.location, "preset",
                 fmt::format("medium preset '{}': not known here; sigma_a and sigma_s (default 1) "
                             "are used",
                             params.getString("preset", "")));
        const Color3f sigmaA =
            params.getSpectrum("sigma_a", SpectrumKind::Unbounded, Color3f(1.0f), dir).constant;
        const Color3f sigmaS =
            params.getSpectrum("sigma_s", SpectrumKind::Unbounded, Color3f(1.0f), dir).constant;
        const float scale = params.getFloat("scale", 1.0f);
        const TextureValue le =
            params.getSpectrum("Le", SpectrumKind::Illuminant, Color3f(0.0f), dir);
        if ((le.constant != 0.0f).any() && params.getFloat("Lescale", 1.0f) != 0.0f)
            warn(medium.location, "Le", "medium emission (Le): not rendered");
        pugi::xml_node node = declare("medium");
        if (medium.type == "homogeneous" || medium.type == "rgbgrid" || medium.type == "cloud") {
            if (medium.type != "homogeneous")
                warn(medium.location, "medium-" + medium.type,
                     fmt::format("medium '{}' is not supported: a homogeneous medium of its "
                                 "sigma_a and sigma_s stands in for it",
                                 medium.type));
            node.append_attribute("type") = "homogeneous";
            addColor(node, "sigmaA", sigmaA);
            addColor(node, "sigmaS", sigmaS);
            addFloat(node, "scale", scale);
        } else {
            // σt = (σa + σs)·scale·density: ours is grey, the albedo σs/σt coloured.
            const Color3f sigmaT = sigmaA + sigmaS;
            const float sigmaTGrey = sigmaT.mean();
            if ((sigmaT - Color3f(sigmaTGrey)).abs().maxCoeff() > 1e-6f * sigmaTGrey)
                warn(medium.location, "coloured-sigma-t",
                     fmt::format("medium '{}': a coloured σa + σs is rendered grey, at its mean {}",
                                 medium.type, sigmaTGrey));
            node.append_attribute("type") = "heterogeneous";
            addFloat(node, "scale", scale * sigmaTGrey);
            addColor(node, "albedo",
                     sigmaTGrey > 0.0f ? Color3f(sigmaS / sigmaTGrey) : Color3f(0.0f));
            if (medium.type == "nanovdb") {
                addString(node, "filename", resolvePath(params.getString("filename", "")));
                addString(node, "gridName", "density");
            } else {
                addString(node, "filename", writeDensityGrid(params));
            }
            addTransform(node, "toWorld", medium.toWorld);
        }
        pugi::xml_node phase = addObject(node, "phase", "hg");
        addFloat(phase, "g", params.getFloat("g", 0.0f));
        return node;
    }

    /// A uniformgrid's densities as a .vol file over its bounds [p0, p1].
    std::string writeDensityGrid(const Parameters &params) {
        const int nx = params.getInt("nx", 1), ny = params.getInt("ny", 1),
                  nz = params.getInt("nz", 1);
        std::vector<float> density = params.getFloats("density");
        if (nx <= 0 || ny <= 0 || nz <= 0 || density.size() != size_t(nx) * size_t(ny) * size_t(nz))
            throw LocatedError(params.entity().location.str(),
                               fmt::format("medium 'uniformgrid': \"float density\" has {} values "
                                           "for nx·ny·nz = {}·{}·{}",
                                           density.size(), nx, ny, nz));
        const Vector3f p0 = params.getVector("p0", Vector3f(0.0f, 0.0f, 0.0f));
        const Vector3f p1 = params.getVector("p1", Vector3f(1.0f, 1.0f, 1.0f));
        Eigen::Matrix4f unitToObject = Eigen::Matrix4f::Identity();
        for (int i = 0; i < 3; ++i) {
            unitToObject(i, i) = p1[i] - p0[i];
            unitToObject(i, 3) = p0[i];
        }
        const VolumeGrid grid(Vector3i(nx, ny, nz), 1, std::move(density), Transform(unitToObject),
                              params.entity().location.str());
        const auto [path, name] = sideFile("density", ".vol");
        grid.writeVol(path);
        return name;
    }

    // ---- shapes ----

    void writeShape(pugi::xml_node parent, const ShapeEntity &shape, bool emits) {
        const Parameters params = checked(shape, "shape", shapeNames());
        const MaterialRef material = materialOf(shape);
        pugi::xml_node node = writeGeometry(parent, shape, params, material);
        if (!node)
            return;
        if (!material.bsdfId.empty())
            addRef(node, material.bsdfId);
        // Bump and normal maps: on pbrt-v4's material, on our shape.
        if (material.entity && material.entity->type != "mix") {
            const Parameters materialParams(*material.entity, "material",
                                            materialNames().count(material.entity->type)
                                                ? materialNames().at(material.entity->type)
                                                : kMaterialCommon);
            if (materialParams.has("displacement"))
                addFloatTexture(node, "bump", materialParams, "displacement", 0.0f);
            if (materialParams.has("normalmap")) {
                pugi::xml_node normalMap = addObject(node, "texture", "image", "normal");
                addString(normalMap, "filename",
                          resolvePath(materialParams.getString("normalmap", "")));
                addString(normalMap, "colorSpace", "linear");
            }
        }
        if (params.has("alpha")) {
            const TextureValue alpha = params.getFloatTexture("alpha", 1.0f);
            if (alpha.isTexture())
                addRef(node, textureId(alpha.texture, "float", shape.location), "alpha");
            else if (alpha.constant.r() < 1.0f)
                addFloat(node, "alpha", alpha.constant.r());
        }
        if (params.has("emissionfilename"))
            warn(shape.location, "emissionfilename",
                 "shape emissionfilename: the area light's L is used instead of the image");
        if (shape.areaLight >= 0 && emits)
            writeAreaLight(node, m_scene.areaLights[size_t(shape.areaLight)]);
        if (shape.insideMedium != shape.outsideMedium) {
            if (!shape.insideMedium.empty())
                addRef(node, mediumId(shape.insideMedium, shape.location), "interior");
            if (!shape.outsideMedium.empty())
                addRef(node, mediumId(shape.outsideMedium, shape.location), "exterior");
        }
    }

    /// Whether a material reads any texture (then a sphere is tessellated, so that its uv
    /// are pbrt-v4's, not our analytic sphere's).
    bool materialTextured(const MaterialEntity *material, int depth = 0) const {
        if (!material || depth > 32)
            return false;
        for (const Parameter &parameter : material->parameters)
            if (parameter.type == "texture")
                return true;
        if (material->type == "mix")
            if (const Parameter *names = material->find("materials"))
                for (const std::string &name : names->strings) {
                    const auto it = m_scene.namedMaterials.find(name);
                    if (it != m_scene.namedMaterials.end() &&
                        materialTextured(&it->second, depth + 1))
                        return true;
                }
        return false;
    }

    pugi::xml_node writeGeometry(pugi::xml_node parent, const ShapeEntity &shape,
                                 const Parameters &params, const MaterialRef &material) {
        const std::string &type = shape.type;
        const Matrix &toWorld = shape.toWorld;
        const bool mirrors = toWorld.topLeftCorner<3, 3>().determinant() < 0.0;
        const float phiMax =
            std::clamp(params.getFloat("phimax", 360.0f), 0.0f, 360.0f) * kPi / 180.0f;
        if (type == "sphere") {
            const float radius = params.getFloat("radius", 1.0f);
            const float zMin = params.getFloat("zmin", -radius),
                        zMax = params.getFloat("zmax", radius);
            const bool partial = phiMax < 2.0f * kPi || std::min(zMin, zMax) > -radius ||
                                 std::max(zMin, zMax) < radius;
            // A uniform scale, rotation and translation keep a sphere a sphere.
            const Eigen::Matrix3d linear = toWorld.topLeftCorner<3, 3>();
            const double scale = std::cbrt(std::abs(linear.determinant()));
            const bool similar =
                (linear.transpose() * linear - scale * scale * Eigen::Matrix3d::Identity())
                    .cwiseAbs()
                    .maxCoeff() <= 1e-5 * scale * scale;
            if (partial)
                warn(shape.location, "partial-sphere",
                     "partial sphere (zmin, zmax, phimax): tessellated into triangles");
            else if (!similar)
                warn(shape.location, "sphere-scale",
                     "sphere under a non-uniform scale: tessellated into triangles");
            if (!partial && similar && !materialTextured(material.entity)) {
                pugi::xml_node node = addObject(parent, "mesh", "sphere");
                addPoint(node, "center", transformPoint(toWorld, Vector3f(0.0f, 0.0f, 0.0f)));
                addFloat(node, "radius", float(scale) * radius);
                if (shape.reverseOrientation)
                    addBoolean(node, "flipNormals", true);
                return node;
            }
            return writeMesh(parent, shape, tessellateSphere(radius, zMin, zMax, phiMax, 128));
        }
        if (type == "disk") {
            const float height = params.getFloat("height", 0.0f),
                        radius = params.getFloat("radius", 1.0f);
            const float inner = params.getFloat("innerradius", 0.0f);
            if (inner > 0.0f || phiMax < 2.0f * kPi) {
                warn(shape.location, "partial-disk",
                     "disk with innerradius or phimax: tessellated into triangles");
                return writeMesh(parent, shape, tessellateDisk(height, radius, inner, phiMax, 128));
            }
            pugi::xml_node node = addObject(parent, "mesh", "disk");
            Matrix local = Matrix::Identity();
            local(0, 0) = local(1, 1) = radius;
            local(2, 3) = height;
            addTransform(node, "toWorld", toWorld * local);
            if (shape.reverseOrientation)
                addBoolean(node, "flipNormals", true);
            return node;
        }
        if (type == "cylinder") {
            const float radius = params.getFloat("radius", 1.0f);
            const float zMin = params.getFloat("zmin", -1.0f), zMax = params.getFloat("zmax", 1.0f);
            const Eigen::Matrix3d linear = toWorld.topLeftCorner<3, 3>();
            const Eigen::Vector3d x = linear.col(0), y = linear.col(1), z = linear.col(2);
            const bool round = std::abs(x.norm() - y.norm()) <= 1e-5 * x.norm() &&
                               std::abs(x.dot(y)) <= 1e-5 * x.squaredNorm() &&
                               std::abs(x.dot(z)) <= 1e-5 * x.norm() * z.norm() &&
                               std::abs(y.dot(z)) <= 1e-5 * y.norm() * z.norm();
            if (phiMax < 2.0f * kPi || !round) {
                warn(shape.location, "partial-cylinder",
                     "cylinder with phimax or an oval cross-section: tessellated into triangles");
                return writeMesh(parent, shape,
                                 tessellateCylinder(radius, zMin, zMax, phiMax, 128));
            }
            pugi::xml_node node = addObject(parent, "mesh", "cylinder");
            addPoint(node, "p0", transformPoint(toWorld, Vector3f(0.0f, 0.0f, zMin)));
            addPoint(node, "p1", transformPoint(toWorld, Vector3f(0.0f, 0.0f, zMax)));
            addFloat(node, "radius", float(x.norm()) * radius);
            // Our cylinder's normals point outward; pbrt-v4's do too, turned by a mirror
            // image as pbrt-v4 turns them (its transformSwapsHandedness) and by
            // ReverseOrientation.
            if (shape.reverseOrientation)
                addBoolean(node, "flipNormals", true);
            return node;
        }
        if (type == "trianglemesh" || type == "bilinearmesh" || type == "loopsubdiv") {
            MeshData mesh = meshFromParameters(params, type != "loopsubdiv");
            std::vector<int> indices = params.getInts("indices");
            if (type == "bilinearmesh") {
                if (indices.empty() && mesh.positions.size() == 4)
                    indices = {0, 1, 2, 3};
                checkIndices(params, indices, 4, mesh.positions.size());
                mesh = bilinearPatchesToTriangles(std::move(mesh), indices);
            } else {
                if (indices.empty() && mesh.positions.size() == 3)
                    indices = {0, 1, 2};
                checkIndices(params, indices, 3, mesh.positions.size());
                for (size_t i = 0; i < indices.size(); i += 3)
                    mesh.triangles.emplace_back(indices[i], indices[i + 1], indices[i + 2]);
                if (type == "loopsubdiv") {
                    const int levels = params.getInt("levels", 3);
                    if (levels < 0 || levels > 8)
                        params.fail(
                            *params.find("levels"),
                            fmt::format("shape 'loopsubdiv': levels {} is not in [0, 8]", levels));
                    // Each level quadruples the triangles: refuse what no memory holds.
                    const double triangles = double(mesh.triangles.size()) * std::pow(4.0, levels);
                    if (triangles > 1e8)
                        params.fail(*params.find("levels"),
                                    fmt::format("shape 'loopsubdiv': {} levels would make {:.3g} "
                                                "triangles",
                                                levels, triangles));
                    mesh = loopSubdivide(std::move(mesh), levels);
                }
            }
            if (params.has("S"))
                warn(shape.location, "tangents",
                     "trianglemesh S (tangents): ours are computed from uv");
            if (params.has("faceIndices"))
                warn(shape.location, "faceIndices",
                     "faceIndices: not used (they select ptex faces)");
            return writeMesh(parent, shape, std::move(mesh));
        }
        if (type == "plymesh") {
            const std::string filename = params.getString("filename", "");
            if (filename.empty())
                throw LocatedError(shape.location.str(),
                                   "shape 'plymesh' needs a \"string filename\"");
            if (params.has("displacement"))
                warn(shape.location, "displacement",
                     "plymesh displacement: rendered as a bump map, not displaced geometry");
            pugi::xml_node node = addObject(parent, "mesh", "ply");
            const std::string path = resolvePath(filename);
            addString(node, "filename", path);
            addTransform(node, "toWorld", toWorld);
            bool flip = shape.reverseOrientation;
            if (mirrors) {
                // pbrt-v4 turns the winding's normal of a mirrored mesh back (its
                // transformSwapsHandedness); flipNormals does that too, and turns vertex
                // normals, which pbrt-v4 leaves: so only for a file without them.
                fs::path file(filename);
                if (file.is_relative())
                    file = fs::path(m_options.sceneDirectory) / file;
                if (readPLY(file.string()).normals.empty())
                    flip = !flip;
            }
            if (flip)
                addBoolean(node, "flipNormals", true);
            if (params.has("displacement"))
                addFloatTexture(node, "bump", params, "displacement", 0.0f);
            return node;
        }
        if (type == "curve") {
            warn(shape.location, "curve", "shape 'curve' is not supported: skipped");
            return {};
        }
        throw LocatedError(shape.location.str(), fmt::format("unknown shape type '{}'", type));
    }

    static void checkIndices(const Parameters &params, const std::vector<int> &indices, size_t per,
                             size_t vertexCount) {
        const Location where =
            params.find("indices") ? params.find("indices")->location : params.entity().location;
        if (indices.empty() || indices.size() % per != 0)
            throw LocatedError(where.str(),
                               fmt::format("{}: \"integer indices\" must hold {} per "
                                           "{}, got {}",
                                           params.what(), per, per == 3 ? "triangle" : "patch",
                                           indices.size()));
        for (int index : indices)
            if (index < 0 || size_t(index) >= vertexCount)
                throw LocatedError(where.str(), fmt::format("{}: index {} is not one of the {} "
                                                            "vertices",
                                                            params.what(), index, vertexCount));
    }

    static MeshData meshFromParameters(const Parameters &params, bool normalsAndUV) {
        MeshData mesh;
        const std::vector<float> p = params.getFloats("P");
        if (p.empty() || p.size() % 3 != 0)
            throw LocatedError(
                params.entity().location.str(),
                fmt::format("{} needs \"point3 P\", x y z per vertex", params.what()));
        const size_t count = p.size() / 3;
        for (size_t i = 0; i < count; ++i)
            mesh.positions.emplace_back(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
        if (!normalsAndUV)
            return mesh;
        const std::vector<float> n = params.getFloats("N");
        if (!n.empty()) {
            if (n.size() != p.size())
                params.fail(*params.find("N"), fmt::format("{}: \"normal N\" has {} numbers for {} "
                                                           "vertices",
                                                           params.what(), n.size(), count));
            for (size_t i = 0; i < count; ++i)
                mesh.normals.emplace_back(n[3 * i], n[3 * i + 1], n[3 * i + 2]);
        }
        const std::vector<float> uv = params.getFloats("uv");
        if (!uv.empty()) {
            if (uv.size() != 2 * count)
                params.fail(*params.find("uv"), fmt::format("{}: \"point2 uv\" has {} numbers for "
                                                            "{} vertices",
                                                            params.what(), uv.size(), count));
            for (size_t i = 0; i < count; ++i)
                mesh.texCoords.emplace_back(uv[2 * i], uv[2 * i + 1]);
        }
        return mesh;
    }

    /// A mesh built here: inline as `trianglemesh`, or as a PLY file when large.
    pugi::xml_node writeMesh(pugi::xml_node parent, const ShapeEntity &shape, MeshData mesh) {
        // pbrt-v4 turns the winding's normal back under a mirroring transform
        // (transformSwapsHandedness): reversing the winding here does the same for ours,
        // and leaves the vertex normals as they are.
        if (shape.toWorld.topLeftCorner<3, 3>().determinant() < 0.0)
            for (Vector3i &face : mesh.triangles)
                std::swap(face.y(), face.z());
        pugi::xml_node node;
        if (mesh.positions.size() > m_options.inlineVertexLimit) {
            node = addObject(parent, "mesh", "ply");
            const auto [path, name] = sideFile("mesh", ".ply");
            writePLY(path, mesh);
            addString(node, "filename", name);
        } else {
            node = addObject(parent, "mesh", "trianglemesh");
            std::vector<float> positions, normals, uvs;
            for (const Point3f &p : mesh.positions)
                positions.insert(positions.end(), {p.x(), p.y(), p.z()});
            for (const Normal3f &n : mesh.normals)
                normals.insert(normals.end(), {n.x(), n.y(), n.z()});
            for (const Point2f &uv : mesh.texCoords)
                uvs.insert(uvs.end(), {uv.x(), uv.y()});
            std::vector<int> indices;
            for (const Vector3i &face : mesh.triangles)
                indices.insert(indices.end(), {face.x(), face.y(), face.z()});
            addString(node, "positions", numberList(positions, 3));
            addString(node, "indices", numberList(indices, 3));
            if (!normals.empty())
                addString(node, "normals", numberList(normals, 3));
            if (!uvs.empty())
                addString(node, "uvs", numberList(uvs, 2));
        }
        addTransform(node, "toWorld", shape.toWorld);
        if (shape.reverseOrientation)
            addBoolean(node, "flipNormals", true);
        return node;
    }

    // ---- instances ----

    void writeInstanceDefinition(const InstanceDefinition &definition) {
        if (definition.shapes.empty())
            return;
        pugi::xml_node group = addObject(m_root, "mesh", "shapegroup");
        group.append_attribute("id") = ("object:" + definition.name).c_str();
        for (const ShapeEntity &shape : definition.shapes)
            writeShape(group, shape, false);
        m_definedObjects.insert(definition.name);
    }

    void writeInstanceUse(const InstanceUse &use) {
        if (!m_definedObjects.count(use.name))
            return; // an empty definition: nothing to place
        pugi::xml_node node = addObject(m_root, "mesh", "instance");
        addRef(node, "object:" + use.name);
        addTransform(node, "toWorld", use.toWorld);
    }

    // ---- lights ----

    /// pbrt-v4's light `scale`, with its `power` or illuminance where it has one (k_e: the
    /// power or illuminance of the light at unit scale).
    float lightScale(const Parameters &params, const char *powerName, float kE) {
        float scale = params.getFloat("scale", 1.0f) * m_imagingRatio;
        const float power = params.getFloat(powerName, -1.0f);
        if (power > 0.0f && kE > 0.0f)
            scale *= power / kE;
        return scale;
    }

    void writeAreaLight(pugi::xml_node shape, const Entity &light) {
        static const std::map<std::string, Names> table = {
            {"diffuse", {"L", "scale", "twosided", "filename", "power"}}};
        const Parameters params = checked(light, "area light", table);
        if (params.has("filename"))
            warn(light.location, "arealight-image",
                 "area light filename: the image is not used, L is");
        if (params.has("power"))
            warn(light.location, "arealight-power",
                 "area light power: not applied (L and scale are)");
        const TextureValue radiance = params.getSpectrum("L", SpectrumKind::Illuminant,
                                                         Color3f(1.0f), m_options.sceneDirectory);
        if (radiance.isTexture())
            params.fail(*params.find("L"), "area light: L must be a colour or a spectrum");
        pugi::xml_node node = addObject(shape, "emitter", "area");
        addColor(node, "radiance",
                 radiance.constant * (params.getFloat("scale", 1.0f) * m_imagingRatio));
        if (params.getBool("twosided", false))
            addBoolean(node, "twoSided", true);
    }

    void writeLight(const LightEntity &light) {
        const Parameters params = checked(light, "light", lightNames());
        const std::string &type = light.type;
        const std::string &dir = m_options.sceneDirectory;
        const Matrix &m = light.toWorld;
        if (type == "point" || type == "goniometric" || type == "projection") {
            if (type != "point")
                warn(light.location, "light-" + type,
                     fmt::format("light '{}' is not supported: a point light of its I stands in",
                                 type));
            const Color3f intensity =
                params.getSpectrum("I", SpectrumKind::Illuminant, Color3f(1.0f), dir).constant;
            pugi::xml_node node = addObject(m_root, "emitter", "point");
            addPoint(node, "position",
                     transformPoint(m, params.getVector("from", Vector3f(0.0f, 0.0f, 0.0f))));
            addColor(node, "intensity", intensity * lightScale(params, "power", 4.0f * kPi));
            return;
        }
        if (type == "spot") {
            const Color3f intensity =
                params.getSpectrum("I", SpectrumKind::Illuminant, Color3f(1.0f), dir).constant;
            const float cone = params.getFloat("coneangle", 30.0f);
            const float delta = params.getFloat("conedeltaangle", 5.0f);
            const float cosEnd = std::cos(cone * kPi / 180.0f);
            const float cosStart = std::cos((cone - delta) * kPi / 180.0f);
            const float kE = 2.0f * kPi * ((1.0f - cosStart) + (cosStart - cosEnd) / 2.0f);
            pugi::xml_node node = addObject(m_root, "emitter", "spot");
            addPoint(node, "position",
                     transformPoint(m, params.getVector("from", Vector3f(0.0f, 0.0f, 0.0f))));
            addPoint(node, "target",
                     transformPoint(m, params.getVector("to", Vector3f(0.0f, 0.0f, 1.0f))));
            addColor(node, "intensity", intensity * lightScale(params, "power", kE));
            addFloat(node, "cutoffAngle", cone);
            addFloat(node, "beamWidth", std::max(cone - delta, 0.0f));
            return;
        }
        if (type == "distant") {
            const Color3f radiance =
                params.getSpectrum("L", SpectrumKind::Illuminant, Color3f(1.0f), dir).constant;
            const Vector3f from = params.getVector("from", Vector3f(0.0f, 0.0f, 0.0f));
            const Vector3f to = params.getVector("to", Vector3f(0.0f, 0.0f, 1.0f));
            pugi::xml_node node = addObject(m_root, "emitter", "directional");
            addVector(node, "direction", transformVector(m, to - from).normalized());
            addColor(node, "irradiance", radiance * lightScale(params, "illuminance", 1.0f));
            return;
        }
        // infinite
        if (params.has("portal"))
            warn(light.location, "portal",
                 "infinite light portal: ignored (the whole sphere is sampled)");
        const std::string filename = params.getString("filename", "");
        if (filename.empty()) {
            const Color3f radiance =
                params.getSpectrum("L", SpectrumKind::Illuminant, Color3f(1.0f), dir).constant;
            pugi::xml_node node = addObject(m_root, "emitter", "constant");
            // A uniform sky of radiance 1 gives an illuminance of π on a horizontal surface.
            addColor(node, "radiance", radiance * lightScale(params, "illuminance", kPi));
            return;
        }
        if (params.has("L"))
            params.fail(*params.find("L"), "light 'infinite': give either L or filename, not both");
        if (params.has("illuminance"))
            warn(light.location, "illuminance",
                 "infinite light illuminance with an image: not applied (scale is)");
        pugi::xml_node node = addObject(m_root, "emitter", "envmap");
        addString(node, "filename", resolvePath(filename));
        addString(node, "mapping", "equalarea");
        addFloat(node, "scale", params.getFloat("scale", 1.0f) * m_imagingRatio);
        addTransform(node, "toWorld", m);
    }

    const Scene &m_scene;
    const ConvertOptions &m_options;
    Conversion m_result;
    Warnings m_warnings;
    pugi::xml_document m_document;
    pugi::xml_node m_root, m_bodyStart;
    pugi::xml_node m_scratch; ///< declarations being written (see declare)
    std::map<std::pair<std::string, std::string>, size_t> m_textures; ///< (value type, name)
    std::map<std::string, size_t> m_media;
    std::set<std::string> m_declaredTextures, m_declaredMaterials, m_declaredMedia,
        m_definedObjects;
    int m_width = 1280, m_height = 720;
    float m_imagingRatio = 1.0f;
    Eigen::AlignedBox2i m_crop;   ///< the pixels rendered, of the m_width × m_height image
    float m_whiteBalance = 0.0f;  ///< K; 0: none
    float m_filmDiagonal = 35.0f; ///< mm, of the realistic camera's film
    int m_sideFiles = 0, m_images = 0;
};

} // namespace

Conversion convertScene(const Scene &scene, const ConvertOptions &options) {
    return Converter(scene, options).run();
}

Conversion convertFile(const std::string &path, ConvertOptions options) {
    const Scene scene = readScene(path);
    const fs::path folder = fs::path(path).parent_path();
    options.sceneDirectory = folder.empty() ? "." : folder.string();
    return convertScene(scene, options);
}

bool isPbrtFile(const std::string &path) {
    const std::string lower = toLower(path);
    return endsWith(lower, ".pbrt") || endsWith(lower, ".pbrt.gz");
}

} // namespace nori::pbrt
