#include "vlf/core/files.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "vlf/core/error.hpp"

namespace vlf {

namespace fs = std::filesystem;

std::string lower_extension(const std::string& path) {
    std::string e = fs::path(path).extension().string();
    for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return e;
}

void check_input_file(const std::string& path, const std::string& what) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        throw Error(fmt::format("{} '{}' is a directory, not a file", what, path));
    if (!std::filesystem::exists(path, ec))
        throw Error(fmt::format("{} '{}' does not exist", what, path));
    if (!std::ifstream(path).good()) throw Error(fmt::format("{} '{}' cannot be read", what, path));
}

void check_output_path(const std::string& path) {
    fs::path dir = fs::path(path).parent_path();
    if (dir.empty()) dir = ".";
    std::error_code ec;
    if (!fs::is_directory(dir, ec))
        throw ParameterError(
            fmt::format("{}: cannot write: directory {} does not exist", path, dir.string()));
    if (access(dir.c_str(), W_OK) != 0)
        throw ParameterError(
            fmt::format("{}: cannot write: directory {} is not writable", path, dir.string()));
}

void write_atomically(const std::string& path,
                      const std::function<void(const std::string& partial)>& write) {
    const std::string partial = path + ".partial";
    auto fail = [&](const std::string& what) {
        std::error_code ignored;
        fs::remove(partial, ignored);
        throw Error(fmt::format("{}: {}", path, what));
    };
    try {
        write(partial);
    } catch (const std::exception& e) {  // Error, and Iex::BaseExc from OpenEXR
        fail(e.what());
    }
    std::error_code ec;
    fs::rename(partial, path, ec);
    if (ec) fail("cannot rename into place: " + ec.message());
}

void write_text(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw Error(fmt::format("cannot write: {}", std::strerror(errno)));
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) throw Error("write failed");
}

void write_text_atomically(const std::string& path, const std::string& text) {
    write_atomically(path, [&](const std::string& partial) { write_text(partial, text); });
}

}  // namespace vlf
