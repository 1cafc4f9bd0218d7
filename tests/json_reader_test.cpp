// json_reader_test.cpp — the one JSON reading layer (vlf/core/json_reader.hpp): parsing with
// places, the reader's typed getters, required/optional/unknown keys, and the one message
// format "<file>: <json.path>: <message>".
#include "vlf/core/json_reader.hpp"

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "vlf/core/error.hpp"

namespace vlf {
namespace {

// `read` must throw an Error whose message is exactly `expected`, on one line.
void expect_message(const std::function<void()>& read, const std::string& expected) {
    try {
        read();
        ADD_FAILURE() << "no error, expected: " << expected;
    } catch (const Error& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg, expected);
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
}

nlohmann::json doc(const char* text) {
    return parse_json(text, "f.json");
}

// ---- parsing --------------------------------------------------------------------------

TEST(JsonParse, SyntaxErrorNamesLineAndColumn) {
    expect_message([] { parse_json("{\n  \"a\": [1, 2,\n}", "f.json"); },
                   "f.json: line 3, column 1: malformed JSON: syntax error while parsing value - "
                   "unexpected '}'; expected '[', '{', or a literal");
    expect_message([] { parse_json("", "f.json"); },
                   "f.json: line 1, column 1: malformed JSON: syntax error while parsing value - "
                   "unexpected end of input; expected '[', '{', or a literal");
}

TEST(JsonParse, DuplicateKeyAndOverflowNameTheirPlace) {
    expect_message([] { parse_json(R"({"a": {"b": 1, "b": 2}})", "f.json"); },
                   "f.json: a.b: duplicate key");
    expect_message([] { parse_json(R"({"a": [[1, 2], [3, 1e999]]})", "f.json"); },
                   "f.json: a[1][1]: number is not finite (it overflows a double)");
    expect_message([] { parse_json("1e999", "f.json"); },
                   "f.json: (top level): number is not finite (it overflows a double)");
}

TEST(JsonParse, OrderedKeepsFileOrder) {
    const auto j = parse_json<nlohmann::ordered_json>(R"({"z": 1, "a": 2, "m": 3})", "f.json");
    const OrderedJsonReader r(j, "f.json");
    std::string keys;
    for (const auto& [k, v] : r.members()) keys += k;
    EXPECT_EQ(keys, "zam");
}

TEST(JsonParse, MissingFile) {
    expect_message([] { read_json_file("/nonexistent/dir/x.json"); },
                   "/nonexistent/dir/x.json: (file): does not exist");
}

// ---- paths ----------------------------------------------------------------------------

TEST(JsonReader, PathsThroughNestedObjectsAndArrays) {
    const auto j = doc(R"({"objects": [{"vertices": [[0,0,0],[1,0,0],[1,"x",0]]}]})");
    const JsonReader r(j, "f.json");
    EXPECT_EQ(r.place(), "(top level)");
    const JsonReader v = r.required("objects").element(0).required("vertices");
    EXPECT_EQ(v.path(), "objects[0].vertices");
    EXPECT_EQ(v.elements()[2].path(), "objects[0].vertices[2]");
    EXPECT_EQ(v.element(1).vec3(), Vec3(1, 0, 0));
    expect_message([&] { v.element(2).vec3(); },
                   "f.json: objects[0].vertices[2][1]: expected a number, got \"x\"");
    expect_message([&] { v.element(3); },
                   "f.json: objects[0].vertices: expected at least 4 elements, got an array of 3 "
                   "elements");
}

TEST(JsonReader, KeysThatAreNotPlainWordsAreBracketed) {
    const auto j = doc(R"({"files": {"scene.json": {"bytes": "x"}, "a b": 1, "plain_key-2": 2}})");
    const JsonReader files = JsonReader(j, "f.json").required("files");
    expect_message([&] { files.required("scene.json").required("bytes").unsigned64(); },
                   "f.json: files[\"scene.json\"].bytes: expected an unsigned integer, got \"x\"");
    EXPECT_EQ(files.required("a b").path(), "files[\"a b\"]");
    EXPECT_EQ(files.required("plain_key-2").path(), "files.plain_key-2");
    EXPECT_EQ(json_key_path("", "x.y"), "[\"x.y\"]");
    EXPECT_EQ(json_index_path("a", 7), "a[7]");
}

// ---- keys -----------------------------------------------------------------------------

TEST(JsonReader, UnknownKeyIsRefusedNamingTheKnownOnes) {
    const auto j = doc(R"({"settings": {"texel_size": 1, "colour": 2}})");
    const JsonReader r(j, "f.json");
    r.only_keys({"settings"});
    expect_message(
        [&] {
            r.required("settings").only_keys({"texel_size", "units"});
        },
        "f.json: settings.colour: unknown key (expected one of: texel_size, units)");
    expect_message([&] { r.required("settings").only_keys({"texel_size"}, " for a box"); },
                   "f.json: settings.colour: unknown key for a box (expected one of: texel_size)");
}

TEST(JsonReader, RequiredAndOptionalKeys) {
    const auto j = doc(R"({"a": {"b": 1}})");
    const JsonReader r(j, "f.json");
    EXPECT_TRUE(r.has("a"));
    EXPECT_FALSE(r.optional("b").has_value());
    ASSERT_TRUE(r.required("a").optional("b").has_value());
    EXPECT_EQ(r.required("a").optional("b")->integer(), 1);
    expect_message([&] { r.required("objects"); },
                   "f.json: (top level): missing required key 'objects'");
    expect_message([&] { r.required("a").required("c"); }, "f.json: a: missing required key 'c'");
    expect_message([&] { r.required("a").required("b").required("c"); },
                   "f.json: a.b: expected an object, got 1");
}

// ---- types ----------------------------------------------------------------------------

TEST(JsonReader, WrongTypesSayWhatWasExpectedAndFound) {
    const auto j = doc(R"({"n": "four", "i": 2.5, "b": 1, "s": [1, 2], "o": [],
                           "v": [1, 2], "long": "abcdefghijklmnopqrstuvwxyzabcdefghijklmnopqrstuvwxyz"})");
    const JsonReader r(j, "f.json");
    expect_message([&] { r.required("n").number(); }, "f.json: n: expected a number, got \"four\"");
    expect_message([&] { r.required("n").integer(); },
                   "f.json: n: expected an integer, got \"four\"");
    expect_message([&] { r.required("i").integer(); }, "f.json: i: expected an integer, got 2.5");
    expect_message([&] { r.required("b").boolean(); }, "f.json: b: expected true or false, got 1");
    expect_message([&] { r.required("s").string(); },
                   "f.json: s: expected a string, got an array of 2 elements");
    expect_message([&] { r.required("o").expect_object(); },
                   "f.json: o: expected an object, got an empty array");
    expect_message([&] { r.required("b").elements(); }, "f.json: b: expected an array, got 1");
    expect_message([&] { r.required("v").vec3(); },
                   "f.json: v: expected an array of 3 numbers, got an array of 2 elements");
    expect_message(
        [&] { r.required("long").number(); },
        "f.json: long: expected a number, got \"abcdefghijklmnopqrstuvwxyzabcdefghijklmn\"...");
}

TEST(JsonReader, OutOfRange) {
    const auto j = doc(R"({"n": 7, "x": -0.5, "big": 3000000000, "neg": -3, "f": 4.0})");
    const JsonReader r(j, "f.json");
    expect_message([&] { r.required("n").integer(0, 6); }, "f.json: n: must be in [0, 6] (got 7)");
    expect_message([&] { r.required("x").number(0, 1); },
                   "f.json: x: must be in [0, 1] (got -0.5)");
    expect_message([&] { r.required("x").positive(); }, "f.json: x: must be > 0 (got -0.5)");
    expect_message([&] { r.required("big").integer(); },
                   "f.json: big: must be in [-2147483648, 2147483647] (got 3000000000)");
    expect_message([&] { r.required("neg").unsigned64(); }, "f.json: neg: must be >= 0 (got -3)");
    EXPECT_EQ(r.required("big").integer64(), 3000000000);
    EXPECT_EQ(r.required("f").integer(0, 6), 4);  // an integral number is an integer
    EXPECT_DOUBLE_EQ(r.required("x").number(-1, 0), -0.5);
}

TEST(JsonReader, LargeUnsignedAndNonFinite) {
    const auto j = doc(R"({"seed": 18446744073709551615})");
    EXPECT_EQ(JsonReader(j, "f.json").required("seed").unsigned64(), 18446744073709551615ull);
    nlohmann::json built = {{"a", {1.0, std::numeric_limits<double>::quiet_NaN()}}};
    expect_message([&] { JsonReader(built, "mem").required("a").numbers(); },
                   "mem: a[1]: number is not finite");
}

TEST(JsonReader, OneOfAList) {
    const auto j = doc(R"({"material": "glas", "scheme": "octahedral"})");
    const JsonReader r(j, "scenes/x.json");
    EXPECT_EQ(r.required("scheme").one_of({"octahedral", "equal-area"}, "scheme"), 0u);
    expect_message(
        [&] {
            r.required("material").one_of({"white", "glass"}, "material");
        },
        "scenes/x.json: material: unknown material 'glas' (known: white, glass)");
}

TEST(JsonReader, ArraysOfCountAndNumbers) {
    const auto j = doc(R"({"a": [1, 2.5, -3], "e": []})");
    const JsonReader r(j, "f.json");
    EXPECT_EQ(r.required("a").numbers(), (std::vector<double>{1, 2.5, -3}));
    EXPECT_EQ(r.required("a").elements(3, 3).size(), 3u);
    expect_message([&] { r.required("e").elements(1); },
                   "f.json: e: expected at least 1 element, got an empty array");
    expect_message([&] { r.required("a").elements(0, 2); },
                   "f.json: a: expected at most 2 elements, got an array of 3 elements");
}

}  // namespace
}  // namespace vlf
