// An image of named float channels: a render's beauty ("R", "G", "B") and its AOV
// layers ("albedo.R", "depth.Z", ...), as our multi-layer EXR files store them, with
// string attributes in the EXR header.
#pragma once

#include <nori/bitmap.h>

#include <map>
#include <string>
#include <vector>

namespace nori {

class LayeredImage {
public:
    using Channel = Eigen::Array<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

    LayeredImage() = default;
    explicit LayeredImage(const Eigen::Vector2i &size) : m_size(size) {}

    const Eigen::Vector2i &size() const { return m_size; }

    /// Adds a layer: its channels are `layer + "." + channelNames[k]` (just the channel
    /// names for the beauty layer, whose name is empty), and `values` holds them as its
    /// colour components (one channel name: the first component). Throws when a channel
    /// exists already or the size differs.
    void addLayer(const std::string &layer, const std::vector<std::string> &channelNames,
                  const Bitmap &values);
    /// Adds one channel (full name, such as "depth.Z").
    void addChannel(const std::string &name, Channel values);

    bool hasLayer(const std::string &layer) const;
    /// The layers in channel order: "" (the beauty) when it has R, G, B, then the others.
    std::vector<std::string> layerNames() const;
    /// The channels of a layer, without the layer's prefix ("R", "G", "B").
    std::vector<std::string> channelsOf(const std::string &layer) const;
    /// A layer as a bitmap: three channels in order as RGB, one channel as grey. Throws
    /// a NoriException naming the layer and the ones there are when it is missing.
    Bitmap layer(const std::string &layer) const;
    const std::map<std::string, Channel> &channels() const { return m_channels; }

    /// Header attributes, written to and read from the EXR as strings.
    std::map<std::string, std::string> attributes;

    /// Writes a single-part scanline EXR of 32-bit floats, channels sorted by name (as
    /// OpenEXR requires), ZIP-compressed.
    void saveEXR(const std::string &filename) const;
    /// Reads every channel of an EXR file (through decodeLayeredEXR in imagefile.h).
    static LayeredImage loadEXR(const std::string &filename);

private:
    Eigen::Vector2i m_size{0, 0};
    std::map<std::string, Channel> m_channels; ///< sorted by name, as EXR stores them
};

} // namespace nori
