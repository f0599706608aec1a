#include <nori/filesystem.h>
#include <nori/imagefile.h>
#include <nori/layeredimage.h>

#include <tinyexr.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>

namespace nori {

namespace {

std::string fullChannelName(const std::string &layer, const std::string &channel) {
    return layer.empty() ? channel : layer + "." + channel;
}

/// The layer of a channel name: what comes before its last dot ("" for "R").
std::string layerOf(const std::string &channel) {
    const size_t dot = channel.rfind('.');
    return dot == std::string::npos ? std::string() : channel.substr(0, dot);
}

} // namespace

void LayeredImage::addLayer(const std::string &layer, const std::vector<std::string> &channelNames,
                            const Bitmap &values) {
    if (channelNames.empty() || channelNames.size() > 3)
        throw NoriException("layer '{}' must have one to three channels, not {}", layer,
                            channelNames.size());
    for (size_t k = 0; k < channelNames.size(); ++k) {
        Channel channel(values.rows(), values.cols());
        for (Eigen::Index y = 0; y < values.rows(); ++y)
            for (Eigen::Index x = 0; x < values.cols(); ++x)
                channel(y, x) = values(y, x)[static_cast<Eigen::Index>(k)];
        addChannel(fullChannelName(layer, channelNames[k]), std::move(channel));
    }
}

void LayeredImage::addChannel(const std::string &name, Channel values) {
    const Eigen::Vector2i size(static_cast<int>(values.cols()), static_cast<int>(values.rows()));
    if (m_channels.empty() && m_size == Eigen::Vector2i(0, 0))
        m_size = size;
    if (size != m_size)
        throw NoriException("channel '{}' is {}x{}, but the image is {}x{}", name, size.x(),
                            size.y(), m_size.x(), m_size.y());
    if (!m_channels.emplace(name, std::move(values)).second)
        throw NoriException("the image has a channel '{}' already", name);
}

bool LayeredImage::hasLayer(const std::string &layer) const {
    return !channelsOf(layer).empty();
}

std::vector<std::string> LayeredImage::layerNames() const {
    std::vector<std::string> names;
    for (const auto &[name, values] : m_channels) {
        const std::string layer = layerOf(name);
        if (std::find(names.begin(), names.end(), layer) == names.end())
            names.push_back(layer);
    }
    return names;
}

std::vector<std::string> LayeredImage::channelsOf(const std::string &layer) const {
    std::vector<std::string> names;
    for (const auto &[name, values] : m_channels)
        if (layerOf(name) == layer)
            names.push_back(layer.empty() ? name : name.substr(layer.size() + 1));
    // Colour channels first, in R, G, B order (sorted by name, they are B, G, R), then the
    // others (A of an RGBA image) in name order.
    std::vector<std::string> ordered;
    for (const char *colour : {"R", "G", "B"})
        if (std::find(names.begin(), names.end(), colour) != names.end())
            ordered.push_back(colour);
    if (ordered.size() != 3)
        return names;
    for (const std::string &name : names)
        if (name != "R" && name != "G" && name != "B")
            ordered.push_back(name);
    return ordered;
}

Bitmap LayeredImage::layer(const std::string &layer) const {
    std::vector<std::string> names = channelsOf(layer);
    // An RGBA layer shows its colour; alpha is not part of the radiance.
    if (names.size() > 3 && names[0] == "R" && names[1] == "G" && names[2] == "B")
        names.resize(3);
    if (names.empty() || names.size() > 3) {
        std::vector<std::string> layers;
        for (const std::string &name : layerNames())
            layers.push_back(name.empty() ? "(beauty)" : name);
        throw NoriException("the image has no layer '{}' (its layers: {})",
                            layer.empty() ? "(beauty)" : layer, fmt::join(layers, ", "));
    }
    Bitmap result(m_size);
    for (int k = 0; k < 3; ++k) {
        const Channel &channel =
            m_channels.at(fullChannelName(layer, names[std::min<size_t>(k, names.size() - 1)]));
        for (int y = 0; y < m_size.y(); ++y)
            for (int x = 0; x < m_size.x(); ++x)
                result(y, x)[k] = channel(y, x);
    }
    return result;
}

void LayeredImage::saveEXR(const std::string &filename) const {
    if (m_channels.empty())
        throw NoriException("cannot write EXR image '{}': the image has no channels", filename);
    EXRHeader header;
    InitEXRHeader(&header);
    EXRImage image;
    InitEXRImage(&image);

    const int channelCount = static_cast<int>(m_channels.size());
    std::vector<EXRChannelInfo> channelInfo(static_cast<size_t>(channelCount));
    std::vector<const float *> planes;
    std::vector<int> pixelTypes(static_cast<size_t>(channelCount), TINYEXR_PIXELTYPE_FLOAT);
    for (const auto &[name, values] : m_channels) {
        if (name.size() > 255)
            throw NoriException("cannot write EXR image '{}': channel name '{}' is longer than "
                                "255 characters",
                                filename, name);
        EXRChannelInfo &info = channelInfo[planes.size()];
        std::memset(&info, 0, sizeof(info));
        std::strncpy(info.name, name.c_str(), sizeof(info.name) - 1);
        planes.push_back(values.data());
    }
    std::vector<EXRAttribute> attributeList;
    for (const auto &[name, value] : attributes) {
        EXRAttribute attribute;
        std::memset(&attribute, 0, sizeof(attribute));
        std::strncpy(attribute.name, name.c_str(), sizeof(attribute.name) - 1);
        std::strncpy(attribute.type, "string", sizeof(attribute.type) - 1);
        attribute.value = reinterpret_cast<unsigned char *>(const_cast<char *>(value.data()));
        attribute.size = static_cast<int>(value.size());
        attributeList.push_back(attribute);
    }

    header.num_channels = channelCount;
    header.channels = channelInfo.data();
    header.pixel_types = pixelTypes.data();
    header.requested_pixel_types = pixelTypes.data();
    header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;
    header.num_custom_attributes = static_cast<int>(attributeList.size());
    header.custom_attributes = attributeList.empty() ? nullptr : attributeList.data();
    image.num_channels = channelCount;
    image.width = m_size.x();
    image.height = m_size.y();
    // tinyexr reads the planes and never writes them.
    image.images = reinterpret_cast<unsigned char **>(const_cast<float **>(planes.data()));

    const char *error = nullptr;
    unsigned char *memory = nullptr;
    const size_t size = SaveEXRImageToMemory(&image, &header, &memory, &error);
    if (size == 0) {
        std::string message = error ? error : "unknown error";
        FreeEXRErrorMessage(error);
        throw NoriException("cannot write EXR image '{}': {}", filename, message);
    }
    std::string bytes(reinterpret_cast<const char *>(memory), size);
    std::free(memory); // tinyexr allocates with malloc
    writeBinaryFile(filename, bytes, "EXR image");
}

LayeredImage LayeredImage::loadEXR(const std::string &filename) {
    return decodeLayeredEXR(readBinaryFile(filename, "EXR image"), filename);
}

} // namespace nori
