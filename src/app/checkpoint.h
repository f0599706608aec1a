// Checkpoint files: a render's state between two passes (RenderOptions::checkpoint),
// written atomically beside the output every so often, so that `nori --resume` continues
// a render that was killed and writes the image the uninterrupted render writes, bit for
// bit. The file says what it is a checkpoint of (nori's version, the scene's hash, the
// options that shape the image), and a resume refuses one of anything else, naming what
// differs.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace nori {

/// What a checkpoint must match to be resumed.
struct CheckpointIdentity {
    std::string version;   ///< nori's version (NORI_VERSION)
    std::string sceneHash; ///< sceneHash(): every file the scene read, -D, --convention
    /// The options that shape the image (--spp, --aovs, --part, ...), as name and value.
    std::vector<std::pair<std::string, std::string>> options;
};

/// The file's bytes: a magic line, the identity, then the render's state.
std::string encodeCheckpoint(const CheckpointIdentity &identity, const std::string &state);

/// A checkpoint file's content.
struct Checkpoint {
    CheckpointIdentity identity;
    std::string state;
};

/// Parses a checkpoint's bytes; throws NoriException naming `file` when they are not one
/// ("'FILE' is not a nori checkpoint"), are truncated or corrupt.
Checkpoint readCheckpoint(const std::string &bytes, const std::string &file);

/// The render's state from a checkpoint's bytes, after checking that it is one (else
/// "'FILE' is not a nori checkpoint") and that its identity is `expected` (else a
/// NoriException naming what differs: the version, the scene, an option).
std::string decodeCheckpoint(const std::string &bytes, const std::string &file,
                             const CheckpointIdentity &expected);

/// The checkpoint file of an output stem: STEM.checkpoint.
std::string checkpointFile(const std::string &outputStem);

} // namespace nori
