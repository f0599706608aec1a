#include "checkpoint.h"

#include <nori/common.h>
#include <nori/statestream.h>

namespace nori {

namespace {

/// The first bytes of every checkpoint, and the version of its layout.
constexpr const char *kMagic = "nori checkpoint\n";
constexpr uint32_t kLayoutVersion = 1;

} // namespace

std::string encodeCheckpoint(const CheckpointIdentity &identity, const std::string &state) {
    StateWriter writer;
    writer.writeString(kMagic);
    writer.write(kLayoutVersion);
    writer.writeString(identity.version);
    writer.writeString(identity.sceneHash);
    writer.write<uint64_t>(identity.options.size());
    for (const auto &[name, value] : identity.options) {
        writer.writeString(name);
        writer.writeString(value);
    }
    writer.writeString(state);
    return writer.bytes();
}

Checkpoint readCheckpoint(const std::string &bytes, const std::string &file) {
    StateReader reader(bytes, fmt::format("checkpoint '{}'", file));
    const std::string magic = std::string(kMagic);
    // The magic is written as a string: its length (8 bytes), then its text.
    if (bytes.size() < 8 + magic.size() || bytes.compare(8, magic.size(), magic) != 0)
        throw NoriException("'{}' is not a nori checkpoint", file);
    reader.readString();
    const auto layout = reader.read<uint32_t>();
    if (layout != kLayoutVersion)
        throw NoriException("checkpoint '{}' has layout {}; this nori reads layout {}", file,
                            layout, kLayoutVersion);
    Checkpoint checkpoint;
    checkpoint.identity.version = reader.readString();
    checkpoint.identity.sceneHash = reader.readString();
    const auto optionCount = reader.read<uint64_t>();
    if (optionCount > bytes.size()) // each takes at least 16 bytes
        throw NoriException("checkpoint '{}' is corrupt", file);
    for (uint64_t i = 0; i < optionCount; ++i) {
        std::string name = reader.readString();
        checkpoint.identity.options.emplace_back(std::move(name), reader.readString());
    }
    checkpoint.state = reader.readString();
    if (!reader.atEnd())
        throw NoriException("checkpoint '{}' is corrupt: bytes after its end", file);
    return checkpoint;
}

std::string decodeCheckpoint(const std::string &bytes, const std::string &file,
                             const CheckpointIdentity &expected) {
    Checkpoint checkpoint = readCheckpoint(bytes, file);
    const CheckpointIdentity &found = checkpoint.identity;
    if (found.version != expected.version)
        throw NoriException("checkpoint '{}' was written by nori {}; this is nori {} (render "
                            "again without --resume)",
                            file, found.version, expected.version);
    if (found.sceneHash != expected.sceneHash)
        throw NoriException("checkpoint '{}' is of another scene: a file the scene reads, a -D "
                            "definition or --convention changed (scene hash {}, the "
                            "checkpoint's {}; render again without --resume)",
                            file, expected.sceneHash, found.sceneHash);
    for (const auto &[name, value] : expected.options) {
        std::string stored = "(not given)";
        for (const auto &entry : found.options)
            if (entry.first == name)
                stored = entry.second;
        if (stored != value)
            throw NoriException("checkpoint '{}' was rendered with {} {}, this render has {} "
                                "(resume with the same options, or render again without "
                                "--resume)",
                                file, name, stored.empty() ? "(none)" : stored,
                                value.empty() ? "(none)" : value);
    }
    return std::move(checkpoint.state);
}

std::string checkpointFile(const std::string &outputStem) {
    return outputStem + ".checkpoint";
}

} // namespace nori
