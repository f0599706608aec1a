// Decompression of the zlib and gzip streams that mesh files come in (.ply.gz, Mitsuba's
// `serialized` meshes), through zlib, bounded so that a hostile file cannot make it
// allocate without limit.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace nori {

enum class CompressedFormat {
    Zlib, ///< a zlib stream (RFC 1950)
    Gzip  ///< a gzip file (RFC 1952)
};

/// The most a compressed mesh file may inflate to: 16 GiB, beyond any mesh a machine of
/// 24 GiB renders, so that a hostile stream is stopped there.
constexpr size_t kMaxInflatedMeshBytes = size_t(16) << 30;

/// Whether bytes start with gzip's magic number 1f 8b.
bool isGzip(std::string_view bytes);

/// Inflates a whole stream. Throws NoriException naming `what` when the stream is
/// malformed or truncated, or when it would inflate past `maxSize` bytes. `consumed`, when
/// given, receives the number of input bytes the stream took (a file may hold several).
std::string inflateBytes(std::string_view compressed, CompressedFormat format,
                         const std::string &what, size_t maxSize, size_t *consumed = nullptr);

} // namespace nori
