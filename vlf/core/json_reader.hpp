// json_reader.hpp — the one way JSON input is read: scene files, camera paths, run
// parameters, and a bake's manifest and scene. Two pieces:
//
//   parse_json   text -> tree. A syntax error names its line and column; a duplicate key
//                or a number that overflows a double (1e999) names its JSON place.
//   JsonReader   a cursor over the tree that knows its JSON path (objects[2].vertices[1][0]):
//                typed reads (numbers in a range, integers, booleans, strings, a name from
//                a list, vec3, arrays), required and optional keys, and a refusal of every
//                key it was not told about.
//
// Every problem throws vlf::Error whose message is one line in one format:
//
//   <file>: <json.path>: <message>
//
//   scenes/x.json: objects[2].material: unknown material 'glas' (known: white, lamp)
//   out/a.vlf/manifest.json: parameters.cycles: expected an integer, got "four"
//
// The document itself is "(top level)"; a syntax error's place is "line L, column C". A
// key that is not a plain word is written in brackets: files["scene.json"].sha256.
//
// Both nlohmann::json and nlohmann::ordered_json (file order kept) are supported.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "vlf/core/math.hpp"

namespace vlf {

// The text of a JSON document, parsed. `file` names it in messages.
template <class Json = nlohmann::json>
Json parse_json(const std::string& text, const std::string& file);

// The file at `path`, read and parsed; "<path>: (file): cannot be opened" when unreadable.
template <class Json = nlohmann::json>
Json read_json_file(const std::string& path);

// The JSON path of `key` inside `parent` ("" is the document): "a.b", "a[\"x.y\"]".
std::string json_key_path(const std::string& parent, const std::string& key);
// ... and of element `index` of the array at `parent`: "a[3]".
std::string json_index_path(const std::string& parent, size_t index);

// What a value is, for "expected ..., got <this>": "four" (quoted), 2.5, true, null,
// an array of 2 elements, an object.
template <class Json>
std::string describe_json(const Json& value);

template <class Json>
class BasicJsonReader {
  public:
    // The document `root`, read from `file`.
    BasicJsonReader(const Json& root, std::string file);

    const Json& json() const { return *m_value; }
    const std::string& file() const { return m_file; }
    const std::string& path() const { return m_path; }  // "" for the document
    std::string place() const;                          // the path, or "(top level)"

    // Throws Error("<file>: <place>: <message>").
    [[noreturn]] void fail(const std::string& message) const;

    // --- objects (each of these fails unless this value is an object) ---
    void expect_object() const;
    bool has(const std::string& key) const;
    // The value of `key`; "missing required key '<key>'" (at this place) when absent.
    BasicJsonReader required(const std::string& key) const;
    std::optional<BasicJsonReader> optional(const std::string& key) const;
    // Fails at the first key not in `known`: "unknown key<context> (expected one of: ...)".
    void only_keys(const std::vector<std::string>& known, const std::string& context = "") const;
    // Every key and its value, in the tree's order.
    std::vector<std::pair<std::string, BasicJsonReader>> members() const;

    // --- arrays ---
    void expect_array() const;
    // The elements; fails unless this is an array of `min` to `max` elements.
    std::vector<BasicJsonReader> elements(size_t min = 0,
                                          size_t max = std::numeric_limits<size_t>::max()) const;
    // Element `index` of this array; "expected at least <index + 1> elements" when short.
    BasicJsonReader element(size_t index) const;

    // --- values ---
    double number() const;                      // any finite number
    double number(double lo, double hi) const;  // ... in [lo, hi]
    double positive() const;                    // ... > 0
    // An integer (2 and 2.0 both are); "expected an integer, got 2.5".
    int integer(int lo = std::numeric_limits<int>::min(),
                int hi = std::numeric_limits<int>::max()) const;
    int64_t integer64(int64_t lo = std::numeric_limits<int64_t>::min(),
                      int64_t hi = std::numeric_limits<int64_t>::max()) const;
    uint64_t unsigned64() const;
    bool boolean() const;
    std::string string() const;
    // A string that is one of `known`; returns its index. Otherwise
    // "unknown <what> '<value>' (known: a, b, c)".
    size_t one_of(const std::vector<std::string>& known, const std::string& what) const;
    Vec3 vec3() const;                    // [x, y, z], finite
    std::vector<double> numbers() const;  // an array of finite numbers

  private:
    BasicJsonReader(const Json& value, const std::string& file, std::string path)
        : m_value(&value), m_file(file), m_path(std::move(path)) {}
    [[noreturn]] void expected(const std::string& what) const;  // "expected <what>, got ..."

    const Json* m_value;
    std::string m_file;
    std::string m_path;
};

using JsonReader = BasicJsonReader<nlohmann::json>;
using OrderedJsonReader = BasicJsonReader<nlohmann::ordered_json>;

extern template class BasicJsonReader<nlohmann::json>;
extern template class BasicJsonReader<nlohmann::ordered_json>;

}  // namespace vlf
