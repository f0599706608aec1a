// Checks of files named from outside (XML, command line): one place that turns what the
// file system says into a clear NoriException, never a std::filesystem_error.
#pragma once

#include <cstdint>
#include <set>
#include <string>

namespace nori {

/// Throws NoriException naming `what` (e.g. "XML file") and `path` unless path names a
/// regular file: "no such file", "is a directory", "is not a regular file (a device,
/// pipe or socket)", or the system's reason ("File name too long", "Too many levels of
/// symbolic links").
void requireRegularFile(const std::string &path, const std::string &what);

/// The canonical form of `path` (symbolic links resolved) where it can be found, else
/// `path` unchanged; never throws.
std::string canonicalPathOrSame(const std::string &path);

/// Reads a whole regular file's bytes (checked as requireRegularFile does); throws
/// NoriException naming `what` and `path` when it cannot.
std::string readBinaryFile(const std::string &path, const std::string &what);
/// Reads a whole regular file (checked as requireRegularFile does). Throws NoriException
/// on a read error, and when the file holds a NUL byte: `what` is a text format, and a
/// binary file (an image, an EXR passed by mistake) is not one.
std::string readTextFile(const std::string &path, const std::string &what);

/// Writes `bytes` to `path` atomically: to a temporary file in the same folder, flushed to
/// the disk, then renamed over `path`. When that fails (disk full, file size limit, no
/// permission) the previous file stays as it was, the temporary file is removed, and a
/// NoriException names `what`, `path` and the reason. Every file the programs write
/// (images, render parts, meshes, volumes) goes through here.
void writeBinaryFile(const std::string &path, const std::string &bytes, const std::string &what);
/// Writes `text` to `path` unless the file already holds exactly that (so generated
/// files keep their time stamps); throws NoriException when it cannot.
void writeFileIfChanged(const std::string &path, const std::string &text);

/// Records, while it lives, a digest (hashBytes) of every file read through
/// readBinaryFile or readTextFile, by any thread: what loading a scene read (the XML file,
/// its includes, meshes, textures, lens files), for a hash that tells whether two
/// processes rendered the same scene. One recorder at a time.
class ReadFileRecorder {
public:
    ReadFileRecorder();
    ~ReadFileRecorder();
    ReadFileRecorder(const ReadFileRecorder &) = delete;
    ReadFileRecorder &operator=(const ReadFileRecorder &) = delete;

    /// The digests of the files read so far, sorted (so independent of the order in which
    /// parallel loads happened, and of where the files are).
    std::set<uint64_t> digests() const;

private:
    friend void recordFileRead(const std::string &bytes);
    std::set<uint64_t> m_digests;
};

} // namespace nori
