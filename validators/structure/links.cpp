// The link pass: every index resolves to an object of the right collection, accessors and buffer
// views fit what they view, and each object is used the way its referrers require (glTF 2.0 spec
// 3.6 "Binary Data Storage", 3.7 "Geometry", 3.8 "Texture Data", 3.11 "Animations"). Then the
// UNUSED_OBJECT pass over whatever nothing references.
#include <algorithm>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string_view>

#include "validators/structure/structure_internal.hpp"

namespace gltf_pbr::structure {

namespace {

std::string format_name(const std::string& type, int component_type, bool normalized = false) {
  std::string text = "{" + (type.empty() ? std::string("null") : type) + ", " +
                     (component_type == 0 ? "null" : component_type_name(component_type));
  if (normalized) text += " normalized";
  return text + "}";
}

// Bytes an accessor spans in its view: every element but the last takes a full stride; matrix
// columns of 1- and 2-byte components are padded to 4 bytes (spec 3.6.2.4 "Data Alignment").
std::int64_t element_size(const AccessorModel& accessor) {
  const int size = component_size(accessor.component_type);
  const int components = component_count(accessor.type);
  if (accessor.type.starts_with("MAT") && size < 4) {
    const int rows = accessor.type == "MAT2" ? 2 : accessor.type == "MAT3" ? 3 : 4;
    const int column = (rows * size + 3) / 4 * 4;
    return static_cast<std::int64_t>(column) * rows;
  }
  return static_cast<std::int64_t>(size) * components;
}

std::int64_t last_element_size(const AccessorModel& accessor) {
  const int size = component_size(accessor.component_type);
  if (accessor.type.starts_with("MAT") && size < 4) {
    const int rows = accessor.type == "MAT2" ? 2 : accessor.type == "MAT3" ? 3 : 4;
    const int column = (rows * size + 3) / 4 * 4;
    return static_cast<std::int64_t>(column) * (rows - 1) + rows * size;
  }
  return static_cast<std::int64_t>(size) * component_count(accessor.type);
}

// A buffer view's use besides the GL targets (34962 vertex data, 34963 index data), as the
// reference names them in BUFFER_VIEW_TARGET_OVERRIDE: inverse bind matrices, other accessor data
// (animations, sparse indices and values), and images.
constexpr int kViewUsageIbm = 1, kViewUsageOther = 2, kViewUsageImage = 3;

class Linker {
 public:
  explicit Linker(Context& context) : context_(context), issues_(context.issues), doc_(context.doc) {}

  // The reference links in dependency order: buffer views, accessors, images, textures,
  // materials, meshes, nodes, skins, animations, scenes.
  void run() {
    auto each = [](auto& list, auto&& link) {
      for (std::size_t i = 0; i < list.size(); ++i)
        if (list[i].object && list[i].valid) link(i);
    };
    each(doc_.buffers, [&](std::size_t i) { buffer(i); });
    // A buffer view missing a property is still linked (reference behaviour), unlike the rest.
    for (std::size_t i = 0; i < doc_.buffer_views.size(); ++i)
      if (doc_.buffer_views[i].object) buffer_view(i);
    each(doc_.accessors, [&](std::size_t i) { accessor(i); });
    each(doc_.images, [&](std::size_t i) { image(i); });
    each(doc_.textures, [&](std::size_t i) { texture(i); });
    each(doc_.materials, [&](std::size_t i) { material(i); });
    each(doc_.meshes, [&](std::size_t i) { mesh(i); });
    each(doc_.nodes, [&](std::size_t i) { node(i); });
    find_loops();
    for (std::size_t i = 0; i < doc_.skins.size(); ++i)  // linked even when invalid, as buffer views
      if (doc_.skins[i].object) skin(i);
    each(doc_.animations, [&](std::size_t i) { animation(i); });
    // The channels' KHR_animation_pointer objects after every animation is linked, before the
    // scenes (the reference's order, checked against the npm validator on constructed files).
    for (std::size_t i = 0; i < doc_.animations.size(); ++i)
      if (doc_.animations[i].object)
        for (std::size_t c = 0; c < doc_.animations[i].channels.size(); ++c) animation_pointer(i, c);
    for (std::size_t i = 0; i < doc_.scenes.size(); ++i) scene(i);
    node_graph();
  }

 private:
  template <typename Model>
  Model* resolve(std::vector<Model>& list, std::int64_t index, const std::string& pointer, bool mark_used = true) {
    if (index < 0) return nullptr;
    if (static_cast<std::size_t>(index) >= list.size() || !list[static_cast<std::size_t>(index)].object) {
      issues_.at("UNRESOLVED_REFERENCE", pointer, {arg(index)});
      return nullptr;
    }
    Model& model = list[static_cast<std::size_t>(index)];
    if (mark_used) model.used = true;
    return &model;
  }

  static std::string at(std::string_view collection, std::size_t index) {
    return "/" + std::string(collection) + "/" + std::to_string(index);
  }

  void accessor(std::size_t i) {
    AccessorModel& a = doc_.accessors[i];
    const std::string p = at("accessors", i);
    BufferViewModel* view = resolve(doc_.buffer_views, a.buffer_view, p + "/bufferView");
    const int size = component_size(a.component_type);
    // Spec 3.6.2.4 "Data Alignment": an accessor's offset is a multiple of its component size.
    if (a.has_byte_offset && size > 0 && a.byte_offset % size != 0)
      issues_.at("ACCESSOR_OFFSET_ALIGNMENT", p + "/byteOffset", {arg(a.byte_offset), arg(size)});
    // Misaligned data is not read (the reference checks no values of it).
    const bool aligned = !(a.has_byte_offset && size > 0 && a.byte_offset % size != 0);
    if (view && view->byte_offset >= 0 && size > 0 && !a.type.empty()) {
      std::int64_t total = 0;  // offsets come from the JSON: a sum beyond int64 is no real offset
      if (__builtin_add_overflow(view->byte_offset, a.byte_offset, &total))
        total = std::numeric_limits<std::int64_t>::max();
      const bool total_aligned = total % size == 0;
      if (!total_aligned) issues_.at("ACCESSOR_TOTAL_OFFSET_ALIGNMENT", p, {arg(total), arg(size)});
      const std::int64_t element = element_size(a);
      const bool stride_fits = !(view->byte_stride > 0 && view->byte_stride < element);
      if (!stride_fits) issues_.at("ACCESSOR_SMALL_BYTESTRIDE", p, {arg(view->byte_stride), arg(element)});
      // Data is read only from where it is known to be, element by element as declared.
      a.fits = aligned && total_aligned && stride_fits && !a.offset_unusable && a.count > 0 && view->byte_length > 0;
      const std::int64_t view_length = std::max<std::int64_t>(view->byte_length, 0);
      if (a.count > 0) {
        const std::int64_t stride = view->byte_stride > 0 ? view->byte_stride : element;
        // count ≤ 2^63 / stride is not guaranteed by the JSON: saturate instead of overflowing.
        const long double length = static_cast<long double>(stride) * static_cast<long double>(a.count - 1) +
                                   static_cast<long double>(last_element_size(a));
        if (static_cast<long double>(a.byte_offset) + length > static_cast<long double>(view_length)) {
          a.fits = false;
          issues_.at("ACCESSOR_TOO_LONG", a.byte_offset >= view_length ? p + "/byteOffset" : p,
                     {arg(a.byte_offset), arg(static_cast<std::int64_t>(std::min<long double>(length, 9e18L))),
                      arg(a.buffer_view), arg(view_length)});
        }
      }
    }
    if (a.sparse && a.count >= 0 && a.sparse_count > a.count)
      issues_.at("ACCESSOR_SPARSE_COUNT_OUT_OF_RANGE", p + "/sparse/count", {arg(a.sparse_count), arg(a.count)});
    if (a.sparse) {
      for (int part = 0; part < 2; ++part) {
        const std::string sp = p + (part == 0 ? "/sparse/indices" : "/sparse/values");
        const std::int64_t view_index = part == 0 ? a.sparse_indices_view : a.sparse_values_view;
        BufferViewModel* sparse_view = resolve(doc_.buffer_views, view_index, sp + "/bufferView");
        if (!sparse_view) continue;
        // Spec 3.6.2.3 "Sparse Accessors": the views hold neither vertex nor index data, so a
        // target is a conflicting use, and they are tightly packed, so a stride is invalid.
        use_view_as(view_index, kViewUsageOther, "Other", sp + "/bufferView");
        if (sparse_view->byte_stride > 0) issues_.at("BUFFER_VIEW_INVALID_BYTE_STRIDE", sp + "/bufferView");
        // Indices and values are aligned and fit their views like any accessor data (3.6.2.4),
        // sparse.count of each.
        const std::int64_t offset = part == 0 ? a.sparse_indices_offset : a.sparse_values_offset;
        const int component = part == 0 ? component_size(a.sparse_indices_component_type) : size;
        if (component > 0) {
          if (offset % component != 0)
            issues_.at("ACCESSOR_OFFSET_ALIGNMENT", sp + "/byteOffset", {arg(offset), arg(component)});
          std::int64_t total = 0;
          if (sparse_view->byte_offset >= 0 && !__builtin_add_overflow(sparse_view->byte_offset, offset, &total) &&
              total % component != 0)
            issues_.at("ACCESSOR_TOTAL_OFFSET_ALIGNMENT", sp, {arg(total), arg(component)});
        }
        const std::int64_t item = part == 0 ? component : element_size(a);
        if (item > 0 && a.sparse_count > 0) {
          const long double length = static_cast<long double>(item) * static_cast<long double>(a.sparse_count);
          const std::int64_t view_length = std::max<std::int64_t>(sparse_view->byte_length, 0);
          // Past the view's end (not at it, unlike an accessor's own offset) the offset is named.
          if (static_cast<long double>(offset) + length > static_cast<long double>(view_length))
            issues_.at("ACCESSOR_TOO_LONG", offset > view_length ? sp + "/byteOffset" : sp,
                       {arg(offset), arg(static_cast<std::int64_t>(std::min<long double>(length, 9e18L))),
                        arg(view_index), arg(view_length)});
        }
      }
    }
  }

  void animation(std::size_t i) {
    AnimationModel& animation = doc_.animations[i];
    const std::string p = at("animations", i);
    // The channels that target each (node, path as written), in order; "pointer" targets no node.
    std::map<std::pair<std::int64_t, std::string>, std::vector<std::size_t>> same_target;
    for (std::size_t c = 0; c < animation.channels.size(); ++c) {
      const AnimationChannelModel& channel = animation.channels[c];
      if (channel.object && channel.node >= 0 && !channel.raw_path.empty() && channel.raw_path != "pointer")
        same_target[{channel.node, channel.raw_path}].push_back(c);
    }
    for (std::size_t s = 0; s < animation.samplers.size(); ++s) {
      AnimationSamplerModel& sampler = animation.samplers[s];
      if (!sampler.object) continue;
      const std::string sp = p + "/samplers/" + std::to_string(s);
      if (AccessorModel* input = resolve(doc_.accessors, sampler.input, sp + "/input")) {
        use_accessor(*input, AccessorModel::Usage::AnimationInput, sp + "/input");
        if (input->usage == AccessorModel::Usage::AnimationInput) input->data_uses.push_back(sp + "/input");
        use_view_as(*input, kViewUsageOther, "Other", sp + "/input");
        // The view's stride is judged before the accessor's format, as for indices and matrices.
        stride_forbidden(*input, sp + "/input", "ANIMATION_SAMPLER_ACCESSOR_WITH_BYTESTRIDE");
        if (input->type != "SCALAR" || input->component_type != 5126 || input->normalized)
          issues_.at("ANIMATION_SAMPLER_INPUT_ACCESSOR_INVALID_FORMAT", sp + "/input",
                     {arg(format_name(input->type, input->component_type, input->normalized))},
                     {arg("{SCALAR, FLOAT}")});
        if (!input->has_min || !input->has_max)
          issues_.at("ANIMATION_SAMPLER_INPUT_ACCESSOR_WITHOUT_BOUNDS", sp + "/input");
        // A count that cannot be read (absent, not an integer, below 1) is -1 here, too few.
        if (sampler.interpolation == "CUBICSPLINE" && input->count < 2)
          issues_.at("ANIMATION_SAMPLER_INPUT_ACCESSOR_TOO_FEW_ELEMENTS", sp + "/input",
                     {arg("CUBICSPLINE"), arg(2), arg(input->count)});
      }
      if (AccessorModel* output = resolve(doc_.accessors, sampler.output, sp + "/output")) {
        // The sampler puts its output to use (an override is reported here, as the reference does);
        // the data checks report at every channel that reads it with the first one's path.
        use_accessor(*output, AccessorModel::Usage::AnimationOutput, sp + "/output");
        // The reference marks an output's view twice, so an override is reported twice (odd, but
        // what it does on constructed files, with or without channels using the sampler).
        use_view_as(*output, kViewUsageOther, "Other", sp + "/output");
        use_view_as(*output, kViewUsageOther, "Other", sp + "/output");
        stride_forbidden(*output, sp + "/output", "ANIMATION_SAMPLER_ACCESSOR_WITH_BYTESTRIDE");
      }
    }
    for (std::size_t c = 0; c < animation.channels.size(); ++c) {
      AnimationChannelModel& channel = animation.channels[c];
      if (!channel.object) continue;
      const std::string cp = p + "/channels/" + std::to_string(c);
      NodeModel* node = resolve(doc_.nodes, channel.node, cp + "/target/node");
      AnimationSamplerModel* sampler = resolve(animation.samplers, channel.sampler, cp + "/sampler");
      const bool trs = channel.path == "translation" || channel.path == "rotation" || channel.path == "scale";
      if (node && trs && node->has_matrix) issues_.at("ANIMATION_CHANNEL_TARGET_NODE_MATRIX", cp + "/target");
      if (node && trs && node->skin >= 0 && node->mesh >= 0)
        issues_.at("ANIMATION_CHANNEL_TARGET_NODE_SKIN", cp + "/target/path");
      std::int64_t morph_targets = -1;
      if (node && channel.path == "weights") {
        morph_targets = 0;
        if (node->mesh >= 0 && static_cast<std::size_t>(node->mesh) < doc_.meshes.size())
          for (const auto& primitive : doc_.meshes[static_cast<std::size_t>(node->mesh)].primitives)
            morph_targets = std::max(morph_targets, primitive.targets);
        if (morph_targets <= 0) issues_.at("ANIMATION_CHANNEL_TARGET_NODE_WEIGHTS_NO_MORPHS", cp + "/target");
      }
      if (sampler && !channel.path.empty() && channel.path != "pointer")
        output_checks(*sampler, channel, cp, morph_targets);
      // Two channels may not drive the same property (spec 3.11 "Animations"), compared as written:
      // two channels with the same unknown path are duplicates too (the reference's answer). Every
      // pair is one issue, at its first channel; past the report's listing they are only counted,
      // so n channels on one target cost n, not n^2 / 2 messages.
      if (const auto group = same_target.find({channel.node, channel.raw_path}); group != same_target.end()) {
        const std::vector<std::size_t>& channels = group->second;
        const auto later = std::upper_bound(channels.begin(), channels.end(), c);
        for (auto other = later; other != channels.end(); ++other) {
          if (issues_.listing_full("ANIMATION_DUPLICATE_TARGETS")) {
            issues_.at_unlisted("ANIMATION_DUPLICATE_TARGETS", cp + "/target",
                                static_cast<std::uint64_t>(channels.end() - other));
            break;
          }
          issues_.at("ANIMATION_DUPLICATE_TARGETS", cp + "/target", {arg(static_cast<std::uint64_t>(*other))});
        }
      }
    }
    // Its samplers that no channel uses, as soon as its channels are linked (the reference's
    // order: before the next animation's issues, not among the other unused objects).
    for (std::size_t s = 0; s < animation.samplers.size(); ++s)
      if (animation.samplers[s].object && !animation.samplers[s].used)
        issues_.at("UNUSED_OBJECT", p + "/samplers/" + std::to_string(s));
  }

  // KHR_animation_pointer: validated only in part (INCOMPLETE_EXTENSION_SUPPORT); the target
  // names its property through the pointer, so it has no node and its path is "pointer".
  void animation_pointer(std::size_t a, std::size_t c) {
    const AnimationChannelModel& channel = doc_.animations[a].channels[c];
    if (!channel.object || !channel.pointer_extension) return;
    const std::string p =
        at("animations", a) + "/channels/" + std::to_string(c) + "/target/extensions/KHR_animation_pointer";
    issues_.at("INCOMPLETE_EXTENSION_SUPPORT", p);
    if (channel.target_has_node) issues_.at("KHR_ANIMATION_POINTER_ANIMATION_CHANNEL_TARGET_NODE", p);
    if (!channel.raw_path.empty() && channel.raw_path != "pointer")
      issues_.at("KHR_ANIMATION_POINTER_ANIMATION_CHANNEL_TARGET_PATH", p, {arg(channel.raw_path)});
  }

  void output_checks(AnimationSamplerModel& sampler, const AnimationChannelModel& channel, const std::string& cp,
                     std::int64_t morph_targets) {
    if (sampler.output < 0 || static_cast<std::size_t>(sampler.output) >= doc_.accessors.size()) return;
    AccessorModel& output = doc_.accessors[static_cast<std::size_t>(sampler.output)];
    if (!output.object) return;
    const std::string pointer = cp + "/sampler";
    auto is = [&](const char* type, int component_type, bool normalized) {
      return output.type == type && output.component_type == component_type && output.normalized == normalized;
    };
    bool valid = false;
    std::vector<MessageArg> allowed;
    if (channel.path == "translation" || channel.path == "scale") {
      valid = is("VEC3", 5126, false);
      allowed = {arg("{VEC3, FLOAT}")};
    } else if (channel.path == "rotation") {
      valid = is("VEC4", 5126, false) || is("VEC4", 5120, true) || is("VEC4", 5121, true) || is("VEC4", 5122, true) ||
              is("VEC4", 5123, true);
      allowed = {arg("{VEC4, FLOAT}"), arg("{VEC4, BYTE normalized}"), arg("{VEC4, UNSIGNED_BYTE normalized}"),
                 arg("{VEC4, SHORT normalized}"), arg("{VEC4, UNSIGNED_SHORT normalized}")};
    } else if (channel.path == "weights") {
      valid = is("SCALAR", 5126, false) || is("SCALAR", 5120, true) || is("SCALAR", 5121, true) ||
              is("SCALAR", 5122, true) || is("SCALAR", 5123, true);
      allowed = {arg("{SCALAR, FLOAT}"), arg("{SCALAR, BYTE normalized}"), arg("{SCALAR, UNSIGNED_BYTE normalized}"),
                 arg("{SCALAR, SHORT normalized}"), arg("{SCALAR, UNSIGNED_SHORT normalized}")};
    }
    if (!valid && !channel.path.empty())
      issues_.at("ANIMATION_SAMPLER_OUTPUT_ACCESSOR_INVALID_FORMAT", pointer,
                 {arg(format_name(output.type, output.component_type, output.normalized)), arg(""), arg(channel.path)},
                 allowed);
    if (sampler.input >= 0 && static_cast<std::size_t>(sampler.input) < doc_.accessors.size()) {
      const AccessorModel& input = doc_.accessors[static_cast<std::size_t>(sampler.input)];
      if (input.object && input.count > 0 && output.count > 0) {
        // In long double: counts come from the JSON and their product need not fit an int64.
        long double expected = static_cast<long double>(input.count) * (sampler.interpolation == "CUBICSPLINE" ? 3 : 1);
        if (channel.path == "weights") expected *= static_cast<long double>(std::max<std::int64_t>(morph_targets, 0));
        if (channel.path != "weights" || morph_targets > 0) {
          if (expected != static_cast<long double>(output.count))
            issues_.at("ANIMATION_SAMPLER_OUTPUT_ACCESSOR_INVALID_COUNT", pointer,
                       {arg(static_cast<std::int64_t>(std::min<long double>(expected, 9e18L))), arg(output.count)});
        }
      }
    }
    if (output.usage == AccessorModel::Usage::AnimationOutput && output.animation_path.empty()) {
      output.animation_path = channel.path;
      output.interpolation = sampler.interpolation;
      output.usage_pointer = pointer;
    }
    if (output.usage == AccessorModel::Usage::AnimationOutput && output.animation_path == channel.path)
      output.data_uses.push_back(pointer);
  }

  // An accessor serves one purpose (spec 3.6.2: its data is read as indices, vertex attributes,
  // matrices or keyframes); the first use fixes it and where the data checks report.
  void use_accessor(AccessorModel& accessor, AccessorModel::Usage usage, const std::string& pointer) {
    static const char* names[] = {"None", "VertexAttribute", "IndexBuffer", "AnimationInput", "AnimationOutput", "IBM",
                                  "Other"};
    if (accessor.usage == AccessorModel::Usage::None) {
      accessor.usage = usage;
      accessor.usage_pointer = pointer;
    } else if (accessor.usage != usage) {
      issues_.at("ACCESSOR_USAGE_OVERRIDE", pointer,
                 {arg(names[static_cast<int>(accessor.usage)]), arg(names[static_cast<int>(usage)])});
    }
  }

  // Indices, inverse bind matrices and animation data: no stride allowed. Whatever reads an
  // accessor also uses its buffer view, even when the accessor itself is not linked for missing a
  // property (the reference marks the view through its reader).
  void stride_forbidden(const AccessorModel& accessor, const std::string& pointer, const char* code) {
    if (accessor.buffer_view < 0 || static_cast<std::size_t>(accessor.buffer_view) >= doc_.buffer_views.size()) return;
    BufferViewModel& view = doc_.buffer_views[static_cast<std::size_t>(accessor.buffer_view)];
    if (!view.object) return;
    view.used = true;
    if (view.byte_stride > 0) issues_.at(code, pointer);
  }

  void buffer(std::size_t i) {
    BufferModel& buffer = doc_.buffers[i];
    // Spec 4.4.3.2: in a GLB, the first buffer without a uri is the BIN chunk (a missing one is
    // reported as the buffers are loaded, data.cpp).
    const bool glb_bin = context_.glb && i == 0 && !buffer.has_uri;
    // EXT_meshopt_compression "Fallback buffers": one with no data of its own can only be read
    // through the extension, which must then be required.
    const auto& required = doc_.extensions_required;
    if (buffer.meshopt_fallback && !buffer.has_uri && !glb_bin &&
        std::find(required.begin(), required.end(), "EXT_meshopt_compression") == required.end())
      issues_.at("MESHOPT_EXTENSION_NOT_REQUIRED", at("buffers", i));
  }

  void buffer_view(std::size_t i) {
    BufferViewModel& view = doc_.buffer_views[i];
    const std::string p = at("bufferViews", i);
    BufferModel* buffer = resolve(doc_.buffers, view.buffer, p + "/buffer");
    // A view that starts at or past the buffer's end does not fit whatever its length, even one
    // that cannot be read (the reference's rule); one that starts inside must end inside.
    if (buffer && buffer->byte_length > 0 && view.byte_offset >= 0 &&
        (view.byte_offset >= buffer->byte_length ||
         (view.byte_length > 0 &&
          static_cast<long double>(view.byte_offset) + static_cast<long double>(view.byte_length) >
              static_cast<long double>(buffer->byte_length))))
      issues_.at("BUFFER_VIEW_TOO_LONG",
                 view.byte_offset >= buffer->byte_length ? p + "/byteOffset" : p + "/byteLength",
                 {arg(view.buffer), arg(buffer->byte_length)});
    if (buffer && buffer->meshopt_fallback && !view.meshopt_present)
      issues_.at("MESHOPT_FALLBACK_UNCOMPRESSED_VIEW", p + "/buffer", {arg(view.buffer)});
    if (view.meshopt) meshopt_source(view, p + "/extensions/EXT_meshopt_compression");
  }

  // EXT_meshopt_compression: the compressed bytes' buffer and range, and the layout rules of the
  // extension's README ("For the extension object to be valid").
  void meshopt_source(const BufferViewModel& view, const std::string& p) {
    const MeshoptView& m = *view.meshopt;
    if (BufferModel* source = resolve(doc_.buffers, m.buffer, p + "/buffer")) {
      if (source->meshopt_fallback) issues_.at("MESHOPT_FALLBACK_AS_SOURCE", p + "/buffer", {arg(m.buffer)});
      const auto length = static_cast<std::uint64_t>(source->byte_length);
      if (source->byte_length > 0 && (m.byte_offset > length || m.byte_length > length - m.byte_offset))
        issues_.at("BUFFER_VIEW_TOO_LONG", m.byte_offset >= length ? p + "/byteOffset" : p + "/byteLength",
                   {arg(m.buffer), arg(source->byte_length)});
    }
    if (view.byte_length > 0) {
      const std::string problem = meshopt_layout_problem(m, static_cast<std::uint64_t>(view.byte_length),
                                                         static_cast<std::uint64_t>(view.byte_stride));
      if (!problem.empty()) issues_.at("MESHOPT_INVALID_LAYOUT", p, {arg_raw(problem)});
    }
  }

  void image(std::size_t i) {
    ImageModel& image = doc_.images[i];
    const std::string p = at("images", i);
    if (BufferViewModel* view = resolve(doc_.buffer_views, image.buffer_view, p + "/bufferView")) {
      use_view_as(image.buffer_view, kViewUsageImage, "Image", p + "/bufferView");  // a target is another use
      if (view->byte_stride > 0) issues_.at("IMAGE_BUFFER_VIEW_WITH_BYTESTRIDE", p + "/bufferView");
    }
  }

  void material(std::size_t i) {
    const MaterialModel& material = doc_.materials[i];
    for (const TextureRef& ref : material.textures) resolve(doc_.textures, ref.index, ref.pointer + "/index");
    for (const auto& [code, pointer] : material.extension_issues) issues_.at(code, pointer);
  }

  const BufferViewModel* view_of(const AccessorModel& accessor) const {
    if (accessor.buffer_view < 0 || static_cast<std::size_t>(accessor.buffer_view) >= doc_.buffer_views.size())
      return nullptr;
    const BufferViewModel& view = doc_.buffer_views[static_cast<std::size_t>(accessor.buffer_view)];
    return view.object ? &view : nullptr;
  }

  void use_view_as(AccessorModel& accessor, int usage, const std::string& name, const std::string& pointer) {
    use_view_as(accessor.buffer_view, usage, name, pointer);
  }
  // The use of view `index` (a GL target or a kViewUsage value) at `pointer`: the first
  // use sets it; another one is reported as an override.
  void use_view_as(std::int64_t index, int usage, const std::string& name, const std::string& pointer) {
    if (index < 0 || static_cast<std::size_t>(index) >= doc_.buffer_views.size()) return;
    BufferViewModel& view = doc_.buffer_views[static_cast<std::size_t>(index)];
    if (!view.object) return;
    view.used = true;  // even through an accessor that is not linked itself (one missing a property)
    if (view.usage_target == 0) {
      view.usage_target = usage;
      view.usage_name = name;
      // Only vertex and index data need a target (other data has none to set).
      if (view.target == 0 && (usage == 34962 || usage == 34963)) issues_.at("BUFFER_VIEW_TARGET_MISSING", pointer);
    } else if (view.usage_target != usage) {
      issues_.at("BUFFER_VIEW_TARGET_OVERRIDE", pointer, {arg(view.usage_name), arg(name)});
    }
  }

  // Spec 3.6.2.4: each vertex attribute element starts on a 4-byte boundary: the accessor's
  // offset, and without a stride (strides are multiples of 4 by the schema) the element size.
  void vertex_alignment(const AccessorModel& accessor, const BufferViewModel& view, const std::string& pointer) {
    const int size = component_size(accessor.component_type);
    const std::int64_t element = static_cast<std::int64_t>(size) * component_count(accessor.type);
    if (size > 0 && (accessor.byte_offset % 4 != 0 || (view.byte_stride == 0 && element % 4 != 0)))
      issues_.at("MESH_PRIMITIVE_ACCESSOR_UNALIGNED", pointer);
  }

  void vertex_attribute(AccessorModel& accessor, const std::string& name, const std::string& pointer) {
    use_view_as(accessor, 34962, "VertexBuffer", pointer);
    if (name == "POSITION" && (!accessor.has_min || !accessor.has_max))
      issues_.at("MESH_PRIMITIVE_POSITION_ACCESSOR_WITHOUT_BOUNDS", pointer);
    // A semantic with a format table gets INVALID_FORMAT for UNSIGNED_INT like any other format
    // outside it; UNSIGNED_INT is the code for attributes the spec gives no table (custom ones).
    if (!attribute_format(accessor, name, pointer) && accessor.component_type == 5125)
      issues_.at("MESH_PRIMITIVE_ATTRIBUTES_ACCESSOR_UNSIGNED_INT", pointer);
    if (const BufferViewModel* view = view_of(accessor)) {
      vertex_alignment(accessor, *view, pointer);
      shared_view_stride(accessor, *view, pointer);
    }
  }

  // Spec 3.6.2.3: vertex attributes that share a buffer view need its byteStride. Said at each
  // accessor that joins a view without one after another (the reference's rule, checked on
  // constructed files: base and morph target attributes alike, each new accessor once).
  void shared_view_stride(const AccessorModel& accessor, const BufferViewModel& view, const std::string& pointer) {
    const auto accessor_index = static_cast<std::int64_t>(&accessor - doc_.accessors.data());
    auto& users = view_accessors_[accessor.buffer_view];
    if (std::find(users.begin(), users.end(), accessor_index) != users.end()) return;
    users.push_back(accessor_index);
    if (view.byte_stride == 0 && users.size() > 1) issues_.at("MESH_PRIMITIVE_ACCESSOR_WITHOUT_BYTESTRIDE", pointer);
  }

  // Spec 3.7.2.1 (attributes) and 3.7.2.2 (morph targets), widened by KHR_mesh_quantization's tables.
  // A target holds displacements: TANGENT is a VEC3 without the handedness, and texture coordinates
  // and colours may also be signed; joints and weights have no table there (3.7.2.2 lists none).
  // Returns whether the semantic has a table.
  bool attribute_format(AccessorModel& accessor, const std::string& name, const std::string& pointer,
                        bool morph_target = false) {
    const bool quantized = context_.declared("KHR_mesh_quantization");
    std::vector<std::tuple<const char*, int, bool>> allowed;
    auto normalized_types = [&](const char* type, std::initializer_list<int> components) {
      for (int ct : components) allowed.push_back({type, ct, true});
    };
    if (name == "POSITION" || name == "NORMAL" || name == "TANGENT") {
      const char* type = name == "TANGENT" && !morph_target ? "VEC4" : "VEC3";
      allowed.push_back({type, 5126, false});
      if (quantized && name == "POSITION") {
        for (int ct : {5120, 5121, 5122, 5123})
          if (!morph_target || ct == 5120 || ct == 5122)  // a displacement is signed
            allowed.push_back({type, ct, false}), allowed.push_back({type, ct, true});
      } else if (quantized) {
        normalized_types(type, {5120, 5122});
      }
    } else if (name.starts_with("TEXCOORD_")) {
      allowed = {{"VEC2", 5126, false}};
      if (morph_target)
        normalized_types("VEC2", {5120, 5121, 5122, 5123});
      else
        normalized_types("VEC2", {5121, 5123});
      if (quantized && morph_target)
        for (int ct : {5120, 5122}) allowed.push_back({"VEC2", ct, false});
      else if (quantized)
        for (int ct : {5120, 5121, 5122, 5123})
          allowed.push_back({"VEC2", ct, false}), allowed.push_back({"VEC2", ct, true});
    } else if (name.starts_with("COLOR_")) {
      for (const char* type : {"VEC3", "VEC4"}) {
        allowed.push_back({type, 5126, false});
        if (morph_target)
          normalized_types(type, {5120, 5121, 5122, 5123});
        else
          normalized_types(type, {5121, 5123});
      }
    } else if (morph_target) {
      return false;
    } else if (name.starts_with("JOINTS_")) {
      allowed = {{"VEC4", 5121, false}, {"VEC4", 5123, false}};
    } else if (name.starts_with("WEIGHTS_")) {
      allowed = {{"VEC4", 5126, false}, {"VEC4", 5121, true}, {"VEC4", 5123, true}};
    } else {
      return false;
    }
    for (const auto& [type, ct, normalized] : allowed)
      if (accessor.type == type && accessor.component_type == ct && accessor.normalized == normalized) return true;
    if (!morph_target && (accessor.usage == AccessorModel::Usage::None || accessor.semantic == name))
      accessor.semantic_format_invalid = true;
    std::vector<MessageArg> list;
    for (const auto& [type, ct, normalized] : allowed) list.push_back(arg(format_name(type, ct, normalized)));
    issues_.at("MESH_PRIMITIVE_ATTRIBUTES_ACCESSOR_INVALID_FORMAT", pointer,
               {arg(format_name(accessor.type, accessor.component_type, accessor.normalized))}, list);
    return true;
  }

  void mesh(std::size_t i) {
    MeshModel& mesh = doc_.meshes[i];
    for (PrimitiveModel& primitive : mesh.primitives) {
      if (!primitive.object) continue;
      const std::string& p = primitive.pointer;
      std::int64_t vertex_count = -1;
      bool has_normal = false, has_tangent = false;
      for (const auto& [name, index] : primitive.attributes) {
        const std::string ap = p + "/attributes/" + escape_pointer_token(name);
        if (name == "NORMAL") has_normal = true;
        if (name == "TANGENT") has_tangent = true;
        AccessorModel* accessor = resolve(doc_.accessors, index, ap);
        if (!accessor) continue;
        vertex_attribute(*accessor, name, ap);
        if (accessor->usage == AccessorModel::Usage::None) accessor->semantic = name;
        use_accessor(*accessor, AccessorModel::Usage::Vertex, ap);
        if (accessor->usage == AccessorModel::Usage::Vertex && accessor->semantic == name)
          accessor->data_uses.push_back(ap);
        // The first accessor with a usable count sets the vertex count; a later one without a
        // usable count (-1) differs from it, as in the reference.
        if (vertex_count < 0) {
          vertex_count = accessor->count;
        } else if (vertex_count != accessor->count) {
          issues_.at("MESH_PRIMITIVE_UNEQUAL_ACCESSOR_COUNT", ap);
        }
      }
      std::set<std::int64_t> used_sets;
      // Each texture binding of a material needs its TEXCOORD_n here.
      auto texture_coordinates = [&](const MaterialModel& bound, const std::string& pointer) {
        // Each set a binding needs (TextureRef: its own, and a texture transform's override).
        const auto need = [&](std::int64_t set, const std::string& binding) {
          if (set < 0) return;
          used_sets.insert(set);
          const std::string wanted = "TEXCOORD_" + std::to_string(set);
          const bool present = std::any_of(primitive.attributes.begin(), primitive.attributes.end(),
                                           [&](const auto& attribute) { return attribute.first == wanted; });
          if (!present) issues_.at("MESH_PRIMITIVE_TOO_FEW_TEXCOORDS", pointer, {arg(binding), arg(set)});
        };
        for (const TextureRef& ref : bound.textures) {
          need(ref.tex_coord, ref.pointer);
          need(ref.transform_tex_coord, ref.pointer + "/extensions/KHR_texture_transform");
        }
      };
      // KHR_materials_variants: each mapping is linked in turn (its dependency on the root's
      // variants, its variants, which no other mapping of the primitive may repeat, and its
      // material), after the attributes and before the indices, as in the reference.
      std::set<std::int64_t> mapped_variants;
      for (const PrimitiveModel::VariantMapping& mapping : primitive.variant_mappings) {
        if (!doc_.has_variants_root) {
          issues_.at("UNSATISFIED_DEPENDENCY", mapping.pointer, {arg("/extensions/KHR_materials_variants")});
          continue;
        }
        for (const auto& [pointer, variant] : mapping.variants) {
          if (!mapped_variants.insert(variant).second) issues_.at("KHR_MATERIALS_VARIANTS_NON_UNIQUE_VARIANT", pointer);
          resolve(doc_.variants, variant, pointer);
        }
        if (MaterialModel* variant_material = resolve(doc_.materials, mapping.material, mapping.material_pointer))
          texture_coordinates(*variant_material, mapping.material_pointer);
      }
      if (AccessorModel* indices = resolve(doc_.accessors, primitive.indices, p + "/indices")) {
        const bool valid = indices->has_index_format();
        // As the reference: the uses first (accessor, then buffer view), the view's stride, then the format.
        use_accessor(*indices, AccessorModel::Usage::Index, p + "/indices");
        use_view_as(*indices, 34963, "IndexBuffer", p + "/indices");
        stride_forbidden(*indices, p + "/indices", "MESH_PRIMITIVE_INDICES_ACCESSOR_WITH_BYTESTRIDE");
        if (!valid)
          issues_.at("MESH_PRIMITIVE_INDICES_ACCESSOR_INVALID_FORMAT", p + "/indices",
                     {arg(format_name(indices->type, indices->component_type, indices->normalized))},
                     {arg("{SCALAR, UNSIGNED_BYTE}"), arg("{SCALAR, UNSIGNED_SHORT}"), arg("{SCALAR, UNSIGNED_INT}")});
        // A primitive without attributes has no vertices: every index is out of range. The index
        // data of a primitive whose mode cannot be read is still read as triangles, the default
        // mode (the reference reports their degenerate triangles).
        indices->index_uses.push_back(
            {p + "/indices", primitive.attributes.empty() ? 0 : vertex_count, primitive.mode < 0 ? 4 : primitive.mode});
        incompatible_mode(primitive, indices->count, p);
      } else if (primitive.indices < 0 && vertex_count > 0) {
        incompatible_mode(primitive, vertex_count, p);
      }
      MaterialModel* material = resolve(doc_.materials, primitive.material, p + "/material");
      if (material) {
        if ((material->has_normal_texture || material->needs_tangents) && !(has_normal && has_tangent)) {
          issues_.at(material->has_normal_texture ? "MESH_PRIMITIVE_GENERATED_TANGENT_SPACE"
                                                  : "MESH_PRIMITIVE_NO_TANGENT_SPACE",
                     p + "/material");
        }
        texture_coordinates(*material, p + "/material");
      }
      if (has_tangent && (!material || !(material->has_normal_texture || material->needs_tangents)))
        issues_.at("UNUSED_MESH_TANGENT", p + "/attributes/TANGENT");
      // TEXCOORD_0 .. TEXCOORD_{n-1}, n the number of texture coordinate sets, that no binding reads;
      // sets that are not numbered from 0 without a gap are already in error, and judged no further.
      std::int64_t sets = 0, last_set = -1;
      for (const auto& [name, index] : primitive.attributes)
        if (const std::optional<int> set = set_number(name, "TEXCOORD_"))
          ++sets, last_set = std::max<std::int64_t>(last_set, *set);
      for (std::int64_t set = 0; set < sets && last_set == sets - 1; ++set) {
        const std::string name = "TEXCOORD_" + std::to_string(set);
        const bool present = std::any_of(primitive.attributes.begin(), primitive.attributes.end(),
                                         [&](const auto& attribute) { return attribute.first == name; });
        if (present && !used_sets.contains(set)) issues_.at("UNUSED_OBJECT", p + "/attributes/" + name);
      }
      for (std::size_t t = 0; t < primitive.target_attributes.size(); ++t) {
        for (const auto& [name, index] : primitive.target_attributes[t]) {
          const std::string tp = p + "/targets/" + std::to_string(t) + "/" + escape_pointer_token(name);
          const std::string& semantic = name;  // C++20 lambdas may not capture a structured binding in clang 14
          // In the reference's order: the buffer view's use, the base, then the accessor's checks.
          AccessorModel* accessor = resolve(doc_.accessors, index, tp);
          if (accessor) use_view_as(*accessor, 34962, "VertexBuffer", tp);
          // A target attribute that resolves needs a base attribute of its semantic that resolves
          // too (spec 3.7.2.2: a target displaces its base's values); one that does not resolve is
          // only unresolved.
          const bool in_base =
              std::any_of(primitive.attributes.begin(), primitive.attributes.end(), [&](const auto& attribute) {
                return attribute.first == semantic && accessor_object(doc_, attribute.second) != nullptr;
              });
          if (accessor && !in_base) issues_.at("MESH_PRIMITIVE_MORPH_TARGET_NO_BASE_ACCESSOR", tp);
          if (!accessor) continue;
          // Against the base accessor of the same semantic, an unknown count (-1) included; then
          // a target POSITION's bounds (the reference's order, unlike a base POSITION's).
          for (const auto& [base_name, base_index] : primitive.attributes)
            if (base_name == semantic)
              if (const AccessorModel* base = accessor_object(doc_, base_index); base && base->count != accessor->count)
                issues_.at("MESH_PRIMITIVE_MORPH_TARGET_INVALID_ATTRIBUTE_COUNT", tp);
          if (name == "POSITION" && (!accessor->has_min || !accessor->has_max))
            issues_.at("MESH_PRIMITIVE_POSITION_ACCESSOR_WITHOUT_BOUNDS", tp);
          attribute_format(*accessor, name, tp, /*morph_target=*/true);
          if (const BufferViewModel* view = view_of(*accessor)) {
            vertex_alignment(*accessor, *view, tp);
            shared_view_stride(*accessor, *view, tp);
          }
        }
      }
      if (primitive.draco)
        resolve(doc_.buffer_views, primitive.draco_buffer_view,
                p + "/extensions/KHR_draco_mesh_compression/bufferView");
    }
  }

  // The vertex count each topology needs (glTF 2.0 §3.7.2.1): at least `minimum`, and a multiple of
  // `multiple`. A mode outside 0-6 is the schema's to report.
  void incompatible_mode(const PrimitiveModel& primitive, std::int64_t count, const std::string& pointer) {
    if (count <= 0 || primitive.mode < 0 || primitive.mode > 6) return;  // unknown count: nothing to compare
    struct Topology {
      const char* name;
      std::int64_t minimum, multiple;
    };
    static constexpr Topology kTopologies[] = {{"POINTS", 1, 1},      {"LINES", 2, 2},     {"LINE_LOOP", 2, 1},
                                               {"LINE_STRIP", 2, 1},  {"TRIANGLES", 3, 3}, {"TRIANGLE_STRIP", 3, 1},
                                               {"TRIANGLE_FAN", 3, 1}};
    const Topology& topology = kTopologies[primitive.mode];
    if (count < topology.minimum || count % topology.multiple != 0)
      issues_.at("MESH_PRIMITIVE_INCOMPATIBLE_MODE", pointer, {arg(count), arg(topology.name)});
  }

  void node(std::size_t i) {
    NodeModel& node = doc_.nodes[i];
    const std::string p = at("nodes", i);
    if (resolve(doc_.cameras, node.camera, p + "/camera")) node.empty = false;
    SkinModel* skin = resolve(doc_.skins, node.skin, p + "/skin");
    MeshModel* mesh = resolve(doc_.meshes, node.mesh, p + "/mesh");
    if (mesh) node.empty = false;
    if (mesh && mesh->valid) {  // a mesh dropped for its schema errors has nothing to compare
      std::int64_t targets = 0;
      bool skinned = false;  // a primitive holds what a skin binds (PrimitiveModel::skinned)
      for (const auto& primitive : mesh->primitives) {
        targets = std::max(targets, primitive.targets);
        skinned = skinned || primitive.skinned;
      }
      if (node.weights >= 0 && mesh->primitives_known && node.weights != targets)
        issues_.at("NODE_WEIGHTS_INVALID", p + "/weights", {arg(node.weights), arg(targets)});
      if (skinned && !skin) issues_.at("NODE_SKINNED_MESH_WITHOUT_SKIN", p);  // absent or unresolved
      if (skinned && skin && !skin->joints.empty()) {                         // a skin without joints bounds nothing
        mesh->skin = node.skin;
        mesh->joint_count = static_cast<std::int64_t>(skin->joints.size());
      }
      if (!skinned && skin) issues_.at("NODE_SKIN_WITH_NON_SKINNED_MESH", p);
    }
    for (std::size_t c = 0; c < node.children.size(); ++c) {
      const std::int64_t child = node.children[c];
      NodeModel* child_node = resolve(doc_.nodes, child, p + "/children/" + std::to_string(c));
      if (!child_node) continue;
      if (child_node->parent >= 0)
        issues_.at("NODE_PARENT_OVERRIDE", p + "/children/" + std::to_string(c), {arg(child)});
      else
        child_node->parent = static_cast<std::int64_t>(i);
    }
    // Without the root KHR_lights_punctual object the dependency error stands alone.
    if (!node.light_pointer.empty() && !doc_.has_lights_root)
      issues_.at("UNSATISFIED_DEPENDENCY", node.light_pointer, {arg("/extensions/KHR_lights_punctual")});
    if (node.light >= 0 && doc_.has_lights_root)
      resolve(doc_.lights, node.light, p + "/extensions/KHR_lights_punctual/light");
  }

  void scene(std::size_t s) {
    const std::string p = at("scenes", s) + "/nodes/";
    const auto& nodes = doc_.scenes[s].nodes;
    for (std::size_t k = 0; k < nodes.size(); ++k) {
      NodeModel* node = resolve(doc_.nodes, nodes[k], p + std::to_string(k));
      if (node && node->parent >= 0) issues_.at("SCENE_NON_ROOT_NODE", p + std::to_string(k), {arg(nodes[k])});
    }
  }

  void skin(std::size_t i) {
    SkinModel& skin = doc_.skins[i];
    const std::string p = at("skins", i);
    for (std::size_t j = 0; j < skin.joints.size(); ++j) {
      if (NodeModel* joint = resolve(doc_.nodes, skin.joints[j], p + "/joints/" + std::to_string(j)))
        joint->joint = true;
    }
    const std::vector<std::int64_t> roots = common_roots(skin);
    skin.has_common_root = !roots.empty();
    if (!skin.joints.empty() && roots.empty()) issues_.at("SKIN_NO_COMMON_ROOT", p + "/joints");
    if (AccessorModel* ibm = resolve(doc_.accessors, skin.inverse_bind_matrices, p + "/inverseBindMatrices")) {
      use_accessor(*ibm, AccessorModel::Usage::InverseBindMatrices, p + "/inverseBindMatrices");
      use_view_as(*ibm, kViewUsageIbm, "IBM", p + "/inverseBindMatrices");
      stride_forbidden(*ibm, p + "/inverseBindMatrices", "SKIN_IBM_ACCESSOR_WITH_BYTESTRIDE");
      if (ibm->type != "MAT4" || ibm->component_type != 5126)
        issues_.at("SKIN_IBM_INVALID_FORMAT", p + "/inverseBindMatrices",
                   {arg(format_name(ibm->type, ibm->component_type, ibm->normalized))}, {arg("{MAT4, FLOAT}")});
      if (ibm->count < static_cast<std::int64_t>(skin.joints.size()))  // an unknown count (-1) too
        issues_.at("INVALID_IBM_ACCESSOR_COUNT", p + "/inverseBindMatrices",
                   {arg(static_cast<std::uint64_t>(skin.joints.size())), arg(ibm->count)});
    }
    // A skeleton names a node without putting it into use (reference behaviour; joints do).
    // Spec 3.7.3.1: when defined, it is the common root of the joints' hierarchy.
    // Without a common root no skeleton can be one.
    if (resolve(doc_.nodes, skin.skeleton, p + "/skeleton", false) &&
        std::find(roots.begin(), roots.end(), skin.skeleton) == roots.end())
      issues_.at("SKIN_SKELETON_INVALID", p + "/skeleton");
  }

  void texture(std::size_t i) {
    TextureModel& texture = doc_.textures[i];
    const std::string p = at("textures", i);
    // Its image's MIME type is judged once the images are read (check_texture_sources).
    resolve(doc_.images, texture.source, p + "/source");
    resolve(doc_.samplers, texture.sampler, p + "/sampler");
    for (const auto& [pointer, index] : texture.extension_sources) resolve(doc_.images, index, pointer);
  }

  // Spec, "Nodes and Hierarchy": nodes form disjoint strict trees. Iterative Tarjan: a node is in a loop when its
  // strongly connected component has more than one node, or it is its own child.
  void find_loops() {
    const std::size_t count = doc_.nodes.size();
    in_loop_.assign(count, 0);
    std::vector<char>& in_loop = in_loop_;
    {
      std::vector<std::int64_t> index(count, -1), low(count, 0);
      std::vector<char> on_stack(count, 0);
      std::vector<std::size_t> stack;
      std::int64_t next = 0;
      std::vector<std::pair<std::size_t, std::size_t>> frames;
      for (std::size_t start = 0; start < count; ++start) {
        if (index[start] >= 0 || !doc_.nodes[start].object) continue;
        frames.push_back({start, 0});
        index[start] = low[start] = next++;
        stack.push_back(start);
        on_stack[start] = 1;
        while (!frames.empty()) {
          auto& [v, edge] = frames.back();
          const auto& children = doc_.nodes[v].children;
          if (edge < children.size()) {
            const std::int64_t w64 = children[edge++];
            if (w64 < 0 || static_cast<std::size_t>(w64) >= count || !doc_.nodes[static_cast<std::size_t>(w64)].object)
              continue;
            const std::size_t w = static_cast<std::size_t>(w64);
            if (w == v) in_loop[v] = 1;
            if (index[w] < 0) {
              index[w] = low[w] = next++;
              stack.push_back(w);
              on_stack[w] = 1;
              frames.push_back({w, 0});
            } else if (on_stack[w]) {
              low[v] = std::min(low[v], index[w]);
            }
            continue;
          }
          const std::size_t finished = v;
          frames.pop_back();
          if (!frames.empty()) low[frames.back().first] = std::min(low[frames.back().first], low[finished]);
          if (low[finished] == index[finished]) {
            std::vector<std::size_t> component;
            while (true) {
              const std::size_t w = stack.back();
              stack.pop_back();
              on_stack[w] = 0;
              component.push_back(w);
              if (w == finished) break;
            }
            if (component.size() > 1)
              for (std::size_t w : component) in_loop[w] = 1;
          }
        }
      }
    }
  }

  // Node checks that need every parent link: loops, skinned meshes below transformed parents,
  // empty nodes.
  void node_graph() {
    const std::size_t count = doc_.nodes.size();
    const std::vector<char> skin_outside_scene = skinned_nodes_apart_from_their_joints();
    for (std::size_t i = 0; i < count; ++i) {
      const NodeModel& node = doc_.nodes[i];
      if (!node.object) continue;
      const std::string p = at("nodes", i);
      if (in_loop_[i]) {
        issues_.at("NODE_LOOP", p);
        continue;
      }
      // A skinned mesh below a parent first, then its own transform (the npm build's order).
      if (node.skin >= 0 && node.mesh >= 0 && node.parent >= 0) {
        bool transformed = false;
        std::int64_t parent = node.parent;
        for (std::size_t steps = 0; parent >= 0 && steps < count; ++steps) {
          const NodeModel& up = doc_.nodes[static_cast<std::size_t>(parent)];
          if (!up.is_identity_transform) transformed = true;
          parent = up.parent;
        }
        if (transformed) issues_.at("NODE_SKINNED_MESH_PARENT_TRANSFORMS", p);
        issues_.at("NODE_SKINNED_MESH_NON_ROOT", p);
      }
      if (node.skin >= 0 && node.mesh >= 0 && !node.is_identity_transform)
        issues_.at("NODE_SKINNED_MESH_LOCAL_TRANSFORMS", p);
      if (skin_outside_scene[i]) issues_.at("NODE_SKIN_NO_SCENE", p);
      if (node.empty && !node.joint) issues_.at("NODE_EMPTY", p);
    }
  }

  // Per node: it draws a skinned mesh in a scene that lacks some of its skin's joints (spec 3.7.3:
  // joints are nodes of the same scene, or the mesh cannot be posed there).
  std::vector<char> skinned_nodes_apart_from_their_joints() {
    std::vector<char> flagged(doc_.nodes.size(), 0);
    std::vector<char> in_scene(doc_.nodes.size());
    for (const SceneModel& scene : doc_.scenes) {
      std::fill(in_scene.begin(), in_scene.end(), 0);
      std::vector<std::int64_t> stack(scene.nodes.begin(), scene.nodes.end());
      while (!stack.empty()) {
        const std::int64_t n = stack.back();
        stack.pop_back();
        if (n < 0 || static_cast<std::size_t>(n) >= doc_.nodes.size() || in_scene[n]) continue;
        in_scene[n] = 1;
        for (std::int64_t child : doc_.nodes[n].children) stack.push_back(child);
      }
      for (std::size_t n = 0; n < doc_.nodes.size(); ++n) {
        const NodeModel& node = doc_.nodes[n];
        // A skin without a common root is reported as such (SKIN_NO_COMMON_ROOT), not here.
        if (!in_scene[n] || node.mesh < 0 || node.skin < 0 ||
            static_cast<std::size_t>(node.skin) >= doc_.skins.size() || !doc_.skins[node.skin].has_common_root)
          continue;
        for (std::int64_t joint : doc_.skins[node.skin].joints)
          if (joint >= 0 && static_cast<std::size_t>(joint) < doc_.nodes.size() && !in_scene[joint]) flagged[n] = 1;
      }
    }
    return flagged;
  }

  // A node and its ancestors, nearest first; the walk stops at a loop.
  std::vector<std::int64_t> ancestors(std::size_t node) {
    std::vector<std::int64_t> chain{static_cast<std::int64_t>(node)};
    std::int64_t parent = doc_.nodes[node].parent;
    for (std::size_t steps = 0; parent >= 0 && steps < doc_.nodes.size(); ++steps) {
      if (in_loop_[static_cast<std::size_t>(parent)]) break;
      chain.push_back(parent);
      parent = doc_.nodes[static_cast<std::size_t>(parent)].parent;
    }
    return chain;
  }

  // The nodes that are ancestors (or selves) of every resolved joint; unresolved joints are
  // skipped, and a skin with no resolved joint has no root.
  std::vector<std::int64_t> common_roots(const SkinModel& skin) {
    std::vector<std::int64_t> common;
    bool first = true;
    for (std::int64_t joint : skin.joints) {
      if (joint < 0 || static_cast<std::size_t>(joint) >= doc_.nodes.size() ||
          !doc_.nodes[static_cast<std::size_t>(joint)].object)
        continue;
      auto chain = ancestors(static_cast<std::size_t>(joint));
      if (first) {
        common = chain;
        first = false;
        continue;
      }
      std::vector<std::int64_t> kept;
      for (std::int64_t item : common)
        if (std::find(chain.begin(), chain.end(), item) != chain.end()) kept.push_back(item);
      common = std::move(kept);
    }
    return common;
  }

  Context& context_;
  IssueSink& issues_;
  Document& doc_;
  std::map<std::int64_t, std::vector<std::int64_t>> view_accessors_;  // vertex accessors per buffer view
  std::vector<char> in_loop_;                                         // per node, from find_loops()
};

}  // namespace

// The set number n of a semantic PREFIXn ("TEXCOORD_1" → 1), when n is written the schema's way.
std::optional<int> set_number(const std::string& name, std::string_view prefix) {
  if (!name.starts_with(prefix)) return std::nullopt;
  const std::string digits = name.substr(prefix.size());
  if (digits.empty() || digits.size() > 6 || (digits.size() > 1 && digits[0] == '0') ||
      !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::nullopt;
  return std::stoi(digits);
}

void check_links(Context& context) { Linker(context).run(); }

void report_unused(Context& context) {
  Document& doc = context.doc;
  IssueSink& issues = context.issues;
  auto each = [&](const auto& list, const char* collection) {
    for (std::size_t i = 0; i < list.size(); ++i)
      if (list[i].object && !list[i].used)
        issues.at("UNUSED_OBJECT", "/" + std::string(collection) + "/" + std::to_string(i));
  };
  each(doc.accessors, "accessors");
  each(doc.buffers, "buffers");
  each(doc.buffer_views, "bufferViews");
  each(doc.cameras, "cameras");
  each(doc.images, "images");
  each(doc.materials, "materials");
  each(doc.meshes, "meshes");
  each(doc.nodes, "nodes");
  each(doc.samplers, "samplers");
  each(doc.skins, "skins");
  each(doc.textures, "textures");
  each(doc.lights, "extensions/KHR_lights_punctual/lights");
  each(doc.variants, "extensions/KHR_materials_variants/variants");
  // Spec 3.7.2.2: a node's weights override its mesh's; when every node has its own, the mesh's
  // are never seen, nor are they when the mesh's primitives cannot be read (it draws nothing; the
  // reference's rule). Reported after every unused object, as the reference does.
  for (std::size_t i = 0; i < doc.meshes.size(); ++i) {
    const bool some_node_reads_mesh_weights = std::any_of(doc.nodes.begin(), doc.nodes.end(), [&](const NodeModel& n) {
      return n.object && n.mesh == static_cast<std::int64_t>(i) && n.weights < 0 && doc.meshes[i].primitives_known;
    });
    if (doc.meshes[i].object && doc.meshes[i].used && doc.meshes[i].weights >= 0 && !some_node_reads_mesh_weights)
      issues.at("UNUSED_MESH_WEIGHTS", "/meshes/" + std::to_string(i) + "/weights");
  }
}

}  // namespace gltf_pbr::structure
