// Document garbage collection after a step dropped references (DESIGN.md: emit no unused
// texture, image, sampler or extension).
#include <algorithm>
#include <functional>
#include <set>

#include "core/asset.hpp"
#include "core/error.hpp"
#include "core/meshopt.hpp"

namespace gltf_pbr {
namespace {

using tinygltf::Value;

// Extensions whose references to textures, images and bufferViews prune_unused understands.
bool references_are_known(const std::string& extension) {
  static const std::set<std::string> known = {"KHR_draco_mesh_compression",
                                              "KHR_mesh_quantization",
                                              "KHR_texture_transform",
                                              "KHR_lights_punctual",
                                              "KHR_texture_basisu",
                                              "EXT_texture_webp",
                                              "KHR_materials_variants",
                                              "EXT_mesh_gpu_instancing",
                                              "KHR_xmp_json_ld",
                                              "KHR_materials_pbrSpecularGlossiness",
                                              "EXT_meshopt_compression"};
  return known.count(extension) || extension.rfind("KHR_materials_", 0) == 0;
}

// Calls visit(int&) for every texture index a material holds, core slots and extensions
// (textureInfo objects sit under keys ending in "Texture", glTF 2.0 section 5.22).
void for_each_texture_index(tinygltf::Material& material, const std::function<void(int&)>& visit) {
  visit(material.pbrMetallicRoughness.baseColorTexture.index);
  visit(material.pbrMetallicRoughness.metallicRoughnessTexture.index);
  visit(material.normalTexture.index);
  visit(material.occlusionTexture.index);
  visit(material.emissiveTexture.index);
}

void collect_ints(const Value& value, const std::string& key, bool key_matches, std::vector<int>& out) {
  if (value.IsObject()) {
    for (const auto& [name, child] : value.Get<Value::Object>()) {
      const bool texture_info = key == "index" && name.size() >= 7 && name.ends_with("Texture");
      if (child.IsInt() && name == key && key_matches) out.push_back(child.GetNumberAsInt());
      collect_ints(child, key, key == "index" ? texture_info : true, out);
    }
  } else if (value.IsArray()) {
    for (const auto& child : value.Get<Value::Array>()) collect_ints(child, key, key_matches, out);
  }
}

std::vector<int> ints_in(const tinygltf::ExtensionMap& extensions, const std::string& key) {
  std::vector<int> out;
  for (const auto& [name, value] : extensions) collect_ints(value, key, key != "index", out);
  return out;
}

// Keeps the elements whose flag is set and returns old -> new indices (-1 for removed ones).
template <typename T>
std::vector<int> keep_flagged(std::vector<T>& items, const std::vector<bool>& keep) {
  std::vector<int> remap(items.size(), -1);
  std::vector<T> kept;
  for (size_t i = 0; i < items.size(); ++i)
    if (keep[i]) {
      remap[i] = static_cast<int>(kept.size());
      kept.push_back(std::move(items[i]));
    }
  items = std::move(kept);
  return remap;
}

int apply(const std::vector<int>& remap, int index) {
  return index >= 0 && static_cast<size_t>(index) < remap.size() ? remap[static_cast<size_t>(index)] : index;
}

}  // namespace

void remap_in_value(Value& value, const std::string& key, const std::vector<int>& remap) {
  if (value.IsObject()) {
    Value::Object object = value.Get<Value::Object>();
    for (auto& [name, child] : object) {
      if (name == key && child.IsInt())
        child = Value(apply(remap, child.GetNumberAsInt()));
      else
        remap_in_value(child, key, remap);
    }
    value = Value(std::move(object));
  } else if (value.IsArray()) {
    Value::Array array = value.Get<Value::Array>();
    for (auto& child : array) remap_in_value(child, key, remap);
    value = Value(std::move(array));
  }
}

PruneResult prune_unused(Asset& asset) {
  tinygltf::Model& model = asset.model;
  PruneResult result;
  for (const std::string& extension : model.extensionsUsed)
    if (!references_are_known(extension)) {
      asset.warnings.push_back("kept unused textures and images: extension " + extension +
                               " may reference them in ways this tool does not follow");
      return result;
    }

  // Textures: referenced by material slots and material extensions.
  std::vector<bool> texture_used(model.textures.size(), false);
  auto mark_texture = [&](int index) {
    if (index >= 0 && static_cast<size_t>(index) < texture_used.size()) texture_used[static_cast<size_t>(index)] = true;
  };
  for (auto& material : model.materials) {
    for_each_texture_index(material, [&](int& index) { mark_texture(index); });
    for (int index : ints_in(material.extensions, "index")) mark_texture(index);
  }
  const std::vector<int> texture_remap = keep_flagged(model.textures, texture_used);
  result.textures = static_cast<int>(std::count(texture_used.begin(), texture_used.end(), false));
  for (auto& material : model.materials) {
    for_each_texture_index(material, [&](int& index) { index = apply(texture_remap, index); });
    for (auto& [name, value] : material.extensions) remap_in_value(value, "index", texture_remap);
  }

  // Images and samplers: referenced by the remaining textures (and their extensions' "source").
  std::vector<bool> image_used(model.images.size(), false), sampler_used(model.samplers.size(), false);
  for (const auto& texture : model.textures) {
    std::vector<int> sources = ints_in(texture.extensions, "source");
    sources.push_back(texture.source);
    for (int source : sources)
      if (source >= 0 && static_cast<size_t>(source) < image_used.size())
        image_used[static_cast<size_t>(source)] = true;
    if (texture.sampler >= 0 && static_cast<size_t>(texture.sampler) < sampler_used.size())
      sampler_used[static_cast<size_t>(texture.sampler)] = true;
  }
  std::vector<int> released_views;
  for (size_t i = 0; i < model.images.size(); ++i)
    if (!image_used[i] && model.images[i].bufferView >= 0) released_views.push_back(model.images[i].bufferView);
  const std::vector<int> image_remap = keep_flagged(model.images, image_used);
  const std::vector<int> sampler_remap = keep_flagged(model.samplers, sampler_used);
  result.images = static_cast<int>(std::count(image_used.begin(), image_used.end(), false));
  result.samplers = static_cast<int>(std::count(sampler_used.begin(), sampler_used.end(), false));
  for (auto& texture : model.textures) {
    texture.source = apply(image_remap, texture.source);
    texture.sampler = apply(sampler_remap, texture.sampler);
    for (auto& [name, value] : texture.extensions) remap_in_value(value, "source", image_remap);
  }

  // BufferViews that only removed images used.
  if (released_views.empty()) return result;
  std::vector<bool> view_used(model.bufferViews.size(), false);
  auto mark_view = [&](int index) {
    if (index >= 0 && static_cast<size_t>(index) < view_used.size()) view_used[static_cast<size_t>(index)] = true;
  };
  for (const auto& accessor : model.accessors) {
    mark_view(accessor.bufferView);
    if (accessor.sparse.isSparse) {
      mark_view(accessor.sparse.indices.bufferView);
      mark_view(accessor.sparse.values.bufferView);
    }
  }
  for (const auto& image : model.images) mark_view(image.bufferView);
  for (const auto& mesh : model.meshes)
    for (const auto& primitive : mesh.primitives)
      for (int view : ints_in(primitive.extensions, "bufferView")) mark_view(view);
  for (int view : ints_in(model.extensions, "bufferView")) mark_view(view);
  // Views the asset never used before this step stay: only the released ones are ours to drop.
  std::vector<bool> keep_view(model.bufferViews.size(), true);
  for (int view : released_views)
    if (view >= 0 && static_cast<size_t>(view) < keep_view.size() && !view_used[static_cast<size_t>(view)])
      keep_view[static_cast<size_t>(view)] = false;
  result.buffer_views = static_cast<int>(std::count(keep_view.begin(), keep_view.end(), false));
  if (result.buffer_views == 0) return result;
  asset.decoded_views = {};  // keyed by view index, which changes below

  // Compact each buffer that lost a view: what stays (kept views, and the compressed sources of
  // EXT_meshopt_compression views) is copied in offset order, 4-byte aligned (glTF 2.0 section
  // 3.6.2.4: accessor offsets are multiples of their component size, at most 4). A fallback
  // placeholder has no bytes to compact.
  std::vector<bool> buffer_lost_view(model.buffers.size(), false), keep_buffer(model.buffers.size(), true);
  for (size_t i = 0; i < keep_view.size(); ++i)
    if (!keep_view[i] && model.bufferViews[i].buffer >= 0 &&
        static_cast<size_t>(model.bufferViews[i].buffer) < model.buffers.size())
      buffer_lost_view[static_cast<size_t>(model.bufferViews[i].buffer)] = true;
  // A malformed extension object has no range to keep: the buffer it names stays whole.
  std::vector<bool> named_by_malformed(model.buffers.size(), false);
  for (const auto& view : model.bufferViews) {
    std::string problem;
    if (const auto buffer = meshopt_source_buffer(view);
        buffer && *buffer < model.buffers.size() && !meshopt_view(view, problem))
      named_by_malformed[static_cast<size_t>(*buffer)] = true;
  }
  for (size_t b = 0; b < model.buffers.size(); ++b) {
    if (!buffer_lost_view[b] || is_meshopt_placeholder(model.buffers[b]) || named_by_malformed[b]) continue;
    struct Range {
      size_t view;
      bool compressed_source;
      std::uint64_t offset, length;
    };
    std::vector<Range> ranges;
    std::string problem;
    for (size_t i = 0; i < model.bufferViews.size(); ++i) {
      if (!keep_view[i]) continue;
      const auto& view = model.bufferViews[i];
      if (static_cast<size_t>(view.buffer) == b) ranges.push_back({i, false, view.byteOffset, view.byteLength});
      if (const auto source = meshopt_view(view, problem); source && static_cast<size_t>(source->buffer) == b)
        ranges.push_back({i, true, source->byte_offset, source->byte_length});
    }
    std::sort(ranges.begin(), ranges.end(), [](const Range& x, const Range& y) { return x.offset < y.offset; });
    const auto& data = model.buffers[b].data;
    Bytes compacted;
    for (const Range& range : ranges) {
      if (range.offset > data.size() || range.length > data.size() - range.offset)
        throw InputError(asset.path.string(),
                         pointer("bufferViews", static_cast<int>(range.view)) +
                             (range.compressed_source ? "/extensions/EXT_meshopt_compression" : ""),
                         "byteOffset " + std::to_string(range.offset) + " + byteLength " +
                             std::to_string(range.length) + " exceed its buffer's " + std::to_string(data.size()) +
                             " bytes");
      compacted.resize((compacted.size() + 3) & ~size_t{3}, 0);
      const size_t offset = compacted.size();
      compacted.insert(compacted.end(), data.begin() + static_cast<std::ptrdiff_t>(range.offset),
                       data.begin() + static_cast<std::ptrdiff_t>(range.offset + range.length));
      auto& view = model.bufferViews[range.view];
      if (range.compressed_source)
        set_meshopt_source(view, static_cast<int>(b), offset);
      else
        view.byteOffset = offset;
    }
    model.buffers[b].data = std::move(compacted);
    model.buffers[b].uri.clear();  // new bytes: save_asset names the file anew
    // A buffer that held only the released views goes too: glTF 2.0 requires byteLength >= 1.
    keep_buffer[b] = !ranges.empty();
  }
  const std::vector<int> view_remap = keep_flagged(model.bufferViews, keep_view);
  const std::vector<int> buffer_remap = keep_flagged(model.buffers, keep_buffer);
  result.buffers = static_cast<int>(std::count(keep_buffer.begin(), keep_buffer.end(), false));
  if (result.buffers > 0)
    for (auto& view : model.bufferViews) {
      // The compressed source's buffer, also where the object is malformed otherwise: it keeps
      // naming the buffer it named (kept whole above).
      if (const auto buffer = meshopt_source_buffer(view); buffer && *buffer < buffer_remap.size())
        set_meshopt_source_buffer(view, apply(buffer_remap, static_cast<int>(*buffer)));
      view.buffer = apply(buffer_remap, view.buffer);
    }
  for (auto& accessor : model.accessors) {
    accessor.bufferView = apply(view_remap, accessor.bufferView);
    if (accessor.sparse.isSparse) {
      accessor.sparse.indices.bufferView = apply(view_remap, accessor.sparse.indices.bufferView);
      accessor.sparse.values.bufferView = apply(view_remap, accessor.sparse.values.bufferView);
    }
  }
  for (auto& image : model.images) image.bufferView = apply(view_remap, image.bufferView);
  for (auto& mesh : model.meshes)
    for (auto& primitive : mesh.primitives)
      for (auto& [name, value] : primitive.extensions) remap_in_value(value, "bufferView", view_remap);
  return result;
}

}  // namespace gltf_pbr
