// files.hpp — the file-system habits every output shares: an output path is checked before
// any long work, and a file is written under `<path>.partial` and renamed into place when
// complete, so nobody ever reads a half-written file that looks complete.
#pragma once

#include <functional>
#include <string>

namespace vlf {

// The extension of `path`, lower-cased, with its dot (".exr"); "" when there is none.
std::string lower_extension(const std::string& path);

// Fails when `path` is not a readable file: Error "<what> '<path>' is a directory, not a
// file" / "does not exist" / "cannot be read".
void check_input_file(const std::string& path, const std::string& what);

// Fails early (before any work) when `path` cannot be written: its directory must exist
// and be writable. Throws ParameterError naming the path.
void check_output_path(const std::string& path);

// Calls `write(partial)` with `partial = path + ".partial"`, then renames it to `path`. On
// any failure the partial file is removed and Error("<path>: <what went wrong>") thrown.
void write_atomically(const std::string& path,
                      const std::function<void(const std::string& partial)>& write);

// Writes `text` to `path` as it is (no temporary): Error("cannot write: ..." or "write
// failed"), without the path, for the caller to place.
void write_text(const std::string& path, const std::string& text);

// write_atomically() of write_text().
void write_text_atomically(const std::string& path, const std::string& text);

}  // namespace vlf
