// binary_reader.hpp — reads the bundle's little-endian binary parts (geometry.bin,
// textures.bin) with every read bounds-checked: a defect throws Error "<file>: <problem>".
// Internal to vlf/bake.
#pragma once

#include <fmt/format.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <type_traits>
#include <vector>

#include "vlf/core/error.hpp"
#include "vlf/core/math.hpp"

namespace vlf {

// Appends v's bytes (the writers' side of the same parts).
template <class T>
void append_raw(std::vector<char>& out, const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const char* p = reinterpret_cast<const char*>(&v);
    out.insert(out.end(), p, p + sizeof(T));
}

class BinaryReader {
  public:
    // The whole of `file`; Error "<file>: cannot be read" when it cannot be opened.
    explicit BinaryReader(const std::string& file) : m_file(file) {
        std::ifstream in(file, std::ios::binary);
        if (!in) throw Error(fmt::format("{}: cannot be read", file));
        m_bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    [[noreturn]] void fail(const std::string& what) const {
        throw Error(fmt::format("{}: {}", m_file, what));
    }
    template <class T>
    T get(const char* what) {
        static_assert(std::is_trivially_copyable_v<T>);
        T v;
        bytes(&v, sizeof(T), what);
        return v;
    }
    void bytes(void* to, size_t n, const char* what) {
        if (left() < n)
            fail(fmt::format("truncated in {} (at byte {} of {})", what, m_at, m_bytes.size()));
        std::memcpy(to, m_bytes.data() + m_at, n);
        m_at += n;
    }
    double finite(const char* what, size_t index) {
        const double v = get<double>(what);
        if (!std::isfinite(v)) fail(fmt::format("{} of {} is not finite", what, index));
        return v;
    }
    Vec3 vec(const char* what, size_t index) {
        Vec3 v;
        for (int c = 0; c < 3; ++c) v[c] = finite(what, index);
        return v;
    }
    int32_t index(const char* what, size_t of, int32_t lo, int32_t hi) {
        const int32_t v = get<int32_t>(what);
        if (v < lo || v > hi)
            fail(fmt::format("{} of {} is {} (must be in [{}, {}])", what, of, v, lo, hi));
        return v;
    }
    size_t size() const { return m_bytes.size(); }
    size_t left() const { return m_bytes.size() - m_at; }
    void expect_end() const {
        if (m_at != m_bytes.size())
            fail(fmt::format("{} bytes after the last array", m_bytes.size() - m_at));
    }

  private:
    std::string m_file;
    std::vector<char> m_bytes;
    size_t m_at = 0;
};

}  // namespace vlf
