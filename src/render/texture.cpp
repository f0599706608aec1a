#include <nori/proplist.h>
#include <nori/shape.h>
#include <nori/texture.h>

namespace nori {

TextureQuery::TextureQuery(const Intersection &its)
    : uv(its.uv), p(its.p), dudx(its.dudx), dudy(its.dudy), dvdx(its.dvdx), dvdy(its.dvdy) {}

CourseCheckerboard::CourseCheckerboard(const PropertyList &props, const std::string &plugin) {
    delta = props.getPoint2("delta", Point2f(0.0f, 0.0f));
    scale = props.getVector2("scale", Vector2f(1.0f, 1.0f));
    if (!(scale.x() != 0.0f && scale.y() != 0.0f && scale.allFinite() && delta.allFinite()))
        throw NoriException("{}: 'scale' must be finite and non-zero, 'delta' finite", plugin);
}

std::shared_ptr<const Texture> makeConstantTexture(const Color3f &value) {
    PropertyList props;
    props.setColor("value", value);
    auto texture = std::static_pointer_cast<Texture>(
        NoriObjectFactory::createInstance("constant", Texture::kClassType, props));
    texture->activate();
    return texture;
}

namespace {

/// The texture bound to `name`, or nullptr when the property is not an object.
std::shared_ptr<const Texture> boundTexture(const PropertyList &props, const std::string &name) {
    if (!props.holdsObject(name))
        return nullptr;
    auto texture = std::dynamic_pointer_cast<const Texture>(props.getObject(name));
    if (!texture)
        throw NoriException("parameter '{}' takes a texture or a value", name);
    return texture;
}

} // namespace

std::shared_ptr<const Texture> TextureParameters::color(const PropertyList &props,
                                                        const std::string &name,
                                                        const Color3f &defaultValue) {
    if (auto texture = boundTexture(props, name))
        return remember(texture);
    return remember(makeConstantTexture(props.getColor(name, defaultValue)));
}

std::shared_ptr<const Texture> TextureParameters::color(const PropertyList &props,
                                                        const std::string &name) {
    if (auto texture = boundTexture(props, name))
        return remember(texture);
    return remember(makeConstantTexture(props.getColor(name)));
}

std::shared_ptr<const Texture> TextureParameters::scalar(const PropertyList &props,
                                                         const std::string &name,
                                                         float defaultValue, float minimum,
                                                         float maximum) {
    if (auto texture = boundTexture(props, name)) {
        // A scalar parameter holds data: 8-bit images are not sRGB-decoded.
        if (auto linear = texture->linearVariant())
            texture = linear;
        return remember(texture);
    }
    const float value = props.getFloat(name, defaultValue);
    if (!(value >= minimum && value <= maximum))
        throw NoriException("parameter '{}' must be in [{}, {}], got {}", name, minimum, maximum,
                            value);
    return remember(makeConstantTexture(Color3f(value)));
}

std::shared_ptr<const Texture> TextureParameters::constant(const Color3f &value) {
    return remember(makeConstantTexture(value));
}

std::shared_ptr<const Texture> TextureParameters::remember(std::shared_ptr<const Texture> texture) {
    m_textures.push_back(texture);
    return texture;
}

} // namespace nori
