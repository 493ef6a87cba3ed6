// Saving: tinygltf serialises the document; buffers and images are laid out here so that
// untouched bytes are written back as they were and every file lands atomically.
#include <algorithm>
#include <cctype>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <tuple>

#include "core/accessor.hpp"
#include "core/asset.hpp"
#include "core/error.hpp"
#include "core/meshopt.hpp"

namespace gltf_pbr {
namespace {

bool has_extension(const fs::path& path, const char* extension) {
  std::string actual = path.extension().string();
  std::transform(actual.begin(), actual.end(), actual.begin(), [](unsigned char c) { return std::tolower(c); });
  return actual == extension;
}

// An absolute path, or a relative one that climbs out of its folder ("../x", "a/../../x").
bool leaves_folder(const fs::path& relative) {
  const fs::path normal = relative.lexically_normal();
  return normal.is_absolute() || (!normal.empty() && *normal.begin() == "..");
}

void pad_to_4(Bytes& bytes) { bytes.resize((bytes.size() + 3) & ~size_t{3}, 0); }

// GLB holds one BIN chunk: every buffer is merged into buffer 0 (bufferViews and the compressed
// sources of EXT_meshopt_compression shifted), and every image moves into a bufferView, so the
// .glb stands alone. Fallback buffers without bytes stay buffers of their own, after buffer 0
// (the extension's "Fallback buffers": index 1 or above in a GLB).
void gather_into_bin(Asset& asset) {
  tinygltf::Model& model = asset.model;
  if (model.buffers.empty()) model.buffers.emplace_back();
  std::vector<int> new_index(model.buffers.size(), 0);
  std::vector<size_t> base(model.buffers.size(), 0);
  std::vector<tinygltf::Buffer> placeholders;
  tinygltf::Buffer merged;  // keeps buffer 0's name, extras and extensions
  Bytes bin;
  for (size_t b = 0; b < model.buffers.size(); ++b) {
    if (is_meshopt_placeholder(model.buffers[b])) {
      placeholders.push_back(std::move(model.buffers[b]));
      new_index[b] = static_cast<int>(placeholders.size());
      continue;
    }
    if (b == 0) {
      bin = std::move(model.buffers[0].data);
      merged = std::move(model.buffers[0]);
      merged.uri.clear();
      continue;
    }
    pad_to_4(bin);
    base[b] = bin.size();
    bin.insert(bin.end(), model.buffers[b].data.begin(), model.buffers[b].data.end());
    // Bytes of other buffers (compressed sources among them) now share buffer 0: it is no
    // fallback any more, which the extension forbids as a source ("Fallback buffers").
    merged.extensions.erase("EXT_meshopt_compression");
  }
  auto moved = [&](int buffer, size_t offset) {
    const auto b = static_cast<size_t>(buffer);
    return b < new_index.size() ? std::pair{new_index[b], offset + base[b]} : std::pair{buffer, offset};
  };
  std::string problem;
  for (auto& view : model.bufferViews) {
    if (const auto compressed = meshopt_view(view, problem)) {
      const auto [buffer, offset] = moved(static_cast<int>(compressed->buffer), compressed->byte_offset);
      set_meshopt_source(view, buffer, offset);
    }
    std::tie(view.buffer, view.byteOffset) = moved(view.buffer, view.byteOffset);
  }
  if (model.buffers.size() > 1) {
    for (auto& mesh : model.meshes)
      for (auto& primitive : mesh.primitives)
        for (auto& [name, value] : primitive.extensions) remap_in_value(value, "buffer", new_index);
  }
  merged.data = std::move(bin);
  model.buffers.assign(1, std::move(merged));
  for (auto& placeholder : placeholders) model.buffers.push_back(std::move(placeholder));
  for (size_t i = 0; i < model.images.size(); ++i) {
    auto& image = model.images[i];
    if (image.bufferView >= 0) continue;
    if (image.mimeType.empty()) image.mimeType = has_extension(image.uri, ".png") ? "image/png" : "image/jpeg";
    image.bufferView = append_buffer_view(model, encoded_image_bytes(asset, static_cast<int>(i)));
    image.image.clear();
    image.uri.clear();
  }
}

// tinygltf 2.7 writes no extensions of buffers and bufferViews (EXT_meshopt_compression lives
// there): they are written here, from the document's values.
nlohmann::json json_of(const tinygltf::Value& value) {
  switch (value.Type()) {
    case tinygltf::BOOL_TYPE:
      return value.Get<bool>();
    case tinygltf::INT_TYPE:
      return value.Get<int>();
    case tinygltf::REAL_TYPE:
      return value.Get<double>();
    case tinygltf::STRING_TYPE:
      return value.Get<std::string>();
    case tinygltf::ARRAY_TYPE: {
      nlohmann::json array = nlohmann::json::array();
      for (const auto& element : value.Get<tinygltf::Value::Array>()) array.push_back(json_of(element));
      return array;
    }
    case tinygltf::OBJECT_TYPE: {
      nlohmann::json object = nlohmann::json::object();
      for (const auto& [key, member] : value.Get<tinygltf::Value::Object>()) object[key] = json_of(member);
      return object;
    }
    default:
      return nullptr;
  }
}

void write_extensions(const tinygltf::ExtensionMap& extensions, nlohmann::json& entry) {
  if (extensions.empty()) return;
  nlohmann::json& out = entry["extensions"];
  for (const auto& [name, value] : extensions) out[name] = json_of(value);
}

// A fallback placeholder's byteLength: large enough for every view it holds (the extension's
// "Fallback buffers"), and at least 1 (glTF 2.0 schema: buffer.byteLength >= 1).
std::uint64_t placeholder_byte_length(const tinygltf::Model& model, int buffer) {
  std::uint64_t length = 1;
  for (const auto& view : model.bufferViews)
    if (view.buffer == buffer)
      length = std::max<std::uint64_t>(length, view.byteLength > UINT64_MAX - view.byteOffset
                                                   ? UINT64_MAX
                                                   : view.byteOffset + view.byteLength);
  return length;
}

std::string mime_extension(const std::string& mime) {
  if (mime == "image/png") return ".png";
  if (mime == "image/jpeg") return ".jpg";
  if (mime == "image/webp") return ".webp";
  if (mime == "image/ktx2") return ".ktx2";
  return ".bin";
}

// A file name beside the output that no other output file and no input file takes.
class FileNamer {
 public:
  FileNamer(fs::path folder, std::set<fs::path> inputs) : folder_(std::move(folder)), inputs_(std::move(inputs)) {}
  bool is_input(const std::string& name) const { return inputs_.count(canonical(name)) > 0; }
  std::string claim(const std::string& wanted) {
    std::string name = wanted;
    const fs::path stem = fs::path(wanted).stem(), extension = fs::path(wanted).extension();
    for (int n = 1; taken_.count(name) || is_input(name); ++n)
      name = (fs::path(wanted).parent_path() / (stem.string() + "_" + std::to_string(n) + extension.string())).string();
    taken_.insert(name);
    return name;
  }
  void reserve(const std::string& name) { taken_.insert(name); }

 private:
  fs::path canonical(const std::string& name) const { return fs::weakly_canonical(folder_ / name); }
  fs::path folder_;
  std::set<fs::path> inputs_;
  std::set<std::string> taken_;
};

// A .gltf's JSON laid out as dump(2) lays it out, except that an array of numbers stays on one
// line: a matrix, an accessor's min and max or a colour factor reads as the vector it is, each in
// about a third of its bytes (BoxTexturedNonPowerOfTwo's JSON: 2,810 -> 2,434 bytes;
// bench/RESULTS.md, session 38).
void append_gltf_json(const nlohmann::json& value, int depth, std::string& out) {
  constexpr int kIndent = 2;
  const auto indent = [&](int level) { out.append(static_cast<size_t>(level * kIndent), ' '); };
  const bool numbers_only =
      value.is_array() && std::all_of(value.begin(), value.end(), [](const auto& v) { return v.is_number(); });
  if (value.empty() || !value.is_structured()) {
    out += value.dump();
  } else if (numbers_only) {
    out += '[';
    for (auto it = value.begin(); it != value.end(); ++it) out.append(it == value.begin() ? "" : ", ") += it->dump();
    out += ']';
  } else {
    out += value.is_object() ? "{\n" : "[\n";
    for (auto it = value.begin(); it != value.end(); ++it) {
      if (it != value.begin()) out += ",\n";
      indent(depth + 1);
      if (value.is_object()) out.append(nlohmann::json(it.key()).dump()) += ": ";
      append_gltf_json(*it, depth + 1, out);
    }
    out += '\n';
    indent(depth);
    out += value.is_object() ? '}' : ']';
  }
}

}  // namespace

Bytes glb_bytes(const std::string& json_text, std::span<const std::uint8_t> bin) {
  // glTF 2.0 section 4.4: 12-byte header, JSON chunk padded with spaces, BIN chunk with zeros.
  std::string json = json_text;
  json.resize((json.size() + 3) & ~size_t{3}, ' ');
  const size_t bin_padded = (bin.size() + 3) & ~size_t{3};
  const size_t total = 12 + 8 + json.size() + (bin.empty() ? 0 : 8 + bin_padded);
  if (total > 0xFFFFFFFFull) throw std::runtime_error("GLB over 4 GiB");
  Bytes out;
  out.reserve(total);
  auto put_u32 = [&](std::uint32_t v) {
    for (int k = 0; k < 4; ++k) out.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
  };
  for (char c : {'g', 'l', 'T', 'F'}) out.push_back(static_cast<std::uint8_t>(c));
  put_u32(2);
  put_u32(static_cast<std::uint32_t>(total));
  put_u32(static_cast<std::uint32_t>(json.size()));
  put_u32(0x4E4F534A);
  out.insert(out.end(), json.begin(), json.end());
  if (!bin.empty()) {
    put_u32(static_cast<std::uint32_t>(bin_padded));
    put_u32(0x004E4942);
    out.insert(out.end(), bin.begin(), bin.end());
    out.resize(total, 0);
  }
  return out;
}

std::vector<fs::path> save_asset(Asset& asset, const fs::path& output, bool replace_input) {
  tinygltf::Model& model = asset.model;
  const bool to_glb = has_extension(output, ".glb");
  const fs::path folder = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  const fs::path input_folder = asset.path.parent_path().empty() ? fs::path(".") : asset.path.parent_path();
  const std::string stem = output.stem().string();
  AtomicWriteSet files;

  // Input files this asset came from, named in it or read by its load (a converted asset may no
  // longer name the diffuse image it replaced): never overwritten.
  std::set<fs::path> inputs{fs::weakly_canonical(asset.path)};
  if (asset.resources)
    for (const fs::path& file : asset.resources->files_read()) inputs.insert(fs::weakly_canonical(file));
  for (const auto& buffer : model.buffers)
    if (!buffer.uri.empty() && !is_data_uri(buffer.uri))
      inputs.insert(fs::weakly_canonical(input_folder / percent_decode(buffer.uri)));
  for (const auto& image : model.images)
    if (!image.uri.empty() && !is_data_uri(image.uri))
      inputs.insert(fs::weakly_canonical(input_folder / percent_decode(image.uri)));
  const bool output_is_input = fs::weakly_canonical(output) == fs::weakly_canonical(asset.path);
  if (inputs.count(fs::weakly_canonical(output)) && !(replace_input && output_is_input))
    throw std::runtime_error("refusing to overwrite the input " + output.string());
  // Replacing a file its owner made read-only would defeat the point of making it so, root or not.
  if (replace_input && output_is_input && !writable_by_owner(output))
    throw std::runtime_error("refusing to replace " + output.string() + ": it is read-only (mode " + mode_text(output) +
                             ")");

  std::vector<std::string> buffer_uris(model.buffers.size());
  if (to_glb) {
    gather_into_bin(asset);
    buffer_uris.assign(model.buffers.size(), "");  // the BIN chunk, then fallback placeholders
  } else {
    FileNamer names(folder, inputs);
    const bool same_folder = fs::weakly_canonical(folder) == fs::weakly_canonical(input_folder);
    // An untouched external resource keeps its URI. Beside its input it needs no write at all;
    // elsewhere it is copied as is.
    auto place = [&](const std::string& uri, std::span<const std::uint8_t> bytes, const std::string& fallback) {
      if (is_data_uri(uri)) return uri;
      if (!uri.empty() && same_folder && names.is_input(percent_decode(uri))) {
        names.reserve(percent_decode(uri));
        return uri;
      }
      std::string wanted = uri.empty() ? fallback : percent_decode(uri);
      // A resource read from outside the input's folder (--allow-outside-uris) is written beside
      // the output under its file name, never outside the output's folder.
      if (leaves_folder(wanted))
        wanted = fs::path(wanted).filename().empty() ? fallback : fs::path(wanted).filename().string();
      const std::string name = names.claim(wanted);
      files.stage(folder / name, bytes);
      return uri.empty() || name != percent_decode(uri) ? name : uri;
    };
    for (size_t b = 0; b < model.buffers.size(); ++b)
      if (!is_meshopt_placeholder(model.buffers[b]))
        buffer_uris[b] =
            place(model.buffers[b].uri, model.buffers[b].data, stem + (b ? "_" + std::to_string(b) : "") + ".bin");
    // An image file keeps its mapping under the URI it is saved with (place() renames one read
    // from outside the folder or whose name is taken), so the saved asset still reads its bytes.
    std::map<std::string, std::shared_ptr<const MappedFile>> saved_files;
    for (size_t i = 0; i < model.images.size(); ++i) {
      auto& image = model.images[i];
      if (image.bufferView >= 0) continue;
      const auto file = asset.image_files.find(image.uri);
      const std::string name = image.name.empty() ? std::to_string(i) : image.name;
      image.uri = place(image.uri, encoded_image_bytes(asset, static_cast<int>(i)),
                        stem + "_" + name + mime_extension(image.mimeType));
      if (image.image.empty() && file != asset.image_files.end()) saved_files.emplace(image.uri, file->second);
    }
    asset.image_files = std::move(saved_files);
  }

  // tinygltf serialises everything but buffer payloads, which are swapped out meanwhile and
  // described by hand below (its stream writer would inline them as base64).
  std::vector<Bytes> payloads(model.buffers.size());
  for (size_t b = 0; b < model.buffers.size(); ++b) payloads[b].swap(model.buffers[b].data);
  std::ostringstream stream;
  tinygltf::TinyGLTF writer;
  writer.SetImageWriter(nullptr, nullptr);
  writer.WriteGltfSceneToStream(&model, stream, /*prettyPrint=*/!to_glb, /*writeBinary=*/false);
  for (size_t b = 0; b < model.buffers.size(); ++b) payloads[b].swap(model.buffers[b].data);

  nlohmann::json document = nlohmann::json::parse(stream.str());
  for (size_t b = 0; b < model.buffers.size(); ++b) {
    nlohmann::json& entry = document["buffers"][b];
    entry["byteLength"] = is_meshopt_placeholder(model.buffers[b])
                              ? placeholder_byte_length(model, static_cast<int>(b))
                              : model.buffers[b].data.size();
    if (buffer_uris[b].empty())
      entry.erase("uri");
    else
      entry["uri"] = buffer_uris[b];
    write_extensions(model.buffers[b].extensions, entry);
  }
  for (size_t v = 0; v < model.bufferViews.size(); ++v)
    write_extensions(model.bufferViews[v].extensions, document["bufferViews"][v]);

  Bytes main_file;
  if (to_glb) {
    main_file =
        glb_bytes(document.dump(), model.buffers.empty() ? std::span<const std::uint8_t>{}
                                                         : std::span<const std::uint8_t>(model.buffers[0].data));
  } else {
    std::string json;
    append_gltf_json(document, 0, json);
    json += '\n';
    main_file.assign(json.begin(), json.end());
  }
  files.stage(output, main_file);  // staged last, so it is renamed last
  return files.commit();
}

std::vector<fs::path> copy_asset_verbatim(const Asset& asset, const fs::path& output,
                                          std::optional<std::span<const std::uint8_t>> file_bytes) {
  if (fs::weakly_canonical(output) == fs::weakly_canonical(asset.path))
    throw std::runtime_error("refusing to overwrite the input " + output.string());
  AtomicWriteSet files;
  const fs::path folder = output.parent_path().empty() ? fs::path(".") : output.parent_path();
  const fs::path input_folder = asset.path.parent_path().empty() ? fs::path(".") : asset.path.parent_path();
  // A GLB may name external files too: they come along as a .gltf's do.
  if (fs::weakly_canonical(folder) != fs::weakly_canonical(input_folder)) {
    // A resource outside the input's folder (--allow-outside-uris) cannot keep its URI in a copy
    // elsewhere: save_asset writes it beside the output and rewrites the URI instead.
    auto outside = [](const std::string& uri) {
      return !uri.empty() && !is_data_uri(uri) && leaves_folder(percent_decode(uri));
    };
    if (std::any_of(asset.model.buffers.begin(), asset.model.buffers.end(),
                    [&](const auto& b) { return outside(b.uri); }) ||
        std::any_of(asset.model.images.begin(), asset.model.images.end(),
                    [&](const auto& i) { return outside(i.uri); })) {
      Asset copy = asset;
      return save_asset(copy, output);
    }
    // Each file through the mapping the load made (the asset's resources) instead of a second
    // read; read here only when there is none (an asset built without resources, a file that
    // could not be mapped).
    auto copy = [&](const std::string& uri) {
      if (uri.empty() || is_data_uri(uri)) return;
      const std::string relative = percent_decode(uri);
      const FileResources::External* mapped = asset.resources ? &asset.resources->external(uri) : nullptr;
      if (mapped && mapped->file) return files.stage(folder / relative, mapped->file->bytes());
      if (!mapped) ++work_counters().files_opened;  // external() counted it otherwise
      const auto bytes = read_file(input_folder / relative);
      if (!bytes) throw InputError(asset.path.string(), "",
                                    "cannot read " + uri + " to copy it: " + unreadable_reason(input_folder / relative));
      files.stage(folder / relative, *bytes);
    };
    for (const auto& buffer : asset.model.buffers) copy(buffer.uri);
    for (const auto& image : asset.model.images) copy(image.uri);
  }
  std::optional<Bytes> read;  // the file's bytes, when the caller has not read them
  if (!file_bytes) {
    ++work_counters().documents_read;
    read = read_file(asset.path);
    if (!read) throw InputError(asset.path.string(), "", "cannot read the file: " + unreadable_reason(asset.path));
  }
  files.stage(output, file_bytes ? *file_bytes : std::span<const std::uint8_t>(*read));
  return files.commit();
}

}  // namespace gltf_pbr
