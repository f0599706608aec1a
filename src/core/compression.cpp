#include <nori/common.h>
#include <nori/compression.h>

#include <zlib.h>

#include <algorithm>
#include <limits>

namespace nori {

bool isGzip(std::string_view bytes) {
    return bytes.size() >= 2 && static_cast<unsigned char>(bytes[0]) == 0x1f &&
           static_cast<unsigned char>(bytes[1]) == 0x8b;
}

std::string inflateBytes(std::string_view compressed, CompressedFormat format,
                         const std::string &what, size_t maxSize, size_t *consumed) {
    z_stream stream{};
    // windowBits 15, plus 16 for a gzip header and trailer (zlib.h, inflateInit2).
    if (inflateInit2(&stream, format == CompressedFormat::Gzip ? 15 + 16 : 15) != Z_OK)
        throw NoriException("{}: cannot start zlib's decompressor", what);
    std::string output;
    size_t inputOffset = 0;
    int status = Z_OK;
    char buffer[1 << 16];
    while (status != Z_STREAM_END) {
        if (stream.avail_in == 0) {
            const size_t chunk =
                std::min<size_t>(compressed.size() - inputOffset, std::numeric_limits<uInt>::max());
            if (chunk == 0) {
                inflateEnd(&stream);
                throw NoriException("{}: the compressed data ends before its stream does", what);
            }
            stream.next_in =
                reinterpret_cast<Bytef *>(const_cast<char *>(compressed.data() + inputOffset));
            stream.avail_in = static_cast<uInt>(chunk);
            inputOffset += chunk;
        }
        stream.next_out = reinterpret_cast<Bytef *>(buffer);
        stream.avail_out = sizeof(buffer);
        status = inflate(&stream, Z_NO_FLUSH);
        if (status != Z_OK && status != Z_STREAM_END) {
            const std::string reason = stream.msg ? stream.msg : "corrupt data";
            inflateEnd(&stream);
            throw NoriException("{}: the compressed data is malformed ({})", what, reason);
        }
        const size_t produced = sizeof(buffer) - stream.avail_out;
        if (output.size() + produced > maxSize) {
            inflateEnd(&stream);
            throw NoriException("{}: inflates to more than {} bytes", what, maxSize);
        }
        output.append(buffer, produced);
    }
    if (consumed)
        *consumed = inputOffset - stream.avail_in;
    inflateEnd(&stream);
    return output;
}

} // namespace nori
