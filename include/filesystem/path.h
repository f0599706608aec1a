// filesystem::path as Nori 2 has it (wjakob's small filesystem library, which Nori 2
// ships in ext/): course code that loads its own files (a texture, a mesh, a lens) writes
// `filesystem::path p = getFileResolver()->resolve(name); ... p.str() ...`. Here it is a
// thin layer on std::filesystem::path with the same member names.
#pragma once

#include <cstddef>
#include <filesystem>
#include <ostream>
#include <string>
#include <system_error>

namespace filesystem {

class path {
public:
    enum path_type { windows_path = 0, posix_path = 1, native_path = posix_path };

    path() = default;
    path(const char *text) : m_path(text) {}                // NOLINT: implicit as in the library
    path(const std::string &text) : m_path(text) {}         // NOLINT: implicit as in the library
    path(std::filesystem::path p) : m_path(std::move(p)) {} // NOLINT: implicit on purpose

    bool empty() const { return m_path.empty(); }
    bool is_absolute() const { return m_path.is_absolute(); }
    path make_absolute() const { return path(std::filesystem::absolute(m_path)); }
    bool exists() const {
        std::error_code error;
        return std::filesystem::exists(m_path, error);
    }
    bool is_directory() const {
        std::error_code error;
        return std::filesystem::is_directory(m_path, error);
    }
    bool is_file() const {
        std::error_code error;
        return std::filesystem::is_regular_file(m_path, error);
    }
    size_t file_size() const {
        std::error_code error;
        const auto size = std::filesystem::file_size(m_path, error);
        return error ? 0 : static_cast<size_t>(size);
    }
    /// The number of components ("a/b/c.txt": 3).
    size_t length() const {
        return static_cast<size_t>(std::distance(m_path.begin(), m_path.end()));
    }
    /// The extension without its dot ("obj"), or "".
    std::string extension() const {
        const std::string ext = m_path.extension().string();
        return ext.empty() ? ext : ext.substr(1);
    }
    std::string filename() const { return m_path.filename().string(); }
    path parent_path() const { return path(m_path.parent_path()); }
    path operator/(const path &other) const { return path(m_path / other.m_path); }
    std::string str(path_type type = native_path) const {
        (void)type;
        return m_path.string();
    }
    void set(const std::string &text, path_type type = native_path) {
        (void)type;
        m_path = text;
    }
    bool remove_file() const {
        std::error_code error;
        return std::filesystem::remove(m_path, error);
    }
    static path getcwd() { return path(std::filesystem::current_path()); }

    bool operator==(const path &other) const { return m_path == other.m_path; }
    bool operator!=(const path &other) const { return m_path != other.m_path; }
    friend std::ostream &operator<<(std::ostream &out, const path &p) { return out << p.str(); }

    /// The standard library's path, for code of ours that takes one.
    const std::filesystem::path &native() const { return m_path; }

private:
    std::filesystem::path m_path;
};

} // namespace filesystem
