#include "vlf/core/checksum.hpp"

#include <fmt/format.h>
#include <openssl/evp.h>

#include <fstream>
#include <vector>

#include "vlf/core/error.hpp"

namespace vlf {

struct Sha256::Context {
    EVP_MD_CTX* ctx = EVP_MD_CTX_new();
    ~Context() { EVP_MD_CTX_free(ctx); }
};

Sha256::Sha256() : m_context(std::make_unique<Context>()) {
    if (m_context->ctx == nullptr || EVP_DigestInit_ex(m_context->ctx, EVP_sha256(), nullptr) != 1)
        throw Error("SHA-256: libcrypto could not initialise a digest");
}

Sha256::~Sha256() = default;

void Sha256::update(const void* data, size_t bytes) {
    if (bytes > 0 && EVP_DigestUpdate(m_context->ctx, data, bytes) != 1)
        throw Error("SHA-256: libcrypto digest update failed");
}

std::array<uint8_t, 32> Sha256::digest() {
    std::array<uint8_t, 32> out{};
    unsigned int size = 0;
    if (EVP_DigestFinal_ex(m_context->ctx, out.data(), &size) != 1 || size != out.size())
        throw Error("SHA-256: libcrypto digest failed");
    return out;
}

std::string Sha256::hex_digest() {
    std::string hex;
    hex.reserve(64);
    for (uint8_t b : digest()) hex += fmt::format("{:02x}", b);
    return hex;
}

std::string sha256_hex(std::string_view data) {
    Sha256 h;
    h.update(data);
    return h.hex_digest();
}

std::string sha256_file(const std::string& path, uint64_t& bytes) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(fmt::format("{}: cannot be opened for reading", path));
    Sha256 h;
    std::vector<char> buf(1 << 20);
    bytes = 0;
    while (in) {
        in.read(buf.data(), static_cast<std::streamsize>(buf.size()));
        const std::streamsize got = in.gcount();
        if (got <= 0) break;
        h.update(buf.data(), static_cast<size_t>(got));
        bytes += static_cast<uint64_t>(got);
    }
    if (in.bad()) throw Error(fmt::format("{}: read error", path));
    return h.hex_digest();
}

}  // namespace vlf
