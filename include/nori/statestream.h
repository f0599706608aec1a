// The binary state of a render between two passes, as a checkpoint holds it: values
// appended in a fixed order and read back in that order, every read checked against the
// bytes left, so that a truncated or foreign file is an error and never a crash.
#pragma once

#include <nori/common.h>

#include <cstring>
#include <string>
#include <type_traits>

namespace nori {

class StateWriter {
public:
    /// Appends a plain value (a number, a bool) in the machine's byte order.
    template <typename T> void write(const T &value) {
        static_assert(std::is_arithmetic_v<T>, "write numbers one by one");
        if constexpr (std::is_same_v<T, bool>)
            m_bytes.push_back(value ? 1 : 0);
        else
            m_bytes.append(reinterpret_cast<const char *>(&value), sizeof(T));
    }
    /// Appends `count` numbers after their count.
    template <typename T> void writeArray(const T *data, size_t count) {
        static_assert(std::is_arithmetic_v<T>, "write arrays of numbers");
        write<uint64_t>(count);
        if (count > 0) // data may be null then
            m_bytes.append(reinterpret_cast<const char *>(data), count * sizeof(T));
    }
    void writeString(const std::string &text) { writeArray(text.data(), text.size()); }

    const std::string &bytes() const { return m_bytes; }

private:
    std::string m_bytes;
};

class StateReader {
public:
    /// Reads `bytes`; `what` names them in errors ("checkpoint 'out.checkpoint'").
    StateReader(const std::string &bytes, std::string what)
        : m_bytes(bytes), m_what(std::move(what)) {}

    template <typename T> T read() {
        static_assert(std::is_arithmetic_v<T>, "read numbers one by one");
        if constexpr (std::is_same_v<T, bool>) {
            // A byte other than 0 or 1 is no bool (and loading it as one is undefined).
            const auto byte = read<uint8_t>();
            if (byte > 1)
                throw NoriException("{} is corrupt: {} where a yes or no belongs", m_what,
                                    int(byte));
            return byte == 1;
        }
        need(sizeof(T));
        T value;
        std::memcpy(&value, m_bytes.data() + m_offset, sizeof(T));
        m_offset += sizeof(T);
        return value;
    }
    /// Reads an array written by writeArray into `data`, which holds `count` numbers: a
    /// different count is an error (the state is of another image or scene).
    template <typename T> void readArray(T *data, size_t count) {
        static_assert(std::is_arithmetic_v<T>, "read arrays of numbers");
        const auto stored = read<uint64_t>();
        if (stored != count)
            throw NoriException("{} does not fit this render: {} values where {} belong", m_what,
                                stored, count);
        need(count * sizeof(T));
        if (count > 0) // data may be null then
            std::memcpy(data, m_bytes.data() + m_offset, count * sizeof(T));
        m_offset += count * sizeof(T);
    }
    std::string readString() {
        const auto size = read<uint64_t>();
        need(size);
        std::string text = m_bytes.substr(m_offset, size);
        m_offset += size;
        return text;
    }

    bool atEnd() const { return m_offset == m_bytes.size(); }
    const std::string &what() const { return m_what; }

private:
    void need(uint64_t count) const {
        if (count > m_bytes.size() - m_offset)
            throw NoriException("{} is truncated ({} bytes, more expected after byte {})", m_what,
                                m_bytes.size(), m_offset);
    }

    const std::string &m_bytes;
    std::string m_what;
    size_t m_offset = 0;
};

} // namespace nori
