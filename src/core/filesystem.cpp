#include <nori/common.h>
#include <nori/filesystem.h>
#include <nori/hash.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>

#include <fcntl.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace nori {

namespace {
std::mutex g_recorderMutex;
ReadFileRecorder *g_recorder = nullptr; ///< guarded by g_recorderMutex
} // namespace

ReadFileRecorder::ReadFileRecorder() {
    std::lock_guard<std::mutex> lock(g_recorderMutex);
    if (g_recorder)
        throw NoriException("internal error: a ReadFileRecorder is already recording");
    g_recorder = this;
}

ReadFileRecorder::~ReadFileRecorder() {
    std::lock_guard<std::mutex> lock(g_recorderMutex);
    g_recorder = nullptr;
}

std::set<uint64_t> ReadFileRecorder::digests() const {
    std::lock_guard<std::mutex> lock(g_recorderMutex);
    return m_digests;
}

void recordFileRead(const std::string &bytes) {
    {
        std::lock_guard<std::mutex> lock(g_recorderMutex);
        if (!g_recorder)
            return; // no digest to compute
    }
    const uint64_t digest = hashBytes(bytes); // outside the lock: parallel loads hash at once
    std::lock_guard<std::mutex> lock(g_recorderMutex);
    if (g_recorder)
        g_recorder->m_digests.insert(digest);
}

void requireRegularFile(const std::string &path, const std::string &what) {
    std::error_code error;
    const fs::file_status status = fs::status(path, error);
    if (status.type() == fs::file_type::not_found)
        throw NoriException("cannot open {} '{}': no such file", what, path);
    if (error)
        throw NoriException("cannot open {} '{}': {}", what, path, error.message());
    if (status.type() == fs::file_type::directory)
        throw NoriException("cannot open {} '{}': it is a directory, not a file", what, path);
    if (status.type() != fs::file_type::regular)
        throw NoriException("cannot open {} '{}': not a regular file (a device, pipe or socket)",
                            what, path);
}

std::string canonicalPathOrSame(const std::string &path) {
    std::error_code error;
    const fs::path canonical = fs::weakly_canonical(path, error);
    return error ? path : canonical.string();
}

std::string readBinaryFile(const std::string &path, const std::string &what) {
    requireRegularFile(path, what);
    std::ifstream stream(path, std::ios::binary);
    if (!stream)
        throw NoriException("cannot open {} '{}': {}", what, path, std::strerror(errno));
    // Read into a string of the file's size: no growing buffer and copy, whose freed
    // blocks would also raise glibc's threshold for mapping large blocks and so leave the
    // big allocations that follow (a large scene's records) in the heap for good.
    stream.seekg(0, std::ios::end);
    const std::streamoff size = stream.tellg();
    stream.seekg(0, std::ios::beg);
    std::string bytes(static_cast<size_t>(std::max<std::streamoff>(size, 0)), '\0');
    stream.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (stream.bad() || size < 0)
        throw NoriException("cannot read {} '{}': read error", what, path);
    bytes.resize(static_cast<size_t>(stream.gcount())); // shorter if it shrank meanwhile
    recordFileRead(bytes);
    return bytes;
}

std::string readTextFile(const std::string &path, const std::string &what) {
    std::string text = readBinaryFile(path, what);
    const size_t nul = text.find('\0');
    if (nul != std::string::npos)
        throw NoriException("'{}' is not a text file (a NUL byte at offset {}), so not a valid {}",
                            path, nul, what);
    return text;
}

void writeBinaryFile(const std::string &path, const std::string &bytes, const std::string &what) {
    // Written beside the target under a name of its own, made durable, then renamed over
    // it: rename() within one file system replaces the old file in one step, so a reader
    // sees the old file or the new one, and a write that fails (disk full, file size
    // limit, no permission) or a process killed mid-write leaves the old file as it was.
    const fs::path target(path);
    const fs::path folder = target.has_parent_path() ? target.parent_path() : fs::path(".");
    static std::atomic<uint64_t> counter{0};
    std::string temporary;
    int fd = -1;
    for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
        temporary = (folder / fmt::format(".{}.{}-{}.tmp", target.filename().string(),
                                          static_cast<long>(::getpid()), counter++))
                        .string();
        // 0666 before the umask, as a file the program created directly would have.
        fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0 && errno != EEXIST)
            break;
    }
    const auto fail = [&](int error) {
        if (fd >= 0)
            ::close(fd);
        ::unlink(temporary.c_str());
        throw NoriException("cannot write {} '{}': {}", what, path, std::strerror(error));
    };
    if (fd < 0)
        throw NoriException("cannot write {} '{}': {}", what, path, std::strerror(errno));
    size_t written = 0;
    while (written < bytes.size()) {
        const ssize_t count = ::write(fd, bytes.data() + written, bytes.size() - written);
        if (count < 0 && errno == EINTR)
            continue;
        if (count <= 0)
            fail(count < 0 ? errno : ENOSPC);
        written += size_t(count);
    }
    if (::fsync(fd) != 0)
        fail(errno);
    const int closed = ::close(fd);
    fd = -1;
    if (closed != 0)
        fail(errno);
    if (::rename(temporary.c_str(), path.c_str()) != 0)
        fail(errno);
    // The rename itself reaches the disk with the folder's entry.
    const int directory = ::open(folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (directory >= 0) {
        ::fsync(directory);
        ::close(directory);
    }
}

void writeFileIfChanged(const std::string &path, const std::string &text) {
    {
        std::ifstream existing(path, std::ios::binary);
        std::ostringstream buffer;
        buffer << existing.rdbuf();
        if (existing && buffer.str() == text)
            return;
    }
    writeBinaryFile(path, text, "file");
}

} // namespace nori
