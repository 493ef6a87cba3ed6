// Loading: a pre-pass over the container, the JSON tree (the one reader's, core/json.hpp) and the
// URIs gives errors that name the file, a JSON pointer and the reason; tinygltf then builds the
// document with images kept encoded.
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <optional>

#include "core/asset.hpp"
#include "core/byte_order.hpp"
#include "core/error.hpp"
#include "core/glb.hpp"
#include "core/json.hpp"
#include "core/meshopt.hpp"

namespace gltf_pbr {

WorkCounters& work_counters() {
  static WorkCounters counters;
  return counters;
}

std::span<const std::uint8_t> encoded_image_bytes(const Asset& asset, int index) {
  const tinygltf::Model& model = asset.model;
  const tinygltf::Image& image = model.images.at(static_cast<size_t>(index));
  if (!image.image.empty()) return image.image;
  if (image.bufferView >= 0) {
    std::string problem;
    return buffer_view_bytes(asset, image.bufferView, problem).value_or(std::span<const std::uint8_t>{});
  }
  const auto file = asset.image_files.find(image.uri);
  return file == asset.image_files.end() ? std::span<const std::uint8_t>{} : file->second->bytes();
}

void release_encoded_image_pages(const Asset& asset, int index) {
  const tinygltf::Image& image = asset.model.images.at(static_cast<size_t>(index));
  if (!image.image.empty() || image.bufferView >= 0) return;
  if (const auto file = asset.image_files.find(image.uri); file != asset.image_files.end())
    file->second->release_pages();
}

namespace {

struct GlbParts {
  std::string json;
  std::span<const std::uint8_t> bin;
};

// glTF 2.0 spec section 4.4 (GLB file format specification), strictly: a JSON chunk first, an
// optional BIN chunk second, both inside the header's length.
GlbParts split_glb(const std::string& file, std::span<const std::uint8_t> bytes) {
  auto fail = [&](size_t offset, const std::string& why) -> GlbParts {
    throw InputError(file, ByteOffset{offset}, why);
  };
  if (bytes.size() < 20) fail(0, "truncated GLB: " + std::to_string(bytes.size()) + " bytes, a header needs 20");
  if (little_endian32(bytes, 4) != 2)
    fail(4, "GLB version " + std::to_string(little_endian32(bytes, 4)) + ", only 2 is supported");
  const std::uint32_t length = little_endian32(bytes, 8);
  if (length > bytes.size())
    fail(8,
         "truncated GLB: header says " + std::to_string(length) + " bytes, file has " + std::to_string(bytes.size()));
  // Walked to the end of the bytes: each chunk is judged against `length` here.
  GlbChunks chunks(bytes, bytes.size());
  const std::optional<GlbChunk> json = chunks.next();  // the 20 bytes hold its header
  if (json->type != kGlbChunkJson) fail(16, "first GLB chunk is not JSON");
  if (json->end() > length) fail(12, "truncated GLB: JSON chunk runs past the end of the file");
  if (json->data.empty()) fail(12, "the GLB's JSON chunk is empty");
  GlbParts parts{std::string(json->data.begin(), json->data.end()), {}};
  if (json->end() + kGlbChunkHeaderSize <= length) {
    const std::optional<GlbChunk> bin = chunks.next();  // its header lies inside `length`, so in the bytes
    if (bin->end() > length) {
      // Chunks start on 4-byte boundaries (spec 4.4.3): after a JSON chunk of another length the
      // next header is read from the wrong bytes, which is the fault to name.
      if (json->data.size() % 4 != 0)
        fail(12, "the GLB's JSON chunk is " + std::to_string(json->data.size()) +
                     " bytes, not a multiple of 4, so no chunk can follow it");
      char type[16];
      std::snprintf(type, sizeof type, "0x%08x", bin->type);
      fail(bin->offset, std::string("truncated GLB: the ") + (bin->type == kGlbChunkBin ? "BIN chunk" : "chunk") +
                            " after the JSON (type " + type + ") runs past the end of the file");
    }
    if (bin->type == kGlbChunkBin) parts.bin = bin->data;
  }
  return parts;
}

// External buffer files by absolute, normal path: the only files tinygltf's read callback serves.
using BufferFiles = std::map<fs::path, std::shared_ptr<const MappedFile>>;

// The JSON text of a GLB starts after the 12-byte header and the JSON chunk's 8-byte header (glTF
// 2.0 section 4.4): offsets into it are given as offsets into the file.
std::size_t json_start(const Asset& asset) { return asset.binary ? kGlbHeaderSize + kGlbChunkHeaderSize : 0; }

// RFC 8259 section 8.1: a reader may ignore a byte order mark, as the document library does.
std::span<const std::uint8_t> without_bom(std::span<const std::uint8_t> text) {
  const bool bom = text.size() >= 3 && text[0] == 0xEF && text[1] == 0xBB && text[2] == 0xBF;
  return bom ? text.subspan(3) : text;
}

std::span<const std::uint8_t> bytes_of(const std::string& text) {
  return {reinterpret_cast<const std::uint8_t*>(text.data()), text.size()};
}

// The document's JSON tree: the one the structure step read when it ran on this file (validate,
// convert's value scan), else read here, through the one reader (core/json.hpp).
JsonDocument read_document(const Asset& asset) {
  const std::string file = asset.path.string();
  const std::span<const std::uint8_t> text = without_bom(bytes_of(asset.original_json));
  const std::size_t start = json_start(asset) + (asset.original_json.size() - text.size());
  FileResources::Document read;
  if (std::optional<FileResources::Document> kept = asset.resources->take_document(bytes_of(asset.original_json))) {
    read = std::move(*kept);
  } else if (const std::optional<JsonProblem> problem = read_json(text, read.root, &read.flaws)) {
    const ByteOffset at{start + problem->offset};
    switch (problem->kind) {
      case JsonProblem::Kind::InvalidUtf8:
        throw InputError(file, at, "malformed JSON: not UTF-8");
      case JsonProblem::Kind::UnexpectedCharacter: {
        const std::uint8_t c = text[problem->offset];
        char shown[8];
        std::snprintf(shown, sizeof shown, c >= 0x20 && c < 0x7F ? "'%c'" : "0x%02x", c);
        throw InputError(file, at, std::string("malformed JSON: unexpected character ") + shown);
      }
      case JsonProblem::Kind::UnexpectedEnd:
        throw InputError(file, at, "malformed JSON: unexpected end of the text");
      case JsonProblem::Kind::TooDeep:
        throw InputError(file, at, "JSON nested deeper than " + std::to_string(kMaxJsonDepth) + " levels");
    }
  }
  JsonDocument& root = read.root;
  // JSON cannot hold NaN or Inf, but 1e999 reads as Inf, and tinygltf cannot hold a lone
  // surrogate; it would refuse either without saying where. The reader notes both, and the tree
  // is searched for the pointer only then.
  if (read.flaws.any())
    if (const std::optional<JsonFlaw> flaw = first_flaw(root)) {
      if (flaw->kind == JsonFlaw::Kind::NotUnicode)
        throw InputError(file, flaw->pointer, "a string holds a lone surrogate (\\uD800-\\uDFFF): not Unicode text");
      throw InputError(file, flaw->pointer, "number " + read.flaws.first_non_finite + " is out of range: not finite");
    }
  if (!root.is_object()) throw InputError(file, "", "the top-level JSON value is not an object");
  return std::move(root);
}

// A non-negative integer, however the reader stored it (int64, or uint64 above its range).
std::optional<std::uintmax_t> non_negative_integer(const JsonDocument& value) {
  if (value.is_number_unsigned()) return value.get<std::uintmax_t>();
  if (value.is_number_integer() && value.get<std::int64_t>() >= 0)
    return static_cast<std::uintmax_t>(value.get<std::int64_t>());
  return std::nullopt;
}

// Checks what tinygltf would otherwise skip or report without a pointer: external and data URIs
// of buffers and images, and the shape of the collections. Maps the files it checked through the
// asset's resources: images into asset.image_files, buffers into `buffer_files`.
void check_resources(Asset& asset, const JsonDocument& root, bool glb_has_bin, BufferFiles& buffer_files) {
  const std::string file = asset.path.string();
  // tinygltf refuses a misshapen collection without saying where ("`meshes' does not contain an
  // JSON object."); name the pointer instead (glTF 2.0 schema: each is an array of objects).
  for (const char* collection : {"accessors", "animations", "buffers", "bufferViews", "cameras", "images", "materials",
                                 "meshes", "nodes", "samplers", "scenes", "skins", "textures"}) {
    const auto it = root.find(collection);
    if (it == root.end()) continue;
    if (!it->is_array()) throw InputError(file, std::string("/") + collection, "not an array");
    for (size_t i = 0; i < it->size(); ++i)
      if (!(*it)[i].is_object()) throw InputError(file, pointer(collection, static_cast<int>(i)), "not an object");
  }
  // tinygltf 2.7 reads extension integers as int: a larger EXT_meshopt_compression offset or
  // length would wrap and decode other bytes, so it is refused here, where it is named.
  if (const auto views = root.find("bufferViews"); views != root.end())
    for (size_t v = 0; v < views->size(); ++v) {
      const JsonDocument& view = (*views)[v];
      const auto extensions = view.find("extensions");
      if (extensions == view.end() || !extensions->is_object()) continue;
      const auto extension = extensions->find("EXT_meshopt_compression");
      if (extension == extensions->end() || !extension->is_object()) continue;
      for (const char* member : {"buffer", "byteOffset", "byteLength", "byteStride", "count"}) {
        const auto value = extension->find(member);
        if (value == extension->end() || !value->is_number()) continue;  // its absence is the decoder's to name
        const double number = value->get<double>();
        if (!(number >= 0 && number <= INT32_MAX && std::trunc(number) == number))
          throw InputError(
              file, pointer("bufferViews", static_cast<int>(v)) + "/extensions/EXT_meshopt_compression/" + member,
              "is not an integer from 0 to 2^31 - 1 (the largest the document library reads)");
      }
    }
  for (const char* collection : {"buffers", "images"}) {
    const auto it = root.find(collection);
    if (it == root.end()) continue;
    for (size_t i = 0; i < it->size(); ++i) {
      const JsonDocument& entry = (*it)[i];
      const std::string where = pointer(collection, static_cast<int>(i));
      const auto uri = entry.find("uri");
      if (uri == entry.end()) {
        if (std::strcmp(collection, "buffers") == 0 && !(i == 0 && glb_has_bin) && !is_meshopt_fallback_json(entry))
          throw InputError(file, where, "buffer has no uri and no GLB BIN chunk to stand for it");
        continue;
      }
      if (!uri->is_string()) throw InputError(file, where + "/uri", "uri is not a string");
      const std::string text = uri->get<std::string>();
      std::uintmax_t size = 0;
      if (is_data_uri(text)) {
        const auto data = decode_data_uri(text);
        if (!data) throw InputError(file, where + "/uri", "data URI is not valid base64");
        size = data->size();
      } else {
        const FileResources::External& external = asset.resources->external(text);
        if (external.resolved.status != UriStatus::Readable)
          throw InputError(file, where + "/uri", external.resolved.problem);
        if (!external.file)
          throw InputError(file, where + "/uri",
                           "cannot read " + text + ": " + unreadable_reason(external.resolved.path));
        size = external.file->bytes().size();
        if (std::strcmp(collection, "images") == 0) {
          if (size == 0) throw InputError(file, where + "/uri", "the image file " + text + " is empty");
          asset.image_files.emplace(text, external.file);
        } else {
          buffer_files.emplace(fs::absolute(external.resolved.path).lexically_normal(), external.file);
        }
      }
      // glTF 2.0 section 3.6.1.1: a buffer's data holds at least byteLength bytes. tinygltf 2.7
      // reads a buffer only when it holds exactly byteLength, and says so without a pointer ("File
      // size mismatch"): both cases are named here. Longer data is valid glTF that we cannot load
      // yet. A wrong-typed byteLength is tinygltf's to refuse.
      const auto length = entry.find("byteLength");
      const std::optional<std::uintmax_t> declared_length =
          length != entry.end() ? non_negative_integer(*length) : std::nullopt;
      if (std::strcmp(collection, "buffers") == 0 && declared_length && size != *declared_length) {
        const std::uintmax_t declared = *declared_length;
        const std::string data = is_data_uri(text) ? std::string("the data URI") : "the file " + text;
        throw InputError(file, where + "/byteLength",
                         "byteLength is " + std::to_string(declared) + " but " + data + " holds " +
                             std::to_string(size) + " bytes" +
                             (size > declared ? " (valid glTF, but the document library reads a buffer only "
                                                "when the two are equal)"
                                              : ""));
      }
    }
  }
}

// tinygltf 2.7 reads every buffer: one without a uri is an error in a .gltf and the BIN chunk in a
// GLB. A fallback buffer without a uri gets a one-byte data URI for the parse and its emptiness
// back afterwards (its byteLength is derived again when saved, core/save.cpp).
std::vector<size_t> hide_meshopt_fallbacks(JsonDocument& root, bool glb_has_bin) {
  std::vector<size_t> hidden;
  const auto buffers = root.find("buffers");
  if (buffers == root.end()) return hidden;
  for (size_t b = 0; b < buffers->size(); ++b) {
    JsonDocument& buffer = (*buffers)[b];
    // A GLB's first buffer without a uri is its BIN chunk, marked fallback or not (glTF 2.0 4.4.3.2).
    if (buffer.contains("uri") || !is_meshopt_fallback_json(buffer) || (b == 0 && glb_has_bin)) continue;
    buffer["uri"] = "data:application/octet-stream;base64,AA==";
    buffer["byteLength"] = 1;
    hidden.push_back(b);
  }
  return hidden;
}

// tinygltf 2.7 without its Draco decoder refuses a Draco primitive's indices accessor, which
// rightly has no bufferView; with the decoder it would decode every mesh on load. So the indices
// of Draco primitives are hidden from it and restored afterwards: meshes stay compressed.
struct HiddenIndices {
  std::vector<std::pair<std::pair<size_t, size_t>, int>> entries;  // ((mesh, primitive), indices)
};

// check_resources has already refused meshes that are not an array of objects (the fuzzer found
// a mesh that is a string); `find`, not operator[], so a mesh without primitives gets no null one.
HiddenIndices hide_draco_indices(JsonDocument& root) {
  HiddenIndices hidden;
  const auto meshes = root.find("meshes");
  if (meshes == root.end()) return hidden;
  for (size_t m = 0; m < meshes->size(); ++m) {
    auto& mesh = (*meshes)[m];
    const auto primitives = mesh.find("primitives");
    if (primitives == mesh.end() || !primitives->is_array()) continue;
    for (size_t p = 0; p < primitives->size(); ++p) {
      auto& primitive = (*primitives)[p];
      if (!primitive.is_object() || !primitive.contains("indices") || !primitive["indices"].is_number_integer())
        continue;
      const auto extensions = primitive.find("extensions");
      if (extensions == primitive.end() || !extensions->is_object() ||
          !extensions->contains("KHR_draco_mesh_compression"))
        continue;
      hidden.entries.push_back({{m, p}, primitive["indices"].get<int>()});
      primitive.erase("indices");
    }
  }
  return hidden;
}

// A URI as tinygltf 2.7 reads it as meant, when it would misread it as written:
// - a data URI in the URL-safe base64 alphabet (RFC 4648 section 5), which decode_base64 (what
//   validators take) reads and tinygltf stops at: the standard alphabet decodes to the same bytes;
// - an image data URI of a media type it does not take (it takes png, jpeg, bmp and gif; a valid
//   image/webp one it reads as a file name): the bytes are kept undecoded either way
//   (keep_encoded), so a type it takes stands in, and the format matters only to a step that
//   needs texels;
// - a buffer file name holding '+', which it URL-decodes as a form does (a space) where a URI
//   keeps '+' as itself (RFC 3986 section 2.2): percent-encoded, both readings give '+'.
// Image files are read by check_resources, not by tinygltf, so their names need no respelling.
std::optional<std::string> spelling_for_tinygltf(const std::string& uri, bool image) {
  std::string spelled = uri;
  if (is_data_uri(uri)) {
    const std::size_t comma = uri.find(',');
    if (comma == std::string::npos) return std::nullopt;
    for (std::size_t i = comma + 1; i < spelled.size(); ++i)
      if (spelled[i] == '-' || spelled[i] == '_') spelled[i] = spelled[i] == '-' ? '+' : '/';
    if (image && !tinygltf::IsDataURI(uri))
      spelled = "data:application/octet-stream;base64," + spelled.substr(comma + 1);
  } else if (!image) {
    spelled.clear();
    for (char c : uri) spelled += c == '+' ? std::string("%2B") : std::string(1, c);
  }
  if (spelled == uri) return std::nullopt;
  return spelled;
}

// The URIs of buffers and images respelled for the parse, each with its spelling as written, which
// the loaded document gets back.
struct RespelledUri {
  bool image;
  std::size_t index;
  std::string as_written;
};

std::vector<RespelledUri> respell_uris_for_tinygltf(JsonDocument& root) {
  std::vector<RespelledUri> respelled;
  for (const bool image : {false, true}) {
    const auto entries = root.find(image ? "images" : "buffers");
    if (entries == root.end()) continue;
    for (std::size_t i = 0; i < entries->size(); ++i) {
      const auto uri = (*entries)[i].find("uri");
      if (uri == (*entries)[i].end() || !uri->is_string()) continue;
      if (std::optional<std::string> spelled = spelling_for_tinygltf(uri->get_ref<const std::string&>(), image)) {
        respelled.push_back({image, i, uri->get<std::string>()});
        *uri = std::move(*spelled);
      }
    }
  }
  return respelled;
}

// tinygltf's messages end in newlines and name absolute paths; ours name the file once, relative.
std::string tidy(std::string message, const std::string& base_dir) {
  for (size_t at; !base_dir.empty() && (at = message.find(base_dir + "/")) != std::string::npos;)
    message.erase(at, base_dir.size() + 1);
  while (!message.empty() && std::isspace(static_cast<unsigned char>(message.back()))) message.pop_back();
  for (size_t at; (at = message.find('\n')) != std::string::npos;) message.replace(at, 1, "; ");
  return message;
}

struct LoaderContext {
  fs::path folder;
  const BufferFiles& buffer_files;
};

// tinygltf image callback: keep the encoded bytes of data-URI images; bufferView images already
// live in their buffer, and image files are mapped by check_resources (tinygltf is built with
// TINYGLTF_NO_EXTERNAL_IMAGE). Decoding waits until a step needs texels (core/image.cpp).
bool keep_encoded(tinygltf::Image* image, const int, std::string*, std::string*, int, int, const unsigned char* bytes,
                  int size, void*) {
  if (image->bufferView < 0) image->image.assign(bytes, bytes + size);
  image->as_is = true;
  return true;
}

// tinygltf joins every URI to the base folder, absolute ones too ("/base" + "/" + "/abs"); this
// undoes that, so that an allowed absolute URI reads the file it names.
std::string expand_file_path(const std::string& joined, void* user) {
  const auto* context = static_cast<const LoaderContext*>(user);
  std::string prefix = context->folder.string();
  if (prefix.empty() || prefix.back() != '/') prefix += '/';
  if (joined.size() > prefix.size() && joined.compare(0, prefix.size(), prefix) == 0 && joined[prefix.size()] == '/')
    return joined.substr(prefix.size());
  return joined;
}

bool read_whole_file(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* user) {
  const auto* context = static_cast<const LoaderContext*>(user);
  // Only the files check_resources resolved through the path policy are served, from their mapping.
  const auto file = context->buffer_files.find(fs::absolute(path).lexically_normal());
  if (file == context->buffer_files.end())
    return (*err += "refused to read a file the loader did not check: " + path + "\n"), false;
  out->assign(file->second->bytes().begin(), file->second->bytes().end());
  file->second->release_pages();  // tinygltf keeps its copy; the mapping's pages go back
  return true;
}

}  // namespace

std::optional<std::vector<std::string>> external_uris(std::span<const std::uint8_t> file_bytes) {
  try {
    const bool binary = file_bytes.size() >= 4 && std::memcmp(file_bytes.data(), "glTF", 4) == 0;
    const std::string json_text = binary ? split_glb("", file_bytes).json : std::string();
    const std::span<const std::uint8_t> text = without_bom(binary ? bytes_of(json_text) : file_bytes);
    JsonDocument root;
    if (read_json(text, root) || !root.is_object()) return std::nullopt;
    std::vector<std::string> uris;
    for (const char* collection : {"buffers", "images"}) {
      const auto entries = root.find(collection);
      if (entries == root.end() || !entries->is_array()) continue;
      for (const JsonDocument& entry : *entries) {
        const auto uri = entry.is_object() ? entry.find("uri") : entry.end();
        if (uri != entry.end() && uri->is_string() && !is_data_uri(uri->get<std::string>()))
          uris.push_back(uri->get<std::string>());
      }
    }
    return uris;
  } catch (const std::exception&) {  // InputError from the container, bad_alloc
    return std::nullopt;
  }
}

Asset load_asset(const fs::path& path, const LoadOptions& options) {
  ++work_counters().assets_loaded;
  Asset asset;
  asset.path = path;
  const std::string file = path.string();
  std::optional<Bytes> read;  // the file's bytes, when the caller has not read them
  if (!options.file_bytes) {
    ++work_counters().documents_read;
    read = read_file(path);
    if (!read) throw InputError(file, "", "cannot read the file: " + unreadable_reason(path));
  }
  const std::span<const std::uint8_t> bytes = options.file_bytes ? *options.file_bytes : *read;
  asset.binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (!asset.binary && extension == ".glb")  // glTF 2.0 section 4.4.2: a GLB starts with its magic
    throw InputError(file, ByteOffset{0},
                     bytes.size() < 12
                         ? "not a GLB: " + std::to_string(bytes.size()) + " bytes, shorter than the 12-byte GLB header"
                         : "not a GLB: the file does not start with the magic 'glTF'");

  std::span<const std::uint8_t> glb_bin;  // a GLB's BIN chunk, in `bytes`
  if (asset.binary) {
    GlbParts chunks = split_glb(file, bytes);
    glb_bin = chunks.bin;
    asset.original_json = std::move(chunks.json);
  } else {
    asset.original_json.assign(bytes.begin(), bytes.end());
  }
  asset.resources = options.resources ? options.resources
                                      : std::make_shared<FileResources>(path.parent_path(), options.allow_outside_uris);
  BufferFiles buffer_files;
  JsonDocument root = read_document(asset);
  check_resources(asset, root, !glb_bin.empty(), buffer_files);
  const HiddenIndices hidden = hide_draco_indices(root);
  const std::vector<RespelledUri> respelled = respell_uris_for_tinygltf(root);
  const std::vector<size_t> fallbacks = hide_meshopt_fallbacks(root, !glb_bin.empty());
  const bool rewritten = !hidden.entries.empty() || !respelled.empty() || !fallbacks.empty();
  std::string json_for_tinygltf;
  Bytes rewritten_glb;
  if (rewritten) {
    json_for_tinygltf = root.dump();
    if (asset.binary) rewritten_glb = glb_bytes(json_for_tinygltf, glb_bin);
  }
  const std::span<const std::uint8_t> glb = rewritten_glb.empty() ? bytes : rewritten_glb;
  const std::string& json_text = rewritten ? json_for_tinygltf : asset.original_json;

  LoaderContext context{fs::absolute(path).parent_path().lexically_normal(), buffer_files};
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&keep_encoded, nullptr);
  tinygltf::FsCallbacks callbacks{&tinygltf::FileExists, &expand_file_path, &read_whole_file, &tinygltf::WriteWholeFile,
                                  &context};
  loader.SetFsCallbacks(callbacks);
  std::string err, warn;
  const std::string base_dir = context.folder.string();
  bool ok = false;
  try {
    ok = asset.binary ? loader.LoadBinaryFromMemory(&asset.model, &err, &warn, glb.data(),
                                                    static_cast<unsigned>(glb.size()), base_dir)
                      : loader.LoadASCIIFromString(&asset.model, &err, &warn, json_text.c_str(),
                                                   static_cast<unsigned>(json_text.size()), base_dir);
  } catch (const std::exception& error) {
    // tinygltf 2.7 indexes with .at() on some inputs it does not check (found by the fuzzer: a GLB
    // buffer of byteLength 0 beside a BIN chunk).
    throw InputError(file, "", std::string("cannot load glTF: ") + error.what());
  }
  if (!ok) throw InputError(file, "", "cannot load glTF: " + tidy(err.empty() ? warn : err, base_dir));
  if (!warn.empty()) asset.warnings.push_back(tidy(warn, base_dir));
  for (const RespelledUri& uri : respelled)
    (uri.image ? asset.model.images.at(uri.index).uri : asset.model.buffers.at(uri.index).uri) = uri.as_written;
  for (size_t buffer : fallbacks) {
    asset.model.buffers.at(buffer).uri.clear();
    asset.model.buffers.at(buffer).data.clear();
  }
  for (const auto& [where, indices] : hidden.entries)
    asset.model.meshes.at(where.first).primitives.at(where.second).indices = indices;
  return asset;
}

}  // namespace gltf_pbr
