// json_reader.cpp — JSON text to a tree (a SAX handler that always knows the JSON place of
// the value being read) and the path-aware reader over the tree (json_reader.hpp).
#include "vlf/core/json_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "vlf/core/error.hpp"

namespace vlf {

namespace {

constexpr const char* kTopLevel = "(top level)";
constexpr size_t kMaxQuoted = 40;  // characters of a string value quoted in a message

[[noreturn]] void fail_at(const std::string& file, const std::string& place,
                          const std::string& message) {
    throw Error(fmt::format("{}: {}: {}", file, place.empty() ? kTopLevel : place, message));
}

bool plain_key(const std::string& key) {
    return !key.empty() && std::all_of(key.begin(), key.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
    });
}

std::string join_names(const std::vector<std::string>& names) {
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    return list;
}

// A SAX handler that builds the tree itself, so that it knows the JSON place of every
// value: nlohmann's DOM parser reports a number overflow (1e999) without one, and keeps
// the last of two equal keys silently.
template <class Json>
class TreeBuilder {
  public:
    using number_integer_t = typename Json::number_integer_t;
    using number_unsigned_t = typename Json::number_unsigned_t;
    using number_float_t = typename Json::number_float_t;
    using string_t = typename Json::string_t;
    using binary_t = typename Json::binary_t;

    TreeBuilder(const std::string& file, const std::string& text) : m_file(file), m_text(text) {}

    Json& root() { return m_root; }

    bool null() { return add(Json(nullptr)); }
    bool boolean(bool v) { return add(Json(v)); }
    bool number_integer(number_integer_t v) { return add(Json(v)); }
    bool number_unsigned(number_unsigned_t v) { return add(Json(v)); }
    bool number_float(number_float_t v, const string_t& s) {
        if (!std::isfinite(v))
            fail_at(m_file, next_place(), fmt::format("number '{}' is not finite", s));
        return add(Json(v));
    }
    bool string(string_t& v) { return add(Json(v)); }
    bool binary(binary_t&) { return add(Json(nullptr)); }  // not produced by the JSON reader
    bool start_object(std::size_t) {
        m_stack.push_back({add_container(Json::object()), false, {}, -1, {}});
        return true;
    }
    bool key(string_t& k) {
        Frame& f = m_stack.back();
        if (!f.keys.insert(k).second)
            fail_at(m_file, json_key_path(place_of_stack(), k), "duplicate key");
        f.key = k;
        return true;
    }
    bool end_object() {
        m_stack.pop_back();
        return true;
    }
    bool start_array(std::size_t) {
        m_stack.push_back({add_container(Json::array()), true, {}, -1, {}});
        return true;
    }
    bool end_array() {
        m_stack.pop_back();
        return true;
    }
    bool parse_error(std::size_t position, const std::string& /*last_token*/,
                     const nlohmann::detail::exception& ex) {
        if (ex.id == 406)  // out_of_range: number overflow, e.g. 1e999
            fail_at(m_file, next_place(), "number is not finite (it overflows a double)");
        // Line and column of the offending character, from nlohmann's byte count.
        const std::size_t at = position == 0 ? 0 : std::min(position - 1, m_text.size());
        std::size_t line = 1, line_start = 0;
        for (std::size_t i = 0; i < at; ++i)
            if (m_text[i] == '\n') ++line, line_start = i + 1;
        const std::size_t column = at - line_start + 1;
        std::string what = ex.what();
        // "[json.exception.parse_error.101] parse error at line 3, column 5: syntax error ..."
        if (auto p = what.find("parse error"); p != std::string::npos)
            if (auto q = what.find(": ", p); q != std::string::npos) what = what.substr(q + 2);
        fail_at(m_file, fmt::format("line {}, column {}", line, column), "malformed JSON: " + what);
    }

  private:
    struct Frame {
        Json* value;
        bool is_array;
        std::string key;
        long index;
        std::set<std::string> keys;
    };

    // Place of the container on top of the stack.
    std::string place_of_stack() const {
        std::string p;
        for (size_t i = 0; i + 1 < m_stack.size(); ++i) {
            const Frame& f = m_stack[i];
            p = f.is_array ? json_index_path(p, size_t(f.index)) : json_key_path(p, f.key);
        }
        return p;
    }
    // Place of the value about to be added to the top container.
    std::string next_place() const {
        if (m_stack.empty()) return kTopLevel;
        const Frame& f = m_stack.back();
        const std::string parent = place_of_stack();
        return f.is_array ? json_index_path(parent, size_t(f.index + 1))
                          : json_key_path(parent, f.key);
    }
    bool add(Json v) {
        if (m_stack.empty()) {
            m_root = std::move(v);
        } else if (Frame& f = m_stack.back(); f.is_array) {
            ++f.index;
            f.value->push_back(std::move(v));
        } else {
            (*f.value)[f.key] = std::move(v);
        }
        return true;
    }
    Json* add_container(Json v) {
        if (m_stack.empty()) {
            m_root = std::move(v);
            return &m_root;
        }
        Frame& f = m_stack.back();
        if (f.is_array) {
            ++f.index;
            f.value->push_back(std::move(v));
            return &f.value->back();
        }
        (*f.value)[f.key] = std::move(v);
        return &(*f.value)[f.key];
    }

    const std::string& m_file;
    const std::string& m_text;
    Json m_root;
    // Pointers into the tree stay valid: only the innermost open container ever grows.
    std::vector<Frame> m_stack;
};

}  // namespace

// ---------------------------------------------------------------------------------------
// Parsing

template <class Json>
Json parse_json(const std::string& text, const std::string& file) {
    TreeBuilder<Json> builder(file, text);
    if (!Json::sax_parse(text, &builder)) fail_at(file, kTopLevel, "malformed JSON");
    return std::move(builder.root());
}

template <class Json>
Json read_json_file(const std::string& path) {
    std::error_code ec;
    if (std::filesystem::is_directory(path, ec))
        fail_at(path, "(file)", "is a directory, not a file");
    if (!std::filesystem::exists(path, ec)) fail_at(path, "(file)", "does not exist");
    std::ifstream in(path, std::ios::binary);
    if (!in) fail_at(path, "(file)", "cannot be opened");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad() || text.bad()) fail_at(path, "(file)", "cannot be read");
    return parse_json<Json>(text.str(), path);
}

std::string json_key_path(const std::string& parent, const std::string& key) {
    if (plain_key(key)) return parent.empty() ? key : parent + "." + key;
    return parent + "[" + nlohmann::json(key).dump() + "]";
}

std::string json_index_path(const std::string& parent, size_t index) {
    return fmt::format("{}[{}]", parent, index);
}

template <class Json>
std::string describe_json(const Json& value) {
    if (value.is_string()) {
        std::string s = value.template get<std::string>();
        const bool cut = s.size() > kMaxQuoted;
        if (cut) s.resize(kMaxQuoted);
        return Json(s).dump(-1, ' ', false, Json::error_handler_t::replace) + (cut ? "..." : "");
    }
    if (value.is_array()) {
        if (value.empty()) return "an empty array";
        return fmt::format("an array of {} element{}", value.size(), value.size() == 1 ? "" : "s");
    }
    if (value.is_object()) return "an object";
    return value.dump();  // number, true, false, null
}

// ---------------------------------------------------------------------------------------
// The reader

template <class Json>
BasicJsonReader<Json>::BasicJsonReader(const Json& root, std::string file)
    : m_value(&root), m_file(std::move(file)) {}

template <class Json>
std::string BasicJsonReader<Json>::place() const {
    return m_path.empty() ? kTopLevel : m_path;
}

template <class Json>
void BasicJsonReader<Json>::fail(const std::string& message) const {
    fail_at(m_file, m_path, message);
}

template <class Json>
void BasicJsonReader<Json>::expected(const std::string& what) const {
    fail(fmt::format("expected {}, got {}", what, describe_json(*m_value)));
}

template <class Json>
void BasicJsonReader<Json>::expect_object() const {
    if (!m_value->is_object()) expected("an object");
}

template <class Json>
bool BasicJsonReader<Json>::has(const std::string& key) const {
    expect_object();
    return m_value->contains(key);
}

template <class Json>
BasicJsonReader<Json> BasicJsonReader<Json>::required(const std::string& key) const {
    expect_object();
    auto it = m_value->find(key);
    if (it == m_value->end()) fail(fmt::format("missing required key '{}'", key));
    return BasicJsonReader(*it, m_file, json_key_path(m_path, key));
}

template <class Json>
std::optional<BasicJsonReader<Json>> BasicJsonReader<Json>::optional(const std::string& key) const {
    expect_object();
    auto it = m_value->find(key);
    if (it == m_value->end()) return std::nullopt;
    return BasicJsonReader(*it, m_file, json_key_path(m_path, key));
}

template <class Json>
void BasicJsonReader<Json>::only_keys(const std::vector<std::string>& known,
                                      const std::string& context) const {
    expect_object();
    for (const auto& item : m_value->items())
        if (std::find(known.begin(), known.end(), item.key()) == known.end())
            fail_at(m_file, json_key_path(m_path, item.key()),
                    fmt::format("unknown key{} (expected one of: {})", context, join_names(known)));
}

template <class Json>
std::vector<std::pair<std::string, BasicJsonReader<Json>>> BasicJsonReader<Json>::members() const {
    expect_object();
    std::vector<std::pair<std::string, BasicJsonReader>> out;
    out.reserve(m_value->size());
    for (const auto& item : m_value->items())
        out.emplace_back(item.key(),
                         BasicJsonReader(item.value(), m_file, json_key_path(m_path, item.key())));
    return out;
}

template <class Json>
void BasicJsonReader<Json>::expect_array() const {
    if (!m_value->is_array()) expected("an array");
}

template <class Json>
std::vector<BasicJsonReader<Json>> BasicJsonReader<Json>::elements(size_t min, size_t max) const {
    expect_array();
    const size_t n = m_value->size();
    if (n < min)
        fail(fmt::format("expected at least {} element{}, got {}", min, min == 1 ? "" : "s",
                         describe_json(*m_value)));
    if (n > max)
        fail(fmt::format("expected at most {} element{}, got {}", max, max == 1 ? "" : "s",
                         describe_json(*m_value)));
    std::vector<BasicJsonReader> out;
    out.reserve(n);
    for (size_t i = 0; i < n; ++i)
        out.push_back(BasicJsonReader((*m_value)[i], m_file, json_index_path(m_path, i)));
    return out;
}

template <class Json>
BasicJsonReader<Json> BasicJsonReader<Json>::element(size_t index) const {
    expect_array();
    if (index >= m_value->size())
        fail(fmt::format("expected at least {} element{}, got {}", index + 1, index == 0 ? "" : "s",
                         describe_json(*m_value)));
    return BasicJsonReader((*m_value)[index], m_file, json_index_path(m_path, index));
}

template <class Json>
double BasicJsonReader<Json>::number() const {
    if (!m_value->is_number()) expected("a number");
    const double v = m_value->template get<double>();
    if (!std::isfinite(v)) fail("number is not finite");
    return v;
}

template <class Json>
double BasicJsonReader<Json>::number(double lo, double hi) const {
    const double v = number();
    if (!(v >= lo && v <= hi)) fail(fmt::format("must be in [{}, {}] (got {})", lo, hi, v));
    return v;
}

template <class Json>
double BasicJsonReader<Json>::positive() const {
    const double v = number();
    if (!(v > 0)) fail(fmt::format("must be > 0 (got {})", v));
    return v;
}

template <class Json>
int64_t BasicJsonReader<Json>::integer64(int64_t lo, int64_t hi) const {
    const Json& j = *m_value;
    auto range = [&](const std::string& got) {
        fail(fmt::format("must be in [{}, {}] (got {})", lo, hi, got));
    };
    int64_t v = 0;
    if (j.is_number_unsigned()) {
        const uint64_t u = j.template get<uint64_t>();
        if (u > uint64_t(std::numeric_limits<int64_t>::max())) range(j.dump());
        v = int64_t(u);
    } else if (j.is_number_integer()) {
        v = j.template get<int64_t>();
    } else if (j.is_number_float()) {
        const double d = number();
        if (d != std::floor(d)) expected("an integer");
        if (!(d >= -0x1p63 && d < 0x1p63)) range(j.dump());
        v = int64_t(d);
    } else {
        expected("an integer");
    }
    if (v < lo || v > hi) range(std::to_string(v));
    return v;
}

template <class Json>
int BasicJsonReader<Json>::integer(int lo, int hi) const {
    return static_cast<int>(integer64(lo, hi));
}

template <class Json>
uint64_t BasicJsonReader<Json>::unsigned64() const {
    const Json& j = *m_value;
    if (j.is_number_unsigned()) return j.template get<uint64_t>();
    if (j.is_number_integer()) fail(fmt::format("must be >= 0 (got {})", j.dump()));
    if (!j.is_number_float()) expected("an unsigned integer");
    const double d = number();
    if (d != std::floor(d)) expected("an unsigned integer");
    if (!(d >= 0 && d < 0x1p64))
        fail(fmt::format("must be in [0, {}] (got {})", std::numeric_limits<uint64_t>::max(),
                         j.dump()));
    return uint64_t(d);
}

template <class Json>
bool BasicJsonReader<Json>::boolean() const {
    if (!m_value->is_boolean()) expected("true or false");
    return m_value->template get<bool>();
}

template <class Json>
std::string BasicJsonReader<Json>::string() const {
    if (!m_value->is_string()) expected("a string");
    return m_value->template get<std::string>();
}

template <class Json>
size_t BasicJsonReader<Json>::one_of(const std::vector<std::string>& known,
                                     const std::string& what) const {
    const std::string s = string();
    const auto it = std::find(known.begin(), known.end(), s);
    if (it == known.end())
        fail(fmt::format("unknown {} '{}' (known: {})", what, s, join_names(known)));
    return size_t(it - known.begin());
}

template <class Json>
Vec3 BasicJsonReader<Json>::vec3() const {
    const Json& j = *m_value;
    if (!j.is_array() || j.size() != 3) expected("an array of 3 numbers");
    Vec3 v;
    for (int i = 0; i < 3; ++i)
        v[i] = BasicJsonReader(j[size_t(i)], m_file, json_index_path(m_path, size_t(i))).number();
    return v;
}

template <class Json>
std::vector<double> BasicJsonReader<Json>::numbers() const {
    expect_array();
    const Json& j = *m_value;
    std::vector<double> out(j.size());
    for (size_t i = 0; i < out.size(); ++i) {
        const Json& e = j[i];
        if (e.is_number()) out[i] = e.template get<double>();
        if (!e.is_number() || !std::isfinite(out[i]))  // the path is only made for a message
            out[i] = BasicJsonReader(e, m_file, json_index_path(m_path, i)).number();
    }
    return out;
}

template nlohmann::json parse_json<nlohmann::json>(const std::string&, const std::string&);
template nlohmann::ordered_json parse_json<nlohmann::ordered_json>(const std::string&,
                                                                   const std::string&);
template nlohmann::json read_json_file<nlohmann::json>(const std::string&);
template nlohmann::ordered_json read_json_file<nlohmann::ordered_json>(const std::string&);
template std::string describe_json<nlohmann::json>(const nlohmann::json&);
template std::string describe_json<nlohmann::ordered_json>(const nlohmann::ordered_json&);
template class BasicJsonReader<nlohmann::json>;
template class BasicJsonReader<nlohmann::ordered_json>;

}  // namespace vlf
