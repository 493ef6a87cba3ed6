// The one JSON reader (core/json.hpp) and what the loader refuses of what it keeps.
#include "core/json.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "core/asset.hpp"
#include "core/error.hpp"
#include "rules/rule_set.hpp"
#include "test_support.hpp"
#include "validators/validate.hpp"

namespace gltf_pbr {
namespace {

std::optional<JsonProblem> read(const std::string& text, JsonDocument& out, JsonFlawsSeen* seen = nullptr) {
  return read_json({reinterpret_cast<const std::uint8_t*>(text.data()), text.size()}, out, seen);
}

// RFC 8259 section 4 leaves repeated names to the reader; this one keeps the first position and
// the last value, for small objects (a linear search) and large ones (an index) alike.
TEST(JsonReader, ARepeatedKeyKeepsItsFirstPlaceAndItsLastValueInObjectsOfAnySize) {
  for (int keys : {3, 16, 17, 1000}) {
    std::string text = "{";
    for (int k = 0; k < keys; ++k) text += "\"k" + std::to_string(k) + "\":" + std::to_string(k) + ",";
    text += "\"k1\":\"last\",\"k0\":null}";
    JsonDocument document;
    ASSERT_FALSE(read(text, document)) << keys;
    ASSERT_EQ(document.size(), static_cast<std::size_t>(keys)) << keys;
    auto member = document.items().begin();
    EXPECT_EQ(member.key(), "k0");
    EXPECT_TRUE(member.value().is_null());
    ++member;
    EXPECT_EQ(member.key(), "k1");
    EXPECT_EQ(member.value(), "last");
    EXPECT_EQ(document["k" + std::to_string(keys - 1)], keys - 1);
  }
}

TEST(JsonReader, ProblemsNameTheirKindAndByte) {
  JsonDocument document;
  const auto bad_byte = read("{\"a\": \"\xC3\x28\"}", document);
  ASSERT_TRUE(bad_byte);
  EXPECT_EQ(bad_byte->kind, JsonProblem::Kind::InvalidUtf8);
  EXPECT_EQ(bad_byte->offset, 7u);
  const auto character = read("{\"a\": ]}", document);
  ASSERT_TRUE(character);
  EXPECT_EQ(character->kind, JsonProblem::Kind::UnexpectedCharacter);
  EXPECT_EQ(character->offset, 6u);
  const auto end = read("{\"a\": [1, 2", document);
  ASSERT_TRUE(end);
  EXPECT_EQ(end->kind, JsonProblem::Kind::UnexpectedEnd);
  const auto deep = read(std::string(kMaxJsonDepth + 2, '[') + std::string(kMaxJsonDepth + 2, ']'), document);
  ASSERT_TRUE(deep);
  EXPECT_EQ(deep->kind, JsonProblem::Kind::TooDeep);
}

// What the reader keeps, as the reference's does, but the document library cannot hold: found in
// document order with its pointer.
TEST(JsonReader, InfinitiesAndLoneSurrogatesAreFlawsWithTheirPointer) {
  JsonDocument document;
  ASSERT_FALSE(read(R"({"a": [1, {"b~/": 1e999}], "c": "\uD800"})", document));
  const auto flaw = first_flaw(document);
  ASSERT_TRUE(flaw);
  EXPECT_EQ(flaw->kind, JsonFlaw::Kind::NonFiniteNumber);
  EXPECT_EQ(flaw->pointer, "/a/1/b~0~1");
  document.erase("a");
  const auto surrogate = first_flaw(document);
  ASSERT_TRUE(surrogate);
  EXPECT_EQ(surrogate->kind, JsonFlaw::Kind::NotUnicode);
  EXPECT_EQ(surrogate->pointer, "/c");
  ASSERT_FALSE(read(R"({"a": "\uD83D\uDE00 and \u00e9"})", document));  // a pair and a BMP letter are text
  EXPECT_FALSE(first_flaw(document));
}

// The reader notes what first_flaw would find, so a clean document is never walked for it.
TEST(JsonReader, TheReaderNotesEveryFlawItKeeps) {
  JsonDocument document;
  for (const char* text : {R"(["\uD800"])", R"(["\uDC00"])", R"(["\uD800\u0041"])", R"({"\uDBFF": 1})"}) {
    JsonFlawsSeen seen;
    ASSERT_FALSE(read(text, document, &seen)) << text;
    EXPECT_TRUE(seen.lone_surrogate) << text;
    EXPECT_TRUE(seen.any()) << text;
    EXPECT_TRUE(first_flaw(document)) << text;
  }
  JsonFlawsSeen numbers;
  ASSERT_FALSE(read(R"([1.5, -2e400, 1e999, 1e308])", document, &numbers));
  EXPECT_EQ(numbers.first_non_finite, "-2e400");  // the first, as written
  EXPECT_FALSE(numbers.lone_surrogate);
  JsonFlawsSeen clean;
  ASSERT_FALSE(read(R"({"a": ["\uD83D\uDE00", 1e308, -0.0, 18446744073709551615, "\u00e9"]})", document, &clean));
  EXPECT_FALSE(clean.any());
  EXPECT_FALSE(first_flaw(document));
}

// tinygltf would refuse the file without a pointer, or the loader's rewrite for it would throw.
TEST(JsonReader, TheLoaderRefusesALoneSurrogateNamingItsPointer) {
  test::ScratchDir scratch;
  const fs::path box = test::assets_dir() / "Box" / "specgloss";
  fs::copy_file(box / "Box0.bin", scratch / "Box0.bin");
  const fs::path gltf = scratch / "Box.gltf";
  std::string text = test::read_text(box / "Box.gltf");
  const std::size_t materials = text.find("\"materials\"");
  ASSERT_NE(materials, std::string::npos);
  const std::size_t open = text.find('{', materials);
  text.insert(open + 1, R"("extras": {"note": "red \uDC00"},)");
  test::write_text(gltf, text);
  try {
    (void)load_asset(gltf, {});
    FAIL() << "a lone surrogate loaded";
  } catch (const InputError& error) {
    EXPECT_EQ(error.pointer, "/materials/0/extras/note");
    EXPECT_NE(error.reason.find("lone surrogate"), std::string::npos) << error.reason;
  }
  // validate reads the JSON once, in the structure step, and its loader still refuses the flaw
  // that the structure step's reader noted.
  const long reads_before = work_counters().json_texts_read;
  const Report report = validate_file(gltf, "Box.gltf", builtin_rules(), {}, ValidateOptions{});
  EXPECT_EQ(work_counters().json_texts_read - reads_before, 1);
  const auto refusal = std::find_if(report.messages.begin(), report.messages.end(), [](const Issue& issue) {
    return issue.message.find("lone surrogate") != std::string::npos;
  });
  ASSERT_NE(refusal, report.messages.end());
  EXPECT_EQ(refusal->pointer, "/materials/0/extras/note");
}

}  // namespace
}  // namespace gltf_pbr
