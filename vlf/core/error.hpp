// error.hpp — the one exception family of the library, and programmer-error checks.
//
// Bad input (scene files, parameters, bundles) throws vlf::Error whose message already
// names the file and the place ("scenes/room.json: objects[3].material: unknown material
// 'glas'"); the executables catch it in one place, print the message as one line on
// stderr and exit with code 2. Programmer errors use VLF_CHECK and abort.
#pragma once

#include <stdexcept>
#include <string>

namespace vlf {

class Error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

// Scene file problems: the message starts with "<file>: <json path>: ".
class SceneError : public Error {
  public:
    using Error::Error;
};

// Command-line or propagation parameters that are out of range.
class ParameterError : public Error {
  public:
    using Error::Error;
};

[[noreturn]] void check_failed(const char* expr, const char* file, int line);

}  // namespace vlf

#define VLF_CHECK(expr) \
    ((expr) ? static_cast<void>(0) : ::vlf::check_failed(#expr, __FILE__, __LINE__))
#ifdef NDEBUG
#define VLF_DCHECK(expr) static_cast<void>(0)
#else
#define VLF_DCHECK(expr) VLF_CHECK(expr)
#endif
