// Bad input: every case gives an InputError (file, JSON pointer, reason) from load_asset or
// convert, never a crash; through the CLI a non-zero exit, the reason on stderr and no output
// file left behind (DESIGN.md, "Errors").
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <cstring>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>

#include "converter/convert.hpp"
#include "core/error.hpp"
#include "rules/rule_set.hpp"
#include "test_support.hpp"
#include "validators/validate.hpp"

namespace gltf_pbr {
namespace {

using test::assets_dir;
using test::CliResult;
using test::files_under;
using test::quoted;
using test::read_text;
using test::run_cli;
using test::ScratchDir;
using test::write_text;

using test::copy_model;
using test::kSpecGloss;
using test::model_folder;
using test::write_bytes;

const std::string kExtensionPointer = std::string("/materials/0/extensions/") + kSpecGloss;

nlohmann::json read_json(const fs::path& path) { return nlohmann::json::parse(read_text(path)); }
void write_json(const fs::path& path, const nlohmann::json& document) { write_text(path, document.dump(1)); }

// Runs `action`, which must throw InputError; returns it for further checks.
InputError input_error(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& e) {
    return e;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got another exception: " << e.what();
    return InputError("", "", "");
  }
  ADD_FAILURE() << "expected InputError, nothing was thrown";
  return InputError("", "", "");
}

// The error load_asset gives for `path`, checked to name the file.
InputError load_error(const fs::path& path, const LoadOptions& options = {}) {
  InputError e = input_error([&] { load_asset(path, options); });
  EXPECT_EQ(e.file, path.string());
  return e;
}

// Loading `path` must fail naming `pointer`, with `words` in its reason.
void expect_load_refused(const fs::path& path, const std::string& pointer, const std::string& words,
                         const LoadOptions& options = {}) {
  SCOPED_TRACE(path.string() + " " + pointer);  // the helper's failures name the case they check
  const InputError e = load_error(path, options);
  EXPECT_EQ(e.pointer, pointer);
  EXPECT_NE(e.reason.find(words), std::string::npos) << e.reason;
}

// The error convert gives after a successful load.
InputError convert_error(const fs::path& path) {
  Asset asset = load_asset(path);
  InputError e = input_error([&] { convert(asset); });
  EXPECT_EQ(e.file, path.string());
  return e;
}

std::vector<fs::path> temporaries_under(const fs::path& folder) {
  std::vector<fs::path> found;
  if (!fs::exists(folder)) return found;
  for (const fs::path& file : files_under(folder))
    if (file.filename().string().find(".tmp-") != std::string::npos) found.push_back(file);
  return found;
}

// The CLI refuses `input`: exit 1 (some files failed), the file and `expected` on stderr, and
// nothing at all in the output folder, nor a temporary beside the input.
void expect_cli_refuses(const fs::path& input, const std::string& expected, const ScratchDir& scratch) {
  SCOPED_TRACE(input.string());
  const fs::path out = scratch / "cli-out";
  fs::remove_all(out);
  fs::create_directories(out);
  const CliResult r = run_cli("convert -q " + quoted(input) + " -o " + quoted(out / input.filename()), scratch);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find(input.string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
  EXPECT_TRUE(files_under(out).empty());
  EXPECT_TRUE(temporaries_under(input.parent_path()).empty());
  fs::remove_all(out);
}

// Box with its buffer (or Duck with its image) pointing at `uri`.
fs::path box_with_buffer_uri(const fs::path& folder, const std::string& uri) {
  copy_model("Box", folder, "Box0.bin");
  nlohmann::json document = read_json(folder / "Box.gltf");
  document["buffers"][0]["uri"] = uri;
  write_json(folder / "Box.gltf", document);
  return folder / "Box.gltf";
}

// Box with the first number after "key": (an array's first element) written as `literal`: number
// text that no JSON library writes, such as 1e999.
fs::path box_with_number_text(const fs::path& folder, const std::string& key, const std::string& literal) {
  copy_model("Box", folder);
  const fs::path gltf = folder / "Box.gltf";
  std::string text = read_text(gltf);
  const std::size_t first = text.find_first_of("-0123456789", text.find("\"" + key + "\": "));
  text.replace(first, text.find_first_of(",]}\n", first) - first, literal);  // out_of_range: no such key
  write_text(gltf, text);
  return gltf;
}

fs::path duck_with_image_uri(const fs::path& folder, const std::string& uri) {
  copy_model("Duck", folder, "DuckCM.png");
  nlohmann::json document = read_json(folder / "Duck.gltf");
  document["images"][0]["uri"] = uri;
  write_json(folder / "Duck.gltf", document);
  return folder / "Duck.gltf";
}

int spec_gloss_materials(const Asset& asset) {
  int n = 0;
  for (const auto& material : asset.model.materials) n += material.extensions.count(kSpecGloss) ? 1 : 0;
  return n;
}

// ---------------------------------------------------------------------------------------------
// Containers and JSON
// ---------------------------------------------------------------------------------------------

TEST(BadInput, TruncatedGlbNamesTheByteOffsetAndWritesNothing) {
  ScratchDir scratch;
  const auto whole = read_file(model_folder("CesiumMilkTruck", "specgloss-glb-generated") / "CesiumMilkTruck.glb");
  ASSERT_TRUE(whole);
  const fs::path half = scratch / "truck-half.glb";
  write_bytes(half, std::span(*whole).first(whole->size() / 2));

  const InputError e = load_error(half);
  EXPECT_EQ(e.offset, 8u);  // the header's length field, which claims the whole file
  EXPECT_NE(e.reason.find("truncated"), std::string::npos) << e.reason;
  EXPECT_NE(e.reason.find(std::to_string(whole->size())), std::string::npos) << e.reason;
  expect_cli_refuses(half, "truncated GLB", scratch);
}

TEST(BadInput, TenByteGlbStubIsRefusedAsATruncatedHeader) {
  ScratchDir scratch;
  const fs::path stub = scratch / "stub.glb";
  const std::uint8_t bytes[10] = {'g', 'l', 'T', 'F', 2, 0, 0, 0, 10, 0};
  write_bytes(stub, bytes);

  const InputError e = load_error(stub);
  EXPECT_EQ(e.offset, 0u);
  EXPECT_NE(e.reason.find("truncated"), std::string::npos) << e.reason;
  EXPECT_NE(e.reason.find("10 bytes"), std::string::npos) << e.reason;
  expect_cli_refuses(stub, "truncated GLB", scratch);
}

TEST(BadInput, GlbWhoseBinChunkRunsPastTheEndNamesTheChunkOffset) {
  ScratchDir scratch;
  const std::string json = R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":64}]})";
  Bytes glb = glb_bytes(json, Bytes(64, 7));
  glb.resize(glb.size() - 16);
  const std::uint32_t length = static_cast<std::uint32_t>(glb.size());  // a header that agrees with the cut
  std::memcpy(glb.data() + 8, &length, 4);
  const fs::path file = scratch / "short-bin.glb";
  write_bytes(file, glb);

  const size_t padded_json = (json.size() + 3) & ~size_t{3};
  const InputError e = load_error(file);
  EXPECT_EQ(e.offset, 20u + padded_json);
  EXPECT_NE(e.reason.find("BIN chunk"), std::string::npos) << e.reason;
}

TEST(BadInput, AGlbWithAnEmptyJsonChunkIsNamedForItNotForTheBytesAfterIt) {
  // The JSON chunk's length set to 0: the JSON text is then read as a chunk header of its own.
  ScratchDir scratch;
  Bytes glb = glb_bytes(R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":64}]})", Bytes(64, 7));
  std::memset(glb.data() + 12, 0, 4);
  const fs::path file = scratch / "empty-json.glb";
  write_bytes(file, glb);
  const InputError e = load_error(file);
  EXPECT_EQ(e.offset, 12u);
  EXPECT_NE(e.reason.find("JSON chunk is empty"), std::string::npos) << e.reason;
  // One byte short of its padded length: the BIN chunk's header is read a byte early.
  Bytes unaligned = glb_bytes(R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":64}]})", Bytes(64, 7));
  std::uint32_t json_length = 0;
  std::memcpy(&json_length, unaligned.data() + 12, 4);
  --json_length;
  std::memcpy(unaligned.data() + 12, &json_length, 4);
  write_bytes(file, unaligned);
  const InputError misaligned = load_error(file);
  EXPECT_EQ(misaligned.offset, 12u);
  EXPECT_NE(misaligned.reason.find("not a multiple of 4"), std::string::npos) << misaligned.reason;
}

TEST(BadInput, MalformedJsonNamesTheByteOfTheError) {
  ScratchDir scratch;
  const std::string text = R"({"asset": {"version": "2.0"}, "materials": [ } ]})";
  const fs::path file = scratch / "malformed.gltf";
  write_text(file, text);

  const InputError e = load_error(file);
  EXPECT_EQ(e.offset, text.find('}', text.find('[')));
  EXPECT_NE(e.reason.find("malformed JSON"), std::string::npos) << e.reason;
  expect_cli_refuses(file, "malformed JSON", scratch);
}

TEST(BadInput, MalformedJsonInsideAGlbNamesTheFileOffset) {
  ScratchDir scratch;
  const std::string json = R"({"asset": {"version": "2.0"}, "nodes": [1, ]})";
  const fs::path file = scratch / "malformed.glb";
  write_bytes(file, glb_bytes(json, {}));

  const InputError e = load_error(file);
  // The JSON chunk starts after the 12-byte header and the 8-byte chunk header.
  EXPECT_EQ(e.offset, 20u + json.find(']'));
}

TEST(BadInput, TopLevelJsonThatIsNotAnObjectIsRefused) {
  ScratchDir scratch;
  const fs::path file = scratch / "array.gltf";
  write_text(file, "[1, 2, 3]");
  const InputError e = load_error(file);
  EXPECT_NE(e.reason.find("not an object"), std::string::npos) << e.reason;
}

TEST(BadInput, CollectionEntryThatIsNotAnObjectIsRefusedNamingItsPointer) {
  ScratchDir scratch;
  const fs::path file = scratch / "string_mesh.gltf";
  write_text(file, R"({"asset": {"version": "2.0"}, "meshes": [{"primitives": []}, "x"]})");
  expect_load_refused(file, "/meshes/1", "not an object");

  write_text(file, R"({"asset": {"version": "2.0"}, "nodes": {"0": {}}})");
  expect_load_refused(file, "/nodes", "not an array");
}

// ---------------------------------------------------------------------------------------------
// Resources
// ---------------------------------------------------------------------------------------------

TEST(BadInput, MissingBinNamesTheBufferUri) {
  ScratchDir scratch;
  copy_model("Box", scratch / "box", "Box0.bin");
  const fs::path gltf = scratch / "box" / "Box.gltf";

  expect_load_refused(gltf, "/buffers/0/uri", "Box0.bin");
  expect_cli_refuses(gltf, "/buffers/0/uri", scratch);
}

TEST(BadInput, MissingImageNamesTheImageUri) {
  ScratchDir scratch;
  copy_model("Duck", scratch / "duck", "DuckCM.png");
  const fs::path gltf = scratch / "duck" / "Duck.gltf";

  expect_load_refused(gltf, "/images/0/uri", "DuckCM.png");
  expect_cli_refuses(gltf, "/images/0/uri", scratch);
}

TEST(BadInput, BadBase64InADataUriBufferIsRefused) {
  ScratchDir scratch;
  const fs::path gltf = box_with_buffer_uri(scratch / "box", "data:application/octet-stream;base64,AAAA!!!!AAAA");

  expect_load_refused(gltf, "/buffers/0/uri", "base64");
  expect_cli_refuses(gltf, "base64", scratch);
}

TEST(BadInput, BadBase64InADataUriImageIsRefused) {
  ScratchDir scratch;
  const fs::path gltf = duck_with_image_uri(scratch / "duck", "data:image/png;base64,iVBORw0KGgo=A");
  expect_load_refused(gltf, "/images/0/uri", "base64");
}

// RFC 4648 base64 of `bytes`, with `last_two` as the alphabet's characters 62 and 63 ("+/" for the
// standard alphabet, "-_" for the URL-safe one), padded with '=' or not.
std::string base64_of(const Bytes& bytes, const char* last_two, bool padded) {
  const std::string alphabet = std::string("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789") + last_two;
  std::string text;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const size_t n = std::min<size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (size_t k = 0; k < 3; ++k) v = (v << 8) | (k < n ? bytes[i + k] : 0u);
    for (size_t k = 0; k < 4; ++k)
      if (k <= n || padded) text += k <= n ? alphabet[(v >> (18 - 6 * k)) & 63] : '=';
  }
  return text;
}

// The counterpart of the refusals above: a well-formed data URI loads.
TEST(DataUri, ValidBase64BufferLoadsItsBytes) {
  ScratchDir scratch;
  const auto bin = read_file(model_folder("Box") / "Box0.bin");
  ASSERT_TRUE(bin);
  const std::string base64 = base64_of(*bin, "+/", true);
  const fs::path gltf = box_with_buffer_uri(scratch / "box", "data:application/octet-stream;base64," + base64);
  const Asset asset = load_asset(gltf);
  EXPECT_EQ(asset.model.buffers.at(0).data, *bin);
}

// RFC 4648 section 5's URL-safe alphabet and left-out padding are base64 to the structure step (as
// to the Khronos validator) and to the loader alike: the buffer holds the same bytes either way.
TEST(DataUri, UrlSafeUnpaddedBase64IsReadAsTheStructureStepReadsIt) {
  ScratchDir scratch;
  const auto bin = read_file(model_folder("Box") / "Box0.bin");
  ASSERT_TRUE(bin);
  const std::string base64 = base64_of(*bin, "-_", false);
  ASSERT_NE(base64.find_first_of("-_"), std::string::npos);  // the test needs the URL-safe characters
  const fs::path gltf = box_with_buffer_uri(scratch / "box", "data:application/octet-stream;base64," + base64);
  EXPECT_EQ(decode_base64(base64), *bin);
  EXPECT_EQ(decode_base64("QUI"), (Bytes{'A', 'B'}));   // padding left out
  EXPECT_EQ(decode_base64("QUI="), (Bytes{'A', 'B'}));  // or written
  EXPECT_FALSE(decode_base64("QUI=Q"));                 // but only at the end
  EXPECT_FALSE(decode_base64("QUI=="));                 // completing the last quantum
  const Asset asset = load_asset(gltf);
  EXPECT_EQ(asset.model.buffers.at(0).data, *bin);
  // and keeps its URI as written, so a save writes back the same text
  EXPECT_EQ(asset.model.buffers.at(0).uri, "data:application/octet-stream;base64," + base64);
  ValidateOptions structure_only;
  structure_only.steps = {ValidationStep::Structure};
  const Report report = validate_file(gltf, "box.gltf", builtin_rules(), {}, structure_only);
  for (const Issue& issue : report.messages)
    EXPECT_TRUE(issue.code != "INVALID_URI" && issue.code != "BUFFER_BYTE_LENGTH_MISMATCH") << issue.message;
}

TEST(BadInput, ParentDirectoryUriIsRefusedNamingTheOption) {
  ScratchDir scratch;
  const fs::path box = box_with_buffer_uri(scratch / "box", "../../etc/passwd");
  expect_load_refused(box, "/buffers/0/uri", "--allow-outside-uris");
  expect_cli_refuses(box, "--allow-outside-uris", scratch);

  const fs::path duck = duck_with_image_uri(scratch / "duck", "../../etc/passwd");
  expect_load_refused(duck, "/images/0/uri", "--allow-outside-uris");
  expect_cli_refuses(duck, "--allow-outside-uris", scratch);
}

TEST(BadInput, CompareRefusesAnOutsideUriAndReadsItWithTheOptionItNames) {
  // Box's buffer one folder up: refused, naming the option, which compare then takes.
  ScratchDir scratch;
  const fs::path box = box_with_buffer_uri(scratch / "box", "../Box0.bin");
  fs::copy_file(model_folder("Box") / "Box0.bin", scratch / "Box0.bin");
  const CliResult refused = run_cli("compare " + quoted(box) + " " + quoted(box), scratch);
  EXPECT_EQ(refused.exit_code, 1) << refused.err;
  EXPECT_NE(refused.err.find("--allow-outside-uris"), std::string::npos) << refused.err;
  const CliResult allowed = run_cli("compare --allow-outside-uris " + quoted(box) + " " + quoted(box), scratch);
  EXPECT_EQ(allowed.exit_code, 0) << allowed.err;
}

TEST(BadInput, AbsolutePathUriIsRefusedNamingTheOption) {
  ScratchDir scratch;
  const fs::path box = box_with_buffer_uri(scratch / "box", "/etc/passwd");
  expect_load_refused(box, "/buffers/0/uri", "--allow-outside-uris");
  expect_cli_refuses(box, "--allow-outside-uris", scratch);

  const fs::path duck = duck_with_image_uri(scratch / "duck", "/etc/passwd");
  expect_load_refused(duck, "/images/0/uri", "--allow-outside-uris");
}

TEST(BadInput, PercentEncodedParentDirectoryIsRefusedToo) {
  ScratchDir scratch;
  const fs::path box = box_with_buffer_uri(scratch / "box", "%2E%2E/%2E%2E/etc/passwd");
  expect_load_refused(box, "/buffers/0/uri", "--allow-outside-uris");
}

TEST(BadInput, SchemeUriIsRefused) {
  ScratchDir scratch;
  const fs::path box = box_with_buffer_uri(scratch / "box", "https://example.com/Box0.bin");
  expect_load_refused(box, "/buffers/0/uri", "scheme");
}

TEST(OutsideUris, AllowedRelativeAndAbsoluteUrisReadAFileOutsideTheAssetFolder) {
  ScratchDir scratch;
  const auto bin = read_file(model_folder("Box") / "Box0.bin");
  const auto png = read_file(model_folder("Duck") / "DuckCM.png");
  ASSERT_TRUE(bin && png);
  write_bytes(scratch / "elsewhere" / "Box0.bin", *bin);
  write_bytes(scratch / "elsewhere" / "DuckCM.png", *png);
  LoadOptions allow;
  allow.allow_outside_uris = true;

  const fs::path relative = box_with_buffer_uri(scratch / "relative", "../elsewhere/Box0.bin");
  EXPECT_EQ(load_asset(relative, allow).model.buffers.at(0).data, *bin);

  const fs::path absolute = box_with_buffer_uri(scratch / "absolute", (scratch / "elsewhere" / "Box0.bin").string());
  EXPECT_EQ(load_asset(absolute, allow).model.buffers.at(0).data, *bin);

  const fs::path image = duck_with_image_uri(scratch / "image", "../elsewhere/DuckCM.png");
  const Asset duck = load_asset(image, allow);
  const auto bytes = encoded_image_bytes(duck, 0);
  EXPECT_EQ(Bytes(bytes.begin(), bytes.end()), *png);

  // Allowed, but the target does not exist: still an InputError, not a crash.
  const fs::path missing = box_with_buffer_uri(scratch / "missing", "../elsewhere/nothing.bin");
  expect_load_refused(missing, "/buffers/0/uri", "not found", allow);
}

TEST(OutsideUris, CliWithTheOptionConvertsAndWritesOnlyInsideTheOutputFolder) {
  ScratchDir scratch;
  const auto bin = read_file(model_folder("Box") / "Box0.bin");
  ASSERT_TRUE(bin);
  write_bytes(scratch / "elsewhere" / "Box0.bin", *bin);
  const fs::path relative = box_with_buffer_uri(scratch / "relative" / "asset", "../../elsewhere/Box0.bin");
  const fs::path absolute = box_with_buffer_uri(scratch / "absolute", (scratch / "elsewhere" / "Box0.bin").string());
  const auto before = files_under(scratch.path());

  for (const fs::path& input : {relative, absolute}) {
    SCOPED_TRACE(input.string());
    const fs::path out = scratch / "out" / input.parent_path().filename();
    const CliResult r =
        run_cli("convert -q --allow-outside-uris " + quoted(input) + " -o " + quoted(out / "Box.gltf"), scratch);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    // The output stands alone inside its folder: it loads without the option.
    const Asset converted = load_asset(out / "Box.gltf");
    EXPECT_EQ(converted.model.buffers.at(0).data, *bin);
    EXPECT_EQ(spec_gloss_materials(converted), 0);
    EXPECT_EQ(files_under(out).size(), 2u);  // Box.gltf and its buffer
  }
  // Nothing was written anywhere but under out/.
  std::vector<fs::path> after;
  for (const fs::path& file : files_under(scratch.path()))
    if (file.lexically_relative(scratch.path()).begin()->string() != "out") after.push_back(file);
  std::sort(after.begin(), after.end());
  std::vector<fs::path> expected = before;
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(after, expected);
}

// ---------------------------------------------------------------------------------------------
// Material values
// ---------------------------------------------------------------------------------------------

TEST(BadInput, InfiniteDiffuseFactorIsRefusedNamingItsComponent) {
  ScratchDir scratch;
  // JSON cannot hold Inf, but 1e999 overflows a double to it.
  const fs::path gltf = box_with_number_text(scratch / "box", "diffuseFactor", "1e999");
  expect_load_refused(gltf, kExtensionPointer + "/diffuseFactor/0", "1e999");
  expect_cli_refuses(gltf, kExtensionPointer + "/diffuseFactor/0", scratch);
}

TEST(BadInput, NegativeOverflowInGlossinessIsRefusedNamingIt) {
  ScratchDir scratch;
  const fs::path gltf = box_with_number_text(scratch / "box", "glossinessFactor", "-1E+999");
  EXPECT_EQ(load_error(gltf).pointer, kExtensionPointer + "/glossinessFactor");
}

TEST(BadInput, NonFiniteFactorsInMemoryAreRefusedByConvertNamingThePointer) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    const char* key;
    int component;  // -1: a scalar
    double value;
  };
  for (const Case c : {Case{"diffuseFactor", 0, inf}, Case{"diffuseFactor", 3, nan}, Case{"specularFactor", 1, -inf},
                       Case{"glossinessFactor", -1, nan}}) {
    const std::string where =
        kExtensionPointer + "/" + c.key + (c.component >= 0 ? "/" + std::to_string(c.component) : "");
    SCOPED_TRACE(where);
    Asset asset = load_asset(model_folder("Box") / "Box.gltf");
    tinygltf::Value::Object extension =
        asset.model.materials.at(0).extensions.at(kSpecGloss).Get<tinygltf::Value::Object>();
    if (c.component < 0) {
      extension[c.key] = tinygltf::Value(c.value);
    } else {
      tinygltf::Value::Array array(std::string(c.key) == "diffuseFactor" ? 4 : 3, tinygltf::Value(0.5));
      array[static_cast<size_t>(c.component)] = tinygltf::Value(c.value);
      extension[c.key] = tinygltf::Value(array);
    }
    asset.model.materials.at(0).extensions[kSpecGloss] = tinygltf::Value(extension);
    const InputError e = input_error([&] { convert(asset); });
    EXPECT_EQ(e.pointer, where);
    EXPECT_NE(e.reason.find("finite"), std::string::npos) << e.reason;
  }
}

TEST(BadInput, TextureIndexOutOfRangeInTheExtensionIsRefused) {
  ScratchDir scratch;
  copy_model("Duck", scratch / "duck");
  const fs::path gltf = scratch / "duck" / "Duck.gltf";
  nlohmann::json document = read_json(gltf);
  document["materials"][0]["extensions"][kSpecGloss]["diffuseTexture"]["index"] = 7;
  write_json(gltf, document);

  const InputError e = convert_error(gltf);
  EXPECT_EQ(e.pointer, kExtensionPointer + "/diffuseTexture/index");
  EXPECT_NE(e.reason.find("7"), std::string::npos) << e.reason;
  expect_cli_refuses(gltf, kExtensionPointer + "/diffuseTexture/index", scratch);

  document["materials"][0]["extensions"][kSpecGloss]["diffuseTexture"]["index"] = 0;
  document["materials"][0]["extensions"][kSpecGloss]["specularGlossinessTexture"] = {{"index", -1}};
  write_json(gltf, document);
  EXPECT_EQ(convert_error(gltf).pointer, kExtensionPointer + "/specularGlossinessTexture/index");
}

TEST(BadInput, TextureWithoutAnImageInTheExtensionIsRefused) {
  ScratchDir scratch;
  copy_model("Duck", scratch / "duck");
  const fs::path gltf = scratch / "duck" / "Duck.gltf";
  nlohmann::json document = read_json(gltf);
  document["textures"][0].erase("source");
  write_json(gltf, document);
  EXPECT_EQ(convert_error(gltf).pointer, kExtensionPointer + "/diffuseTexture/index");
}

TEST(BadInput, UndecodableImageIsAnInputErrorNamingTheImage) {
  ScratchDir scratch;
  copy_model("Duck", scratch / "duck", "DuckCM.png");
  const auto png = read_file(model_folder("Duck") / "DuckCM.png");
  ASSERT_TRUE(png);
  write_bytes(scratch / "duck" / "DuckCM.png", std::span(*png).first(40));  // signature, IHDR, then nothing
  const fs::path gltf = scratch / "duck" / "Duck.gltf";

  const InputError e = convert_error(gltf);
  EXPECT_EQ(e.pointer, "/images/0");
  expect_cli_refuses(gltf, "/images/0", scratch);
}

// ---------------------------------------------------------------------------------------------
// The CLI: batches, usage, and never overwriting the input
// ---------------------------------------------------------------------------------------------

TEST(CliBadInput, BatchWithOneBadFileConvertsTheGoodOneAndExits1) {
  ScratchDir scratch;
  const fs::path inputs = scratch / "inputs";
  copy_model("Box", inputs / "good");
  copy_model("Box", inputs / "bad", "Box0.bin");
  const fs::path out = scratch / "out";

  const CliResult r = run_cli("convert -q -j 2 " + quoted(inputs) + " -o " + quoted(out), scratch);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find((inputs / "bad" / "Box.gltf").string()), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("/buffers/0/uri"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find((inputs / "good" / "Box.gltf").string()), std::string::npos)
      << "-q prints only failures: " << r.err;

  const Asset converted = load_asset(out / "inputs" / "good" / "Box.gltf");
  EXPECT_EQ(spec_gloss_materials(converted), 0);
  EXPECT_FALSE(fs::exists(out / "inputs" / "bad" / "Box.gltf"));
  for (const fs::path& file : files_under(out)) EXPECT_EQ(file.parent_path(), out / "inputs" / "good") << file;
  EXPECT_TRUE(temporaries_under(scratch.path()).empty());
}

TEST(CliBadInput, BadUsageExits2) {
  ScratchDir scratch;
  copy_model("Box", scratch / "box");
  const fs::path gltf = scratch / "box" / "Box.gltf";
  const fs::path out = scratch / "out";
  for (const std::string& arguments : std::vector<std::string>{
           "convert --no-such-option " + quoted(gltf) + " -o " + quoted(out), "convert " + quoted(gltf),
           "convert -o " + quoted(out), "convert " + quoted(scratch / "nothing.gltf") + " -o " + quoted(out),
           "convert --target shiny " + quoted(gltf) + " -o " + quoted(out), "no-such-command"}) {
    SCOPED_TRACE(arguments);
    const CliResult r = run_cli(arguments, scratch);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_FALSE(r.err.empty());
  }
  EXPECT_FALSE(fs::exists(out));
}

TEST(CliBadInput, OutputEqualToTheInputIsRefusedAndTheInputKeepsItsBytes) {
  ScratchDir scratch;
  copy_model("Box", scratch / "box");
  copy_model("CesiumMilkTruck", scratch / "truck", "", "specgloss-glb-generated");
  for (const fs::path& input : {scratch / "box" / "Box.gltf", scratch / "truck" / "CesiumMilkTruck.glb"}) {
    SCOPED_TRACE(input.string());
    auto folder_before = files_under(input.parent_path());
    std::sort(folder_before.begin(), folder_before.end());
    std::vector<Bytes> bytes_before;
    for (const fs::path& file : folder_before) bytes_before.push_back(*read_file(file));

    const CliResult r = run_cli("convert -q " + quoted(input) + " -o " + quoted(input), scratch);
    EXPECT_EQ(r.exit_code, 1) << r.err;
    EXPECT_NE(r.err.find("overwrite"), std::string::npos) << r.err;
    auto folder_after = files_under(input.parent_path());
    std::sort(folder_after.begin(), folder_after.end());
    EXPECT_EQ(folder_after, folder_before);
    for (size_t i = 0; i < folder_before.size(); ++i)
      EXPECT_EQ(read_file(folder_before[i]), bytes_before[i]) << folder_before[i];
  }
}

TEST(NeverOverwrite, SaveAssetRefusesTheInputFileAndItsResources) {
  ScratchDir scratch;
  copy_model("Box", scratch / "box");
  const fs::path gltf = scratch / "box" / "Box.gltf", bin = scratch / "box" / "Box0.bin";
  const auto gltf_before = read_file(gltf), bin_before = read_file(bin);
  for (const fs::path& target : {gltf, bin}) {
    Asset asset = load_asset(gltf);
    convert(asset);
    EXPECT_THROW(save_asset(asset, target), std::runtime_error) << target;
  }
  EXPECT_EQ(read_file(gltf), gltf_before);
  EXPECT_EQ(read_file(bin), bin_before);
  EXPECT_EQ(files_under(scratch / "box").size(), 2u);
}

TEST(CliBadInput, InPlaceReplacesTheInputWithItsConversion) {
  ScratchDir scratch;
  copy_model("Box", scratch / "box");
  const fs::path gltf = scratch / "box" / "Box.gltf";
  const auto bin_before = read_file(scratch / "box" / "Box0.bin");
  ASSERT_EQ(spec_gloss_materials(load_asset(gltf)), 1);

  const CliResult r = run_cli("convert -q --in-place " + quoted(gltf), scratch);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const Asset converted = load_asset(gltf);
  EXPECT_EQ(spec_gloss_materials(converted), 0);
  EXPECT_TRUE(std::find(converted.model.extensionsUsed.begin(), converted.model.extensionsUsed.end(), kSpecGloss) ==
              converted.model.extensionsUsed.end());
  EXPECT_EQ(read_file(scratch / "box" / "Box0.bin"), bin_before);  // the untouched buffer keeps its bytes
  // Only the two files: no temporary and no staging copy left beside them.
  EXPECT_EQ(files_under(scratch / "box").size(), 2u);
}

// Baked images take the input's stem, never that of a temporary or staging file (hidden names such
// as ".gltf-pbr-Duck_baseColor_1.png").
TEST(CliBadInput, InPlaceBakedImagesAreNamedAfterTheInputNotTheStagingFile) {
  ScratchDir scratch;
  copy_model("Duck", scratch / "duck");
  const fs::path gltf = scratch / "duck" / "Duck.gltf";
  const CliResult r = run_cli("convert -q --in-place " + quoted(gltf), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const fs::path& file : files_under(scratch / "duck")) EXPECT_NE(file.filename().string().front(), '.') << file;
  EXPECT_EQ(spec_gloss_materials(load_asset(gltf)), 0);
}

}  // namespace
}  // namespace gltf_pbr
