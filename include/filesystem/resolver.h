// filesystem::resolver as Nori 2 has it: an ordered list of folders in which a relative
// file name is looked up (nori::getFileResolver() returns the renderer's, which puts the
// folder of the scene file being read first).
#pragma once

#include <filesystem/path.h>

#include <algorithm>
#include <vector>

namespace filesystem {

class resolver {
public:
    using iterator = std::vector<path>::iterator;
    using const_iterator = std::vector<path>::const_iterator;

    resolver() { m_paths.push_back(path::getcwd()); }

    size_t size() const { return m_paths.size(); }
    iterator begin() { return m_paths.begin(); }
    iterator end() { return m_paths.end(); }
    const_iterator begin() const { return m_paths.begin(); }
    const_iterator end() const { return m_paths.end(); }
    void erase(iterator it) { m_paths.erase(it); }
    void prepend(const path &folder) { m_paths.insert(m_paths.begin(), folder); }
    void append(const path &folder) { m_paths.push_back(folder); }
    const path &operator[](size_t index) const { return m_paths[index]; }
    path &operator[](size_t index) { return m_paths[index]; }

    /// The first folder/value that exists, else `value` unchanged.
    path resolve(const path &value) const {
        if (value.is_absolute())
            return value;
        for (const path &folder : m_paths) {
            const path combined = folder / value;
            if (combined.exists())
                return combined;
        }
        return value;
    }

    friend std::ostream &operator<<(std::ostream &out, const resolver &r) {
        out << "resolver[\n";
        for (size_t i = 0; i < r.m_paths.size(); ++i)
            out << "  \"" << r.m_paths[i] << "\"" << (i + 1 < r.m_paths.size() ? ",\n" : "\n");
        return out << "]";
    }

private:
    std::vector<path> m_paths;
};

} // namespace filesystem
