#include <nori/filesystem.h>
#include <nori/imagefile.h>
#include <nori/strutil.h>

// Debian's stb_image, fuzzed, writes out of bounds on a JPEG whose Huffman counts sum
// past 256, loops forever on a truncated run-length HDR scanline and trusts a 2 GB PNG
// chunk length; so PNG and JPEG are decoded by libpng and libjpeg-turbo (both
// continuously fuzzed upstream), HDR by the bounded reader below, EXR by tinyexr with
// its error paths' leaks plugged here.
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <jpeglib.h>
#include <png.h>
#include <tinyexr.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace nori {

namespace {

constexpr int kMaxSide = 65536;

void checkSize(int64_t width, int64_t height, std::size_t maxPixels, const std::string &name,
               const char *format) {
    if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide ||
        static_cast<uint64_t>(width) * static_cast<uint64_t>(height) > maxPixels)
        throw NoriException("{} image '{}' has an unsupported size {}x{} (each side 1 to {}, at "
                            "most {} pixels)",
                            format, name, width, height, kMaxSide, maxPixels);
}

bool startsWith(const std::string &bytes, const char *magic, std::size_t length) {
    return bytes.size() >= length && std::memcmp(bytes.data(), magic, length) == 0;
}

// ---------------------------------------------------------------------------------- PNG
// libpng reports errors by longjmp to the setjmp in readPng's frame; only plain data
// lives in the frames it jumps over, and every C++ object is owned by the caller.

struct PngSource {
    const std::string *bytes;
    std::size_t offset = 0;
    char message[256] = "";
};

void pngError(png_structp png, png_const_charp message) {
    auto *source = static_cast<PngSource *>(png_get_error_ptr(png));
    std::snprintf(source->message, sizeof(source->message), "%s", message);
    png_longjmp(png, 1);
}

void pngWarning(png_structp, png_const_charp) {}

void pngRead(png_structp png, png_bytep out, png_size_t count) {
    auto *source = static_cast<PngSource *>(png_get_io_ptr(png));
    if (source->bytes->size() - source->offset < count)
        png_error(png, "the file ends early (truncated)");
    std::memcpy(out, source->bytes->data() + source->offset, count);
    source->offset += count;
}

struct PngLayout {
    png_uint_32 width = 0, height = 0;
    int bitDepth = 0;
    bool hasAlpha = false;
    std::size_t rowBytes = 0;
};

/// Phase 1: header and transformations (to 8- or 16-bit RGB). Returns false on error.
bool readPngHeader(png_structp png, png_infop info, std::size_t maxPixels, PngLayout &layout) {
    if (setjmp(png_jmpbuf(png)))
        return false;
    png_set_user_limits(png, kMaxSide, kMaxSide);
    png_set_chunk_malloc_max(png, 8u << 20); // ancillary chunks (text, ICC) up to 8 MiB
    png_read_info(png, info);
    layout.width = png_get_image_width(png, info);
    layout.height = png_get_image_height(png, info);
    if (static_cast<uint64_t>(layout.width) * layout.height > maxPixels)
        png_error(png, "image too large");
    const png_byte colorType = png_get_color_type(png, info);
    layout.hasAlpha =
        (colorType & PNG_COLOR_MASK_ALPHA) != 0 || png_get_valid(png, info, PNG_INFO_tRNS) != 0;
    png_set_expand(png); // palette → RGB, grey < 8 bit → 8 bit, tRNS → alpha
    png_set_gray_to_rgb(png);
    if (!layout.hasAlpha) // every row RGBA: an opaque alpha where the file has none
        png_set_filler(png, 0xffff, PNG_FILLER_AFTER);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    layout.bitDepth = png_get_bit_depth(png, info);
    layout.rowBytes = png_get_rowbytes(png, info);
    return true;
}

/// Phase 2: the rows, into `data` (sized by the caller). Returns false on error.
bool readPngRows(png_structp png, png_infop info, std::vector<png_bytep> &rows) {
    if (setjmp(png_jmpbuf(png)))
        return false;
    png_read_image(png, rows.data());
    png_read_end(png, info);
    return true;
}

ImageFile decodePng(const std::string &bytes, const std::string &name, std::size_t maxPixels) {
    PngSource source{&bytes};
    png_structp png =
        png_create_read_struct(PNG_LIBPNG_VER_STRING, &source, &pngError, &pngWarning);
    png_infop info = png ? png_create_info_struct(png) : nullptr;
    struct Guard {
        png_structp &png;
        png_infop &info;
        ~Guard() { png_destroy_read_struct(&png, &info, nullptr); }
    } guard{png, info};
    if (!info)
        throw NoriException("PNG image '{}': out of memory", name);
    png_set_read_fn(png, &source, &pngRead);

    PngLayout layout;
    if (!readPngHeader(png, info, maxPixels, layout)) {
        if (std::strcmp(source.message, "image too large") == 0)
            checkSize(layout.width, layout.height, maxPixels, name, "PNG");
        throw NoriException("PNG image '{}' is invalid: {}", name, source.message);
    }
    checkSize(layout.width, layout.height, maxPixels, name, "PNG");
    const int bytesPerSample = layout.bitDepth == 16 ? 2 : 1;
    if (layout.rowBytes != static_cast<std::size_t>(layout.width) * 4 * bytesPerSample)
        throw NoriException("PNG image '{}': unexpected row layout", name);
    std::vector<png_byte> data(layout.rowBytes * layout.height);
    std::vector<png_bytep> rows(layout.height);
    for (png_uint_32 y = 0; y < layout.height; ++y)
        rows[y] = data.data() + y * layout.rowBytes;
    if (!readPngRows(png, info, rows))
        throw NoriException("PNG image '{}' is invalid: {}", name, source.message);

    ImageFile image{Bitmap(Eigen::Vector2i(layout.width, layout.height)), true, Bitmap()};
    if (layout.hasAlpha)
        image.alpha = Bitmap(Eigen::Vector2i(layout.width, layout.height));
    const float scale = 1.0f / (bytesPerSample == 2 ? 65535.0f : 255.0f);
    for (png_uint_32 y = 0; y < layout.height; ++y)
        for (png_uint_32 x = 0; x < layout.width; ++x)
            for (int c = 0; c < 4; ++c) {
                const png_byte *sample = rows[y] + (4 * std::size_t(x) + c) * bytesPerSample;
                const int value = bytesPerSample == 2 ? (sample[0] << 8) | sample[1] : sample[0];
                if (c < 3)
                    image.pixels.coeffRef(y, x)[c] = value * scale;
                else if (layout.hasAlpha)
                    image.alpha.coeffRef(y, x) = Color3f(value * scale);
            }
    return image;
}

// --------------------------------------------------------------------------------- JPEG

struct JpegErrors {
    jpeg_error_mgr base;
    std::jmp_buf jump;
    char message[JMSG_LENGTH_MAX] = "";
};

void jpegError(j_common_ptr cinfo) {
    auto *errors = reinterpret_cast<JpegErrors *>(cinfo->err);
    (*cinfo->err->format_message)(cinfo, errors->message);
    std::longjmp(errors->jump, 1);
}

/// libjpeg only warns about corrupt or truncated data (and fills the gaps with grey);
/// a texture with made-up pixels is not what the user asked for, so warnings are errors.
void jpegMessage(j_common_ptr cinfo, int level) {
    if (level < 0)
        jpegError(cinfo);
}

/// A progressive JPEG can hold thousands of tiny scans, each re-decoding the whole image:
/// a few hundred bytes that take minutes. No real encoder writes more than a few dozen.
constexpr int kMaxJpegScans = 256;

void jpegProgress(j_common_ptr cinfo) {
    if (cinfo->is_decompressor &&
        reinterpret_cast<j_decompress_ptr>(cinfo)->input_scan_number > kMaxJpegScans) {
        auto *errors = reinterpret_cast<JpegErrors *>(cinfo->err);
        std::snprintf(errors->message, sizeof(errors->message), "more than %d progressive scans",
                      kMaxJpegScans);
        std::longjmp(errors->jump, 1);
    }
}

/// Decodes into `data` (resized by a callback-free two-step protocol: the header first,
/// then the rows). Returns false on error, with the message in `errors`.
bool readJpeg(jpeg_decompress_struct &cinfo, JpegErrors &errors, const std::string &bytes,
              std::size_t maxPixels, std::vector<unsigned char> &data, int &width, int &height) {
    if (setjmp(errors.jump))
        return false;
    jpeg_mem_src(&cinfo, reinterpret_cast<const unsigned char *>(bytes.data()),
                 static_cast<unsigned long>(bytes.size()));
    jpeg_read_header(&cinfo, TRUE);
    width = static_cast<int>(cinfo.image_width);
    height = static_cast<int>(cinfo.image_height);
    if (width < 1 || height < 1 || width > kMaxSide || height > kMaxSide ||
        static_cast<uint64_t>(width) * static_cast<uint64_t>(height) > maxPixels) {
        std::snprintf(errors.message, sizeof(errors.message), "size");
        return false;
    }
    cinfo.out_color_space = JCS_RGB;
    jpeg_start_decompress(&cinfo);
    if (cinfo.output_components != 3) {
        std::snprintf(errors.message, sizeof(errors.message), "unsupported colour space");
        return false;
    }
    data.resize(static_cast<std::size_t>(width) * height * 3);
    while (cinfo.output_scanline < cinfo.output_height) {
        JSAMPROW row = data.data() + static_cast<std::size_t>(cinfo.output_scanline) * width * 3;
        jpeg_read_scanlines(&cinfo, &row, 1);
    }
    jpeg_finish_decompress(&cinfo);
    return true;
}

ImageFile decodeJpeg(const std::string &bytes, const std::string &name, std::size_t maxPixels) {
    jpeg_decompress_struct cinfo;
    JpegErrors errors;
    cinfo.err = jpeg_std_error(&errors.base);
    errors.base.error_exit = &jpegError;
    errors.base.emit_message = &jpegMessage;
    jpeg_progress_mgr progress;
    progress.progress_monitor = &jpegProgress;
    jpeg_create_decompress(&cinfo);
    cinfo.progress = &progress;
    cinfo.mem->max_memory_to_use = 512L << 20;
    struct Guard {
        jpeg_decompress_struct &cinfo;
        ~Guard() { jpeg_destroy_decompress(&cinfo); }
    } guard{cinfo};

    std::vector<unsigned char> data;
    int width = 0, height = 0;
    if (!readJpeg(cinfo, errors, bytes, maxPixels, data, width, height)) {
        if (std::strcmp(errors.message, "size") == 0)
            checkSize(width, height, maxPixels, name, "JPEG");
        throw NoriException("JPEG image '{}' is invalid: {}", name, errors.message);
    }
    ImageFile image{Bitmap(Eigen::Vector2i(width, height)), true, Bitmap()};
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c)
                image.pixels.coeffRef(y, x)[c] =
                    data[3 * (static_cast<std::size_t>(y) * width + x) + c] / 255.0f;
    return image;
}

// ---------------------------------------------------------------------- Radiance HDR
// Ward, "Real Pixels" (Graphics Gems II, 1991): RGBE pixels, optionally run-length coded
// per scanline and channel. Every read is bounds-checked, every run must fit its line.

class HdrReader {
public:
    HdrReader(const std::string &bytes, const std::string &name) : m_bytes(bytes), m_name(name) {}

    ImageFile decode(std::size_t maxPixels) {
        readHeader();
        checkSize(m_width, m_height, maxPixels, m_name, "HDR");
        ImageFile image{Bitmap(Eigen::Vector2i(m_width, m_height)), false, Bitmap()};
        std::vector<uint8_t> line(static_cast<std::size_t>(m_width) * 4);
        for (int y = 0; y < m_height; ++y) {
            readScanline(line, y);
            for (int x = 0; x < m_width; ++x)
                image.pixels.coeffRef(y, x) = rgbeToColor(&line[4 * std::size_t(x)]);
        }
        return image;
    }

private:
    [[noreturn]] void fail(const std::string &what) const {
        throw NoriException("HDR image '{}' is invalid: {} (at byte {})", m_name, what, m_offset);
    }

    uint8_t next() {
        if (m_offset >= m_bytes.size())
            fail("the file ends early (truncated)");
        return static_cast<uint8_t>(m_bytes[m_offset++]);
    }

    std::string nextLine() {
        const std::size_t end = m_bytes.find('\n', m_offset);
        if (end == std::string::npos || end - m_offset > 4096)
            fail("a header line is missing its end");
        std::string line = m_bytes.substr(m_offset, end - m_offset);
        m_offset = end + 1;
        return line;
    }

    void readHeader() {
        const std::string magic = nextLine();
        if (magic != "#?RADIANCE" && magic != "#?RGBE")
            fail("no '#?RADIANCE' signature");
        for (;;) {
            const std::string line = nextLine();
            if (line.empty())
                break;
            if (line.rfind("FORMAT=", 0) == 0 && line != "FORMAT=32-bit_rle_rgbe")
                fail("unsupported " + line + " (only 32-bit_rle_rgbe)");
        }
        const std::string resolution = nextLine();
        char height[16], width[16];
        long h = 0, w = 0;
        if (std::sscanf(resolution.c_str(), "%15s %ld %15s %ld", height, &h, width, &w) != 4 ||
            std::strcmp(height, "-Y") != 0 || std::strcmp(width, "+X") != 0)
            fail("unsupported resolution line '" + resolution + "' (only '-Y h +X w')");
        if (h < 1 || w < 1 || h > kMaxSide || w > kMaxSide)
            checkSize(w, h, 0, m_name, "HDR");
        m_width = static_cast<int>(w);
        m_height = static_cast<int>(h);
    }

    void readScanline(std::vector<uint8_t> &line, int y) {
        uint8_t first[4];
        for (uint8_t &value : first)
            value = next();
        // New-style RLE: 2, 2, then the width in two bytes; only for widths 8..32767.
        if (first[0] == 2 && first[1] == 2 && (first[2] & 0x80) == 0 && m_width >= 8 &&
            m_width < 32768) {
            if (((first[2] << 8) | first[3]) != m_width)
                fail(fmt::format("scanline {} declares a width other than {}", y, m_width));
            for (int channel = 0; channel < 4; ++channel)
                for (int x = 0; x < m_width;) {
                    int count = next();
                    const bool run = count > 128;
                    if (run)
                        count -= 128;
                    if (count == 0 || x + count > m_width)
                        fail(fmt::format("a run of scanline {} overflows the line", y));
                    const uint8_t value = run ? next() : 0;
                    for (int i = 0; i < count; ++i, ++x)
                        line[4 * std::size_t(x) + channel] = run ? value : next();
                }
            return;
        }
        // Flat pixels, possibly with old-style runs (1, 1, 1, n: repeat the last pixel).
        int x = 0, shift = 0;
        for (bool firstPixel = true; x < m_width; firstPixel = false) {
            uint8_t pixel[4];
            for (int c = 0; c < 4; ++c)
                pixel[c] = firstPixel ? first[c] : next();
            if (pixel[0] == 1 && pixel[1] == 1 && pixel[2] == 1) {
                if (x == 0 || shift > 24)
                    fail(fmt::format("a bad old-style run in scanline {}", y));
                const long count = static_cast<long>(pixel[3]) << shift;
                if (x + count > m_width)
                    fail(fmt::format("a run of scanline {} overflows the line", y));
                for (long i = 0; i < count; ++i, ++x)
                    std::copy_n(&line[4 * std::size_t(x - 1)], 4, &line[4 * std::size_t(x)]);
                shift += 8;
            } else {
                std::copy_n(pixel, 4, &line[4 * std::size_t(x)]);
                ++x;
                shift = 0;
            }
        }
    }

    /// mantissa · 2^(exponent − 136); exponent 0 is black. This is stb_image's, pbrt-v4's
    /// and Walter's rgbe.c decoding, the inverse of their (and our) encoders, which
    /// truncate: values m·2^k with an 8-bit m read back exactly. (Ward's original
    /// (m + 0.5) rounding reads every map up to 0.4 % brighter than the peers do.)
    static Color3f rgbeToColor(const uint8_t *rgbe) {
        if (rgbe[3] == 0)
            return Color3f(0.0f);
        const float scale = std::ldexp(1.0f, static_cast<int>(rgbe[3]) - 136);
        return Color3f(rgbe[0] * scale, rgbe[1] * scale, rgbe[2] * scale);
    }

    const std::string &m_bytes;
    const std::string &m_name;
    std::size_t m_offset = 0;
    int m_width = 0, m_height = 0;
};

// ---------------------------------------------------------------------------------- EXR

/// The R, G and B channels of the first layer that has them (the beauty, "R", "G", "B",
/// sorts first; an alpha channel beside them is ignored), or a single channel as grey.
ImageFile decodeExr(const std::string &bytes, const std::string &name, std::size_t maxPixels) {
    const LayeredImage layered = decodeLayeredEXR(bytes, name, maxPixels);
    for (const std::string &layer : layered.layerNames()) {
        const std::vector<std::string> channels = layered.channelsOf(layer);
        if (channels.size() >= 3 && channels[0] == "R" && channels[1] == "G" && channels[2] == "B")
            return {layered.layer(layer), false, Bitmap()};
    }
    if (layered.channels().size() == 1)
        return {layered.layer(layered.layerNames().front()), false, Bitmap()};
    throw NoriException("EXR image '{}' has no R, G and B channels (and is not a one-channel "
                        "grey image)",
                        name);
}

// ---------------------------------------------------------------------------------- PFM
// Portable float map: "PF" (RGB) or "Pf" (grey), width and height, a scale whose sign
// gives the byte order (negative: little-endian), then rows of 32-bit floats from the
// bottom of the image up.

ImageFile decodePfm(const std::string &bytes, const std::string &name, std::size_t maxPixels) {
    std::size_t offset = 2;
    auto token = [&]() {
        while (offset < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[offset])))
            ++offset;
        const std::size_t begin = offset;
        while (offset < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[offset])))
            ++offset;
        if (begin == offset || offset - begin > 32)
            throw NoriException("PFM image '{}' has a malformed header", name);
        return bytes.substr(begin, offset - begin);
    };
    const int channels = bytes[1] == 'F' ? 3 : 1;
    int64_t width = 0, height = 0;
    double scale = 0.0;
    try {
        std::size_t used = 0;
        std::string text = token();
        width = std::stoll(text, &used);
        bool whole = used == text.size();
        text = token();
        height = std::stoll(text, &used);
        whole = whole && used == text.size();
        text = token();
        scale = std::stod(text, &used);
        if (!whole || used != text.size())
            throw std::invalid_argument(text);
    } catch (const std::logic_error &) {
        throw NoriException("PFM image '{}' has a malformed header (expected width, height and "
                            "scale)",
                            name);
    }
    checkSize(width, height, maxPixels, name, "PFM");
    if (!std::isfinite(scale) || scale == 0.0)
        throw NoriException("PFM image '{}' has an invalid scale {} (its sign is the byte order)",
                            name, scale);
    ++offset; // the single whitespace character before the data
    const std::size_t valueCount = std::size_t(width) * std::size_t(height) * channels;
    if (offset > bytes.size() || bytes.size() - offset < valueCount * sizeof(float))
        throw NoriException("PFM image '{}' ends early (truncated): {}x{} pixels need {} bytes",
                            name, width, height, valueCount * sizeof(float));
    const bool bigEndian = scale > 0.0;
    ImageFile image{Bitmap(Eigen::Vector2i(int(width), int(height))), false, Bitmap()};
    for (int64_t row = 0; row < height; ++row)
        for (int64_t x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c) {
                const std::size_t index =
                    (std::size_t(row) * std::size_t(width) + std::size_t(x)) * channels +
                    std::size_t(std::min(c, channels - 1));
                unsigned char raw[4];
                std::memcpy(raw, bytes.data() + offset + 4 * index, 4);
                if (bigEndian)
                    std::reverse(raw, raw + 4);
                float value;
                std::memcpy(&value, raw, 4);
                image.pixels.coeffRef(height - 1 - row, x)[c] = value;
            }
    return image;
}

/// The value of the string attribute `type` of a single-part EXR header as tinyexr reads
/// it: the last non-empty one, up to its first NUL; "" when it has none (or the header is
/// malformed, which tinyexr reports). tinyexr asserts, and so aborts, on a `type` that is
/// not one of its four names or disagrees with the tiled flag.
std::string exrTypeAttribute(const std::string &bytes) {
    std::size_t offset = 8; // magic number and version
    std::string type;
    while (offset < bytes.size() && bytes[offset] != '\0') {
        const std::size_t nameEnd = bytes.find('\0', offset);
        if (nameEnd == std::string::npos)
            return type;
        const std::size_t typeEnd = bytes.find('\0', nameEnd + 1);
        if (typeEnd == std::string::npos || bytes.size() - typeEnd - 1 < 4)
            return type;
        uint32_t size = 0;
        for (int k = 3; k >= 0; --k) // little-endian
            size = (size << 8) | static_cast<unsigned char>(bytes[typeEnd + 1 + k]);
        const std::size_t dataStart = typeEnd + 5;
        if (size > bytes.size() - dataStart)
            return type;
        if (bytes.compare(offset, nameEnd - offset, "type") == 0) {
            const std::string value = bytes.substr(dataStart, size);
            if (!value.empty() && value[0] != '\0')
                type = value.substr(0, value.find('\0'));
        }
        offset = dataStart + size;
    }
    return type;
}

// ---------------------------------------------------------------------------- TGA
// Truevision TGA (the "Truevision TGA File Format Specification", version 2.0, 1989):
// true-colour, grey and colour-mapped images, plain or run-length coded, 8 to 32 bits a
// pixel, stored bottom-up unless the descriptor says otherwise. Every read is
// bounds-checked; every run must fit the image.

class TgaReader {
public:
    TgaReader(const std::string &bytes, const std::string &name) : m_bytes(bytes), m_name(name) {}

    ImageFile decode(std::size_t maxPixels) {
        const uint8_t idLength = next(), colorMapType = next(), imageType = next();
        const int mapFirst = next16(), mapLength = next16(), mapEntryBits = next();
        next16(); // x origin
        next16(); // y origin
        const int width = next16(), height = next16(), pixelBits = next(), descriptor = next();
        const bool mapped = imageType == 1 || imageType == 9;
        const bool grey = imageType == 3 || imageType == 11;
        const bool runLength = imageType >= 9;
        if (!(imageType == 1 || imageType == 2 || imageType == 3 || imageType == 9 ||
              imageType == 10 || imageType == 11))
            fail(fmt::format("unsupported image type {} (1-3 and 9-11: colour-mapped, true-colour, "
                             "grey, plain or run-length coded)",
                             imageType));
        if (colorMapType > 1 || (mapped && colorMapType != 1))
            fail(fmt::format("colour map type {} does not fit image type {}", colorMapType,
                             imageType));
        checkSize(width, height, maxPixels, m_name, "TGA");
        if (mapped
                ? pixelBits != 8 && pixelBits != 16
                : (grey ? pixelBits != 8 && pixelBits != 16
                        : pixelBits != 15 && pixelBits != 16 && pixelBits != 24 && pixelBits != 32))
            fail(fmt::format("{} bits a pixel do not fit image type {}", pixelBits, imageType));
        skip(idLength);
        std::vector<Color3f> palette;
        if (colorMapType == 1) {
            if (mapEntryBits != 15 && mapEntryBits != 16 && mapEntryBits != 24 &&
                mapEntryBits != 32)
                fail(fmt::format("colour-map entries of {} bits", mapEntryBits));
            palette.reserve(static_cast<std::size_t>(mapLength));
            for (int i = 0; i < mapLength; ++i)
                palette.push_back(readColor(mapEntryBits, false));
        }
        auto readPixel = [&]() -> Color3f {
            if (!mapped)
                return readColor(pixelBits, grey);
            const int index = (pixelBits == 8 ? next() : next16()) - mapFirst;
            if (index < 0 || index >= static_cast<int>(palette.size()))
                fail(fmt::format("colour index {} outside the map of {} entries", index + mapFirst,
                                 palette.size()));
            return palette[static_cast<std::size_t>(index)];
        };
        ImageFile image{Bitmap(Eigen::Vector2i(width, height)), true, Bitmap()};
        const std::size_t count =
            static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
        std::size_t written = 0;
        auto store = [&](const Color3f &color) {
            // Rows run bottom-up unless bit 5 of the descriptor is set, right to left if bit 4.
            const std::size_t row = written / static_cast<std::size_t>(width);
            const std::size_t column = written % static_cast<std::size_t>(width);
            const int y =
                (descriptor & 0x20) ? static_cast<int>(row) : height - 1 - static_cast<int>(row);
            const int x = (descriptor & 0x10) ? width - 1 - static_cast<int>(column)
                                              : static_cast<int>(column);
            image.pixels.coeffRef(y, x) = color;
            ++written;
        };
        while (written < count) {
            if (!runLength) {
                store(readPixel());
                continue;
            }
            const uint8_t packet = next();
            const std::size_t length = (packet & 0x7f) + 1u;
            if (written + length > count)
                fail("a run-length packet runs past the end of the image");
            if (packet & 0x80) {
                const Color3f color = readPixel();
                for (std::size_t i = 0; i < length; ++i)
                    store(color);
            } else {
                for (std::size_t i = 0; i < length; ++i)
                    store(readPixel());
            }
        }
        return image;
    }

private:
    [[noreturn]] void fail(const std::string &what) const {
        throw NoriException("TGA image '{}' is invalid: {} (at byte {})", m_name, what, m_offset);
    }
    uint8_t next() {
        if (m_offset >= m_bytes.size())
            fail("the file ends early (truncated)");
        return static_cast<uint8_t>(m_bytes[m_offset++]);
    }
    int next16() {
        const int low = next();
        return low | (next() << 8);
    }
    void skip(std::size_t count) {
        if (count > m_bytes.size() - m_offset)
            fail("the file ends early (truncated)");
        m_offset += count;
    }
    /// A stored colour: BGR(A) bytes, 5-5-5 bits (A RRRRR GGGGG BBBBB, little-endian), or
    /// grey; 16-bit grey is an 8-bit value and its alpha. Alpha is dropped.
    Color3f readColor(int bits, bool grey) {
        if (grey) {
            const float value = static_cast<float>(next()) / 255.0f;
            if (bits == 16)
                next();
            return Color3f(value);
        }
        if (bits == 15 || bits == 16) {
            const int packed = next16();
            return Color3f(static_cast<float>((packed >> 10) & 31) / 31.0f,
                           static_cast<float>((packed >> 5) & 31) / 31.0f,
                           static_cast<float>(packed & 31) / 31.0f);
        }
        const float b = static_cast<float>(next()) / 255.0f,
                    g = static_cast<float>(next()) / 255.0f,
                    r = static_cast<float>(next()) / 255.0f;
        if (bits == 32)
            next();
        return Color3f(r, g, b);
    }

    const std::string &m_bytes;
    const std::string &m_name;
    std::size_t m_offset = 0;
};

/// Whether a file is a TGA: it has no signature at its start, so by its name, or by the
/// footer of version 2.0 files.
bool isTga(const std::string &bytes, const std::string &name) {
    const std::string lower = toLower(name);
    if (lower.size() >= 4 && lower.compare(lower.size() - 4, 4, ".tga") == 0)
        return true;
    static const char kFooter[] = "TRUEVISION-XFILE.";
    const std::size_t footerLength = sizeof(kFooter); // with its NUL
    return bytes.size() >= 26 + 18 &&
           std::memcmp(bytes.data() + bytes.size() - footerLength, kFooter, footerLength) == 0;
}

/// The scan lines in each chunk of an EXR file of this compression (tinyexr's codes: the
/// OpenEXR ones it reads, and its own ZFP).
int64_t exrLinesPerChunk(int compression) {
    switch (compression) {
    case TINYEXR_COMPRESSIONTYPE_ZIP:
    case TINYEXR_COMPRESSIONTYPE_ZFP:
        return 16;
    case TINYEXR_COMPRESSIONTYPE_PIZ:
        return 32;
    default: // NONE, RLE, ZIPS
        return 1;
    }
}

} // namespace

LayeredImage decodeLayeredEXR(const std::string &bytes, const std::string &name,
                              std::size_t maxPixels) {
    const auto *data = reinterpret_cast<const unsigned char *>(bytes.data());
    auto failure = [&](const char *error, const char *fallback) {
        std::string message = error ? error : fallback;
        FreeEXRErrorMessage(error);
        while (!message.empty() && std::isspace(static_cast<unsigned char>(message.back())))
            message.pop_back();
        return NoriException("EXR image '{}' is invalid: {}", name, message);
    };
    EXRVersion version;
    if (ParseEXRVersionFromMemory(&version, data, bytes.size()) != TINYEXR_SUCCESS)
        throw failure(nullptr, "bad version field");
    if (version.tiled || version.multipart || version.non_image)
        throw NoriException("EXR image '{}': tiled, multi-part and deep EXR files are not "
                            "supported; save it as a single-part scanline EXR",
                            name);
    const std::string type = exrTypeAttribute(bytes);
    if (!type.empty() && type != "scanlineimage")
        throw NoriException("EXR image '{}': its type is '{}', but only single-part scanline "
                            "images (type 'scanlineimage') are supported",
                            name, type);
    EXRHeader header;
    InitEXRHeader(&header);
    struct HeaderGuard {
        EXRHeader &header;
        ~HeaderGuard() { FreeEXRHeader(&header); }
    } headerGuard{header};
    const char *error = nullptr;
    if (ParseEXRHeaderFromMemory(&header, &version, data, bytes.size(), &error) != TINYEXR_SUCCESS)
        throw failure(error, "bad header");
    if (header.tiled)
        throw NoriException("EXR image '{}': tiled EXR files are not supported", name);
    const int64_t width = int64_t(header.data_window.max_x) - header.data_window.min_x + 1;
    const int64_t height = int64_t(header.data_window.max_y) - header.data_window.min_y + 1;
    checkSize(width, height, maxPixels, name, "EXR");
    // All channels are decoded: bound their number and total size too.
    if (header.num_channels < 1 || header.num_channels > kMaxEXRChannels ||
        uint64_t(width) * uint64_t(height) * uint64_t(header.num_channels) > 4 * maxPixels)
        throw NoriException("EXR image '{}' has {} channels of {}x{} pixels (1 to {} channels, "
                            "at most {} values in all)",
                            name, header.num_channels, width, height, kMaxEXRChannels,
                            4 * maxPixels);
    // A scanline image is stored in chunks of 1, 16 or 32 lines by its compression (OpenEXR's
    // "Technical Introduction", "Scan Lines"); the optional `chunkCount` attribute must say
    // the same. tinyexr sizes its offset table by the attribute alone, unchecked: 2^31 − 1
    // chunks declared by a 1×1 image would take 16 GiB before the table is read.
    if (header.chunk_count > 0) {
        const int64_t linesPerChunk = exrLinesPerChunk(header.compression_type);
        const int64_t chunks = (height + linesPerChunk - 1) / linesPerChunk;
        if (header.chunk_count != chunks)
            throw NoriException("EXR image '{}' declares {} chunks (attribute 'chunkCount'), "
                                "but an image of {} lines in chunks of {} has {}",
                                name, header.chunk_count, height, linesPerChunk, chunks);
    }
    for (int c = 0; c < header.num_channels; ++c)
        if (header.pixel_types[c] == TINYEXR_PIXELTYPE_HALF)
            header.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;

    EXRImage exr;
    InitEXRImage(&exr);
    // tinyexr 1.0.1 sets num_channels only after a successful decode, and on a bad chunk
    // calls FreeEXRImage, which then frees the channel array but not the channels (a
    // leak) and leaves the array pointer dangling. Setting num_channels first makes that
    // FreeEXRImage free the channels too; after a failure nothing is left to free.
    exr.num_channels = header.num_channels;
    if (LoadEXRImageFromMemory(&exr, &header, data, bytes.size(), &error) != TINYEXR_SUCCESS)
        throw failure(error, "bad pixel data");
    struct ImageGuard {
        EXRImage &image;
        ~ImageGuard() { FreeEXRImage(&image); }
    } imageGuard{exr};

    LayeredImage image(Eigen::Vector2i(exr.width, exr.height));
    for (int c = 0; c < header.num_channels; ++c) {
        LayeredImage::Channel values(exr.height, exr.width);
        for (int64_t i = 0; i < int64_t(exr.width) * exr.height; ++i)
            values(i / exr.width, i % exr.width) =
                header.pixel_types[c] == TINYEXR_PIXELTYPE_UINT
                    ? static_cast<float>(reinterpret_cast<const unsigned int *>(exr.images[c])[i])
                    : reinterpret_cast<const float *>(exr.images[c])[i];
        const std::string channelName = header.channels[c].name;
        if (image.channels().count(channelName))
            throw NoriException("EXR image '{}' has two channels named '{}'", name, channelName);
        image.addChannel(channelName, std::move(values));
    }
    for (int a = 0; a < header.num_custom_attributes; ++a) {
        const EXRAttribute &attribute = header.custom_attributes[a];
        if (std::strcmp(attribute.type, "string") == 0 && attribute.size >= 0)
            image.attributes[attribute.name] =
                std::string(reinterpret_cast<const char *>(attribute.value), attribute.size);
    }
    return image;
}

ImageFile decodeImageFile(const std::string &bytes, const std::string &name,
                          std::size_t maxPixels) {
    if (startsWith(bytes, "\x89PNG\r\n\x1a\n", 8))
        return decodePng(bytes, name, maxPixels);
    if (startsWith(bytes, "\xff\xd8\xff", 3))
        return decodeJpeg(bytes, name, maxPixels);
    if (startsWith(bytes, "\x76\x2f\x31\x01", 4))
        return decodeExr(bytes, name, maxPixels);
    if (startsWith(bytes, "#?", 2))
        return HdrReader(bytes, name).decode(maxPixels);
    if (startsWith(bytes, "PF", 2) || startsWith(bytes, "Pf", 2))
        return decodePfm(bytes, name, maxPixels);
    if (isTga(bytes, name))
        return TgaReader(bytes, name).decode(maxPixels);
    throw NoriException("'{}' is not a PNG, JPEG, Radiance HDR, OpenEXR, PFM or TGA image "
                        "(unknown signature)",
                        name);
}

ImageFile readImageFile(const std::string &filename) {
    return decodeImageFile(readBinaryFile(filename, "image file"), filename);
}

} // namespace nori
