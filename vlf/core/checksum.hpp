// checksum.hpp — SHA-256 for the bake bundle's file checksums (DESIGN §6: "a checksum of
// every other file" in manifest.json), computed by OpenSSL's libcrypto (EVP interface).
// Tested against the FIPS 180-4 / NIST example vectors (tests/bake_test.cpp).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>

namespace vlf {

// Incremental SHA-256: update() any number of times, then digest() once.
class Sha256 {
  public:
    Sha256();
    ~Sha256();
    Sha256(const Sha256&) = delete;
    Sha256& operator=(const Sha256&) = delete;
    void update(const void* data, size_t bytes);
    void update(std::string_view s) { update(s.data(), s.size()); }
    std::array<uint8_t, 32> digest();  // finalises; the object must not be updated after
    std::string hex_digest();          // 64 lower-case hex digits

  private:
    struct Context;
    std::unique_ptr<Context> m_context;
};

std::string sha256_hex(std::string_view data);

// SHA-256 of a file's bytes; `bytes` receives its size. Throws Error naming the path when
// the file cannot be read.
std::string sha256_file(const std::string& path, uint64_t& bytes);

}  // namespace vlf
