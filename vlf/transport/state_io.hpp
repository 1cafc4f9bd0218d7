// state_io.hpp — the binary streams a checkpoint's state file is written and read with
// (checkpoint.hpp): tagged sections of plain values and arrays, in the machine's own byte
// order (the checkpoint's manifest names it), hashed with SHA-256 as they are written.
// A reader checks every tag and length against what the running transport expects, so a
// file from another build or another scene fails with the section's name, never with a
// silently wrong map.
#pragma once

#include <fmt/format.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <type_traits>
#include <vector>

#include "vlf/core/checksum.hpp"
#include "vlf/core/error.hpp"

namespace vlf {

class StateWriter {
  public:
    explicit StateWriter(const std::string& path)
        : m_path(path), m_out(path, std::ios::binary | std::ios::trunc) {
        if (!m_out) throw Error(fmt::format("{}: cannot write", path));
    }
    // A section: its tag, then its length in values, then the values' bytes.
    template <class T>
    void array(const char* tag, const T* data, uint64_t count) {
        static_assert(std::is_trivially_copyable_v<T>);
        header(tag, count, sizeof(T));
        bytes(data, count * sizeof(T));
    }
    template <class T>
    void array(const char* tag, const std::vector<T>& v) {
        array(tag, v.data(), v.size());
    }
    template <class T>
    void value(const char* tag, const T& v) {
        array(tag, &v, 1);
    }
    // Flushes and closes; throws naming the file when anything failed.
    void close() {
        m_out.close();
        if (!m_out) throw Error(fmt::format("{}: write failed", m_path));
    }
    std::string hex_digest() { return m_hash.hex_digest(); }
    uint64_t size() const { return m_size; }

  private:
    void header(const char* tag, uint64_t count, uint64_t width) {
        char name[16] = {};
        std::strncpy(name, tag, sizeof(name) - 1);
        bytes(name, sizeof(name));
        bytes(&count, sizeof(count));
        bytes(&width, sizeof(width));
    }
    void bytes(const void* p, uint64_t n) {
        m_out.write(static_cast<const char*>(p), static_cast<std::streamsize>(n));
        m_hash.update(p, n);
        m_size += n;
    }
    std::string m_path;
    std::ofstream m_out;
    Sha256 m_hash;
    uint64_t m_size = 0;
};

class StateReader {
  public:
    explicit StateReader(const std::string& path) : m_path(path), m_in(path, std::ios::binary) {
        if (!m_in) throw Error(fmt::format("{}: cannot be read", path));
    }
    // Reads a section into v; `expected` (when not -1) is the length the caller needs.
    template <class T>
    void array(const char* tag, std::vector<T>& v, int64_t expected = -1) {
        static_assert(std::is_trivially_copyable_v<T>);
        const uint64_t count = header(tag, sizeof(T));
        if (expected >= 0 && count != uint64_t(expected))
            throw Error(fmt::format("{}: section '{}' holds {} values where this run has {}",
                                    m_path, tag, count, expected));
        v.resize(count);
        bytes(v.data(), count * sizeof(T), tag);
    }
    // Reads only the values [first, first + v.size()) of a section of `expected` values into
    // v (an MPI rank's own directions' rays, issue 13) and skips the others.
    template <class T>
    void array_part(const char* tag, std::vector<T>& v, uint64_t expected, uint64_t first) {
        static_assert(std::is_trivially_copyable_v<T>);
        const uint64_t count = header(tag, sizeof(T));
        if (count != expected)
            throw Error(fmt::format("{}: section '{}' holds {} values where this run has {}",
                                    m_path, tag, count, expected));
        if (first + v.size() > count)
            throw Error(
                fmt::format("{}: section '{}' is shorter than the part asked", m_path, tag));
        skip(first * sizeof(T), tag);
        bytes(v.data(), v.size() * sizeof(T), tag);
        skip((count - first - v.size()) * sizeof(T), tag);
    }
    template <class T>
    void value(const char* tag, T& v) {
        static_assert(std::is_trivially_copyable_v<T>);
        if (header(tag, sizeof(T)) != 1)
            throw Error(fmt::format("{}: section '{}' is not one value", m_path, tag));
        bytes(&v, sizeof(T), tag);
    }
    // The file must end here.
    void finish() {
        if (m_in.peek() != std::char_traits<char>::eof())
            throw Error(fmt::format("{}: unexpected data after the last section", m_path));
    }

  private:
    uint64_t header(const char* tag, uint64_t width) {
        char name[16] = {};
        uint64_t count = 0, w = 0;
        bytes(name, sizeof(name), tag);
        bytes(&count, sizeof(count), tag);
        bytes(&w, sizeof(w), tag);
        name[sizeof(name) - 1] = 0;
        if (std::strncmp(name, tag, sizeof(name) - 1) != 0)
            throw Error(fmt::format("{}: expected section '{}', found '{}'", m_path, tag, name));
        if (w != width)
            throw Error(fmt::format("{}: section '{}' has {}-byte values where this build has {}",
                                    m_path, tag, w, width));
        return count;
    }
    void skip(uint64_t n, const char* tag) {
        m_in.seekg(static_cast<std::streamoff>(n), std::ios::cur);
        if (!m_in) throw Error(fmt::format("{}: truncated in section '{}'", m_path, tag));
    }
    void bytes(void* p, uint64_t n, const char* tag) {
        m_in.read(static_cast<char*>(p), static_cast<std::streamsize>(n));
        if (uint64_t(m_in.gcount()) != n)
            throw Error(fmt::format("{}: truncated in section '{}'", m_path, tag));
    }
    std::string m_path;
    std::ifstream m_in;
};

}  // namespace vlf
