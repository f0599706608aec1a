/*
 * image — a texture read from a PNG, JPEG, TGA, Radiance HDR or OpenEXR file and filtered
 * over the lookup's footprint with a MIP map (pbrt-v3 §10.4): trilinear by default,
 * or EWA (Heckbert 1989). uv (0, 0) is the image's bottom-left corner, as in OBJ files.
 * One decoded pyramid is shared by every texture naming the same file and colour space.
 *
 * Parameters:
 *   filename       string   (required)   the image file, relative to the scene file
 *   colorSpace     string   auto          "srgb" (decode 8/16-bit values from sRGB),
 *                                         "linear" (take values as stored) or "auto":
 *                                         srgb for 8/16-bit colour images, linear for
 *                                         float images (HDR, EXR) and in data slots
 *                                         (normal, bump, roughness)
 *   gamma          float    (none)        decode by a power law, value^gamma, instead of
 *                                         colorSpace (pbrt-v4's "gamma G" encoding,
 *                                         Mitsuba's gamma; there -1 means srgb, 1 linear)
 *   wrap           string   "repeat"      outside [0, 1]²: "repeat", "clamp" or "mirror"
 *   uvScale        vector   (1, 1)        uv are scaled by this (a <float> scales both) ...
 *   uvOffset       vector   (0, 0)        ... then offset by this
 *   filter         string   "trilinear"   "nearest", "bilinear" (both on the full-size
 *                                         image, unfiltered), "trilinear" or "ewa"
 *   maxAnisotropy  float    8             EWA's largest ratio of the footprint's axes
 *
 *   <bsdf type="diffuse">
 *       <texture type="image" name="albedo">
 *           <string name="filename" value="scenes/textured/textures/bricks.png"/>
 *           <float name="uvScale" value="4"/>
 *       </texture>
 *   </bsdf>
 */
#include <nori/loadahead.h>
#include <nori/proplist.h>
#include <nori/strutil.h>
#include <nori/texture.h>
#include <nori/texturecache.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <vector>

namespace nori {
namespace {

class ImageTexture : public Texture {
public:
    explicit ImageTexture(const PropertyList &props) {
        m_filename = props.getPath("filename");
        m_colorSpace = parseColorSpace(props.getString("colorSpace", "auto"));
        if (props.has("gamma")) {
            if (props.has("colorSpace"))
                throw NoriException("image: give 'colorSpace' or 'gamma', not both");
            m_gamma = props.getFloat("gamma");
            if (m_gamma == -1.0f)
                m_colorSpace = ColorSpace::SRGB;
            else if (m_gamma > 0.0f && m_gamma <= 16.0f)
                m_colorSpace = ColorSpace::Gamma;
            else
                throw NoriException("image: 'gamma' must lie in (0, 16], or be -1 (sRGB), got {}",
                                    m_gamma);
        }
        m_wrap = parseWrap(props.getString("wrap", "repeat"));
        m_uvScale = props.holdsScalar("uvScale")
                        ? Vector2f::Constant(props.getFloat("uvScale"))
                        : props.getVector2("uvScale", Vector2f(1.0f, 1.0f));
        m_uvOffset = props.getVector2("uvOffset", Vector2f(0.0f, 0.0f));
        m_filter = parseFilter(props.getString("filter", "trilinear"));
        m_maxAnisotropy = props.getFloat("maxAnisotropy", 8.0f);
        if (!m_uvScale.allFinite() || !m_uvOffset.allFinite())
            throw NoriException("image: 'uvScale' and 'uvOffset' must be finite");
        if (!(m_maxAnisotropy >= 1.0f && m_maxAnisotropy <= 64.0f))
            throw NoriException("image: 'maxAnisotropy' must be in [1, 64], got {}",
                                m_maxAnisotropy);
        m_mipmap = loadTextureImage(m_filename, m_colorSpace, m_gamma);
    }

    Color3f eval(const TextureQuery &q) const override {
        const Point2f st = toST(q.uv);
        switch (m_filter) {
        case MIPMap::Filter::Nearest:
            return m_mipmap->nearest(st, m_wrap);
        case MIPMap::Filter::Bilinear:
            return m_mipmap->bilinear(0, st, m_wrap);
        case MIPMap::Filter::Trilinear:
            return m_mipmap->trilinear(st, dstdx(q), dstdy(q), m_wrap);
        case MIPMap::Filter::EWA:
            return m_mipmap->ewa(st, dstdx(q), dstdy(q), m_maxAnisotropy, m_wrap);
        }
        return Color3f(0.0f);
    }

    Color3f average() const override { return m_mipmap->average(); }

    bool usesFootprint() const override {
        return m_filter == MIPMap::Filter::Trilinear || m_filter == MIPMap::Filter::EWA;
    }

    float mipLevel(const TextureQuery &q) const override {
        switch (m_filter) {
        case MIPMap::Filter::Trilinear:
            return m_mipmap->trilinearLevel(dstdx(q), dstdy(q));
        case MIPMap::Filter::EWA:
            return m_mipmap->ewaLevel(dstdx(q), dstdy(q), m_maxAnisotropy);
        default:
            return 0.0f;
        }
    }

    std::shared_ptr<const Texture> linearVariant() const override {
        if (m_colorSpace != ColorSpace::Auto)
            return nullptr;
        auto variant = std::make_shared<ImageTexture>(*this);
        variant->m_colorSpace = ColorSpace::Linear;
        variant->m_mipmap = loadTextureImage(m_filename, ColorSpace::Linear);
        return variant;
    }

    std::string toString() const override {
        return fmt::format("ImageTexture[filename=\"{}\", {}x{}, levels={}]", m_filename,
                           m_mipmap->level(0).width(), m_mipmap->level(0).height(),
                           m_mipmap->levels());
    }

private:
    /// Image coordinates: uv scaled and offset, t flipped so that v = 0 is the bottom row.
    Point2f toST(const Point2f &uv) const {
        return Point2f(uv.x() * m_uvScale.x() + m_uvOffset.x(),
                       1.0f - (uv.y() * m_uvScale.y() + m_uvOffset.y()));
    }
    Vector2f dstdx(const TextureQuery &q) const {
        return Vector2f(q.dudx * m_uvScale.x(), -q.dvdx * m_uvScale.y());
    }
    Vector2f dstdy(const TextureQuery &q) const {
        return Vector2f(q.dudy * m_uvScale.x(), -q.dvdy * m_uvScale.y());
    }

    /// The value of `choices` named `name`; an error listing the names otherwise.
    template <typename T>
    static T choose(const char *parameter, const std::string &name,
                    std::initializer_list<std::pair<const char *, T>> choices) {
        std::vector<std::string> names;
        for (const auto &[choiceName, value] : choices) {
            if (name == choiceName)
                return value;
            names.emplace_back(choiceName);
        }
        throw NoriException("image: unknown {} '{}'{} (use {})", parameter, name,
                            didYouMean(name, names), fmt::join(names, ", "));
    }
    static ColorSpace parseColorSpace(const std::string &name) {
        return choose<ColorSpace>("colorSpace", name,
                                  {{"auto", ColorSpace::Auto},
                                   {"srgb", ColorSpace::SRGB},
                                   {"linear", ColorSpace::Linear}});
    }
    static MIPMap::Wrap parseWrap(const std::string &name) {
        return choose<MIPMap::Wrap>("wrap", name,
                                    {{"repeat", MIPMap::Wrap::Repeat},
                                     {"clamp", MIPMap::Wrap::Clamp},
                                     {"mirror", MIPMap::Wrap::Mirror}});
    }
    static MIPMap::Filter parseFilter(const std::string &name) {
        return choose<MIPMap::Filter>("filter", name,
                                      {{"nearest", MIPMap::Filter::Nearest},
                                       {"bilinear", MIPMap::Filter::Bilinear},
                                       {"trilinear", MIPMap::Filter::Trilinear},
                                       {"ewa", MIPMap::Filter::EWA}});
    }

    std::string m_filename;
    ColorSpace m_colorSpace;
    float m_gamma = 1.0f; ///< the exponent of ColorSpace::Gamma
    MIPMap::Wrap m_wrap;
    Vector2f m_uvScale, m_uvOffset;
    MIPMap::Filter m_filter;
    float m_maxAnisotropy;
    std::shared_ptr<const MIPMap> m_mipmap;
};

NORI_REGISTER_CLASS(ImageTexture, "image");
NORI_REGISTER_LOAD_AHEAD(ImageTexture, "image", kTextureImageReader);

} // namespace
} // namespace nori
