// The schema walk over the core glTF 2.0 objects (spec section 5 "Properties Reference"), with the
// semantic checks that need one object only. Properties are read in schema order, which is the
// order the reference reports in; unknown properties are reported first, in document order.
#include <algorithm>
#include <cmath>
#include <regex>
#include <set>

#include "core/image_header.hpp"
#include "validators/structure/extensions.hpp"
#include "validators/structure/images.hpp"
#include "validators/structure/schema_reader.hpp"

namespace gltf_pbr::structure {

namespace {

const std::initializer_list<std::int64_t> kComponentTypes = {5120, 5121, 5122, 5123, 5125, 5126};
const std::initializer_list<std::string_view> kAccessorTypes = {"SCALAR", "VEC2", "VEC3", "VEC4",
                                                                "MAT2",   "MAT3", "MAT4"};

bool valid_extension_name(const std::string& name) {
  // glTF 2.0 spec 3.12 "Extensions": a prefix of upper-case letters or digits, an underscore, a name.
  static const std::regex pattern("^[A-Z0-9]+_[A-Za-z0-9_]+$");
  return std::regex_match(name, pattern);
}

// Missing properties inside a nested object (a primitive, a channel) invalidate that object only,
// not the top-level one that holds it.
class NestedScope {
 public:
  explicit NestedScope(SchemaReader& read) : read_(read), saved_(read.missing_count()) {}
  ~NestedScope() { read_.set_missing_count(saved_); }
  NestedScope(const NestedScope&) = delete;
  NestedScope& operator=(const NestedScope&) = delete;

 private:
  SchemaReader& read_;
  std::size_t saved_;
};

class Walker {
 public:
  explicit Walker(Context& context) : context_(context), read_(context), doc_(context.doc) {
    hooks_.texture_info = [this](const Json& owner, const std::string& pointer, std::string_view key, int kind) {
      if (current_material_) texture_info(owner, pointer, key, *current_material_, kind);
    };
    hooks_.material = [this] { return current_material_; };
    hooks_.primitive = [this] { return current_primitive_; };
    hooks_.node = [this] { return current_node_; };
    hooks_.texture = [this] { return current_texture_; };
    hooks_.buffer = [this] { return current_buffer_; };
    hooks_.buffer_view = [this] { return current_buffer_view_; };
  }

  // False when the document cannot be validated further (no usable asset).
  bool run() {
    const Json& root = context_.root;
    read_.check_members(root, "",
                        {"extensionsUsed", "extensionsRequired", "accessors", "animations", "asset", "buffers",
                         "bufferViews", "cameras", "images", "materials", "meshes", "nodes", "samplers", "scene",
                         "scenes", "skins", "textures", "extensions", "extras"});
    read_extension_lists(root);
    // Without an asset of a known major version nothing else can be read with confidence: the
    // reference stops here (spec 3.2 "Asset": version is the only required property).
    if (const Json* asset = read_.object(root, "", "asset", false)) {
      if (!read_asset(*asset)) return false;
    } else {
      if (!present(root, "asset")) context_.issues.at("UNDEFINED_PROPERTY", "/", {arg("asset")});
      return false;
    }
    each(root, "accessors", doc_.accessors,
         [&](const Json& o, const std::string& p, AccessorModel& m) { accessor(o, p, m); });
    each(root, "animations", doc_.animations,
         [&](const Json& o, const std::string& p, AnimationModel& m) { animation(o, p, m); });
    each(root, "buffers", doc_.buffers, [&](const Json& o, const std::string& p, BufferModel& m) { buffer(o, p, m); });
    each(root, "bufferViews", doc_.buffer_views,
         [&](const Json& o, const std::string& p, BufferViewModel& m) { buffer_view(o, p, m); });
    each(root, "cameras", doc_.cameras, [&](const Json& o, const std::string& p, SimpleModel&) { camera(o, p); });
    each(root, "images", doc_.images, [&](const Json& o, const std::string& p, ImageModel& m) { image(o, p, m); });
    each(root, "materials", doc_.materials,
         [&](const Json& o, const std::string& p, MaterialModel& m) { material(o, p, m); });
    each(root, "meshes", doc_.meshes, [&](const Json& o, const std::string& p, MeshModel& m) { mesh(o, p, m); });
    each(root, "nodes", doc_.nodes, [&](const Json& o, const std::string& p, NodeModel& m) { node(o, p, m); });
    each(root, "samplers", doc_.samplers,
         [&](const Json& o, const std::string& p, SamplerModel& m) { sampler(o, p, m); });
    each(root, "scenes", doc_.scenes, [&](const Json& o, const std::string& p, SceneModel& m) { scene(o, p, m); });
    // The default scene resolves as soon as the scenes are read (the reference reports it here).
    doc_.scene = read_.index(root, "", "scene");
    if (doc_.scene >= 0 && (static_cast<std::size_t>(doc_.scene) >= doc_.scenes.size() ||
                            !doc_.scenes[static_cast<std::size_t>(doc_.scene)].object))
      context_.issues.at("UNRESOLVED_REFERENCE", "/scene", {arg(doc_.scene)});
    each(root, "skins", doc_.skins, [&](const Json& o, const std::string& p, SkinModel& m) { skin(o, p, m); });
    each(root, "textures", doc_.textures,
         [&](const Json& o, const std::string& p, TextureModel& m) { texture(o, p, m); });
    extensions(root, "", Owner::Root);
    read_.extras(root, "");
    return true;
  }

 private:
  template <typename Model, typename Fn>
  void each(const Json& root, std::string_view key, std::vector<Model>& models, Fn&& fn) {
    auto list = read_.object_array(root, "", key, false, true);
    if (!list) return;
    models.resize(list->size());
    for (std::size_t i = 0; i < list->size(); ++i) {
      if (!(*list)[i]) {
        read_.element_not_object(root[std::string(key)], "/" + std::string(key), i);
        continue;
      }
      models[i].object = true;
      const std::size_t missing_before = read_.missing_count();
      fn(*(*list)[i], "/" + std::string(key) + "/" + std::to_string(i), models[i]);
      if (read_.missing_count() != missing_before) models[i].valid = false;
    }
  }

  void extensions(const Json& object, const std::string& pointer, Owner owner) {
    read_extensions(read_, object, pointer, owner, hooks_);
  }

  // The two lists' schemas first, then each declared extension in turn, then the required ones
  // (the reference's order).
  void read_extension_lists(const Json& root) {
    const auto used = string_list(root, "extensionsUsed");
    // Schema: extensionsRequired depends on extensionsUsed, whatever its value (judged before it).
    if (present(root, "extensionsRequired") && !present(root, "extensionsUsed"))
      context_.issues.at("UNSATISFIED_DEPENDENCY", "/extensionsRequired", {arg("extensionsUsed")});
    const auto required = string_list(root, "extensionsRequired");
    if (used) doc_.extensions_used = *used;
    if (required) doc_.extensions_required = *required;
    for (std::size_t i = 0; i < doc_.extensions_used.size(); ++i) {
      const std::string& name = doc_.extensions_used[i];
      const std::string pointer = "/extensionsUsed/" + std::to_string(i);
      // KHR_mesh_quantization changes what core accessors may hold, so a loader that ignores it
      // reads garbage: it cannot be optional (KHR_mesh_quantization, "Extending Mesh Attributes").
      if (name == "KHR_mesh_quantization" && std::find(doc_.extensions_required.begin(), doc_.extensions_required.end(),
                                                       name) == doc_.extensions_required.end())
        context_.issues.at("NON_REQUIRED_EXTENSION", pointer, {arg(name)});
      if (!valid_extension_name(name)) context_.issues.at("INVALID_EXTENSION_NAME_FORMAT", pointer);
      if (!extension_supported(name)) context_.issues.at("UNSUPPORTED_EXTENSION", pointer, {arg(name)});
    }
    for (std::size_t i = 0; i < doc_.extensions_required.size(); ++i)
      if (!context_.declared(doc_.extensions_required[i]))
        context_.issues.at("UNUSED_EXTENSION_REQUIRED", "/extensionsRequired/" + std::to_string(i),
                           {arg(doc_.extensions_required[i])});
  }

  std::optional<std::vector<std::string>> string_list(const Json& root, const char* key) {
    auto found = root.find(key);
    if (found == root.end()) return std::nullopt;
    const std::string pointer = std::string("/") + key;
    if (!found->is_array()) {
      context_.issues.at("TYPE_MISMATCH", pointer, {arg_json(*found), arg("array")});
      return std::nullopt;
    }
    if (found->empty()) {
      context_.issues.at("EMPTY_ENTITY", pointer);
      return std::nullopt;
    }
    // A list with an item that is not a string fails its schema whole and declares nothing; its
    // strings are still checked for repeats.
    std::vector<std::string> names;
    std::set<std::string> seen;
    bool all_strings = true;
    for (std::size_t i = 0; i < found->size(); ++i) {
      const Json& item = (*found)[i];
      if (!item.is_string()) {
        context_.issues.at("ARRAY_TYPE_MISMATCH", pointer + "/" + std::to_string(i), {arg_json(item), arg("string")});
        all_strings = false;
        continue;
      }
      if (!seen.insert(item.get<std::string>()).second)
        context_.issues.at("DUPLICATE_ELEMENTS", pointer + "/" + std::to_string(i));
      names.push_back(item.get<std::string>());
    }
    if (!all_strings) return std::nullopt;
    return names;
  }

  bool read_asset(const Json& asset) {
    const std::string p = "/asset";
    read_.check_members(asset, p, {"copyright", "generator", "version", "minVersion", "extensions", "extras"});
    read_.string(asset, p, "copyright");
    read_.string(asset, p, "generator");
    static const std::regex version_pattern("^([0-9]+)\\.([0-9]+)$");
    auto version = read_.string(asset, p, "version", true);
    int major = -1, minor = -1;
    if (version) {
      std::smatch match;
      if (std::regex_match(*version, match, version_pattern)) {
        major = std::stoi(match[1].str().substr(0, 9));
        minor = std::stoi(match[2].str().substr(0, 9));
        doc_.version = *version;
      } else {
        context_.issues.at("PATTERN_MISMATCH", p + "/version", {arg(*version), arg("^([0-9]+)\\.([0-9]+)$")});
      }
    }
    auto min_version = read_.string(asset, p, "minVersion");
    int min_major = -1, min_minor = -1;
    if (min_version) {
      std::smatch match;
      if (std::regex_match(*min_version, match, version_pattern)) {
        min_major = std::stoi(match[1].str().substr(0, 9));
        min_minor = std::stoi(match[2].str().substr(0, 9));
      } else {
        context_.issues.at("PATTERN_MISMATCH", p + "/minVersion", {arg(*min_version), arg("^([0-9]+)\\.([0-9]+)$")});
      }
    }
    extensions(asset, p, Owner::Asset);
    read_.extras(asset, p);
    if (major >= 0) {  // the two versions compared first, then the version judged (the reference's order)
      if (min_major >= 0 && (min_major > major || (min_major == major && min_minor > minor)))
        context_.issues.at("ASSET_MIN_VERSION_GREATER_THAN_VERSION", p + "/minVersion",
                           {arg(*min_version), arg(*version)});
      if (major != 2)
        context_.issues.at("UNKNOWN_ASSET_MAJOR_VERSION", p + "/version", {arg(major)});
      else if (minor > 0)
        context_.issues.at("UNKNOWN_ASSET_MINOR_VERSION", p + "/version", {arg(minor)});
    }
    return major == 2;
  }

  // Spec 3.5.2: a node matrix must decompose into translation, rotation and scale. The upper 3x3 of
  // an invertible affine matrix is R S (S diagonal, one entry negative for a mirror) exactly when
  // its columns are mutually orthogonal, so a shear is the largest cosine between two columns.
  static double largest_column_cosine(const std::vector<double>& a) {  // column-major
    auto dot = [&a](int i, int j) {
      return a[4 * i] * a[4 * j] + a[4 * i + 1] * a[4 * j + 1] + a[4 * i + 2] * a[4 * j + 2];
    };
    double largest = 0;
    for (const auto& [i, j] : {std::pair{0, 1}, std::pair{0, 2}, std::pair{1, 2}})
      if (const double cosine = std::fabs(dot(i, j)) / std::sqrt(dot(i, i) * dot(j, j)); !(cosine <= largest))
        largest = cosine;  // a NaN too, so that it fails the tolerance
    return largest;
  }
  // The tolerance is not in the spec. 1e-3 (a shear of 0.06 degrees) passes matrices written with
  // four significant digits and flags any shear a viewer could show. The reference flags shears
  // from about 1e-4 near the identity, but it also flags exact TRS matrices whose scales pass about
  // 100 (single-precision round-off against an absolute tolerance); that part is not followed.
  static constexpr double kShearTolerance = 1e-3;

  // accessor.min or max: one number per component. For integer component types (spec 3.6.2.5:
  // bounds are in the stored, unnormalized values) each is an integer the type can hold; a bound
  // list with any other value is reported at the list and not compared with the data.
  std::optional<std::vector<double>> bounds(const Json& o, const std::string& p, const char* key, int components,
                                            int component_type) {
    // Integer bounds have their length checked before anything else, so an empty list is the
    // wrong length, not an empty entity as float bounds are (checked against the npm validator).
    if (component_type != 5126 && o[key].is_array() && o[key].empty()) {
      context_.issues.at("ARRAY_LENGTH_NOT_IN_LIST", p + "/" + key, {arg(std::uint64_t{0})}, {arg(components)});
      return std::nullopt;
    }
    auto numbers = read_.numbers(o, p, key, {components});
    if (!numbers || component_type == 5126) return numbers;
    static const std::map<int, std::pair<double, double>> ranges = {
        {5120, {-128, 127}}, {5121, {0, 255}}, {5122, {-32768, 32767}}, {5123, {0, 65535}}, {5125, {0, 4294967295.0}}};
    const auto range = ranges.find(component_type);
    if (range == ranges.end()) return numbers;
    const std::string pointer = p + "/" + key;
    bool usable = true;
    for (const Json& item : o[key]) {
      if (!integer_value(item)) {
        context_.issues.at("ARRAY_TYPE_MISMATCH", pointer, {arg_json(item), arg("integer")});
        usable = false;
      } else if (const double value = item.get<double>(); value < range->second.first || value > range->second.second) {
        context_.issues.at("INVALID_GL_VALUE", pointer, {arg_json(item), arg(component_type_name(component_type))});
        usable = false;
      }
    }
    if (!usable) return std::nullopt;
    return numbers;
  }

  void accessor(const Json& o, const std::string& p, AccessorModel& m) {
    read_.check_members(o, p,
                        {"bufferView", "byteOffset", "componentType", "normalized", "count", "type", "max", "min",
                         "sparse", "name", "extensions", "extras"});
    // Read in the reference's order, which is its report order.
    m.buffer_view = read_.index(o, p, "bufferView");
    std::optional<std::int64_t> offset;
    if (o.contains("byteOffset") && o["byteOffset"].is_null()) {
      read_.integer(o, p, "byteOffset");  // a null is reported, then absent
    } else if (present(o, "byteOffset")) {
      // Without a usable bufferView the offset means nothing: only the dependency is reported.
      if (m.buffer_view < 0)
        context_.issues.at("UNSATISFIED_DEPENDENCY", p + "/byteOffset", {arg("bufferView")});
      else if ((offset = read_.integer(o, p, "byteOffset", false, {0})))
        m.byte_offset = *offset;
      else
        m.offset_unusable = true;  // where its data starts is unknown: none of it is read
    }
    const auto component_type = read_.integer(o, p, "componentType", true, {}, kComponentTypes);
    if (component_type) m.component_type = int(*component_type);
    const auto count = read_.integer(o, p, "count", true, {1});
    if (count) m.count = *count;
    // Without its component type or count an accessor has no extent: one that cannot be read is
    // not linked, as one that is missing (the reference's rule: its buffer view is left unused,
    // its references and offsets unjudged; checked on constructed files).
    if (!component_type || !count) m.valid = false;
    if (auto type = read_.string(o, p, "type", true, kAccessorTypes)) m.type = *type;
    if (auto normalized = read_.boolean(o, p, "normalized")) {
      m.normalized = *normalized;
      if (*normalized && (m.component_type == 5126 || m.component_type == 5125))
        context_.issues.at("ACCESSOR_NORMALIZED_INVALID", p + "/normalized");
    }
    // Bounds have one value per component: without a valid type and component type they are
    // not read at all.
    const int components = component_count(m.type);
    if (components > 0 && m.component_type != 0) {
      if (o.contains("min"))  // a null is reported by the read
        if (auto numbers = bounds(o, p, "min", components, m.component_type)) m.has_min = true, m.min = *numbers;
      if (o.contains("max"))
        if (auto numbers = bounds(o, p, "max", components, m.component_type)) m.has_max = true, m.max = *numbers;
    }
    if (const Json* sparse = read_.object(o, p, "sparse")) this->sparse(*sparse, p + "/sparse", m);
    read_.string(o, p, "name");
    extensions(o, p, Owner::Accessor);
    read_.extras(o, p);
    m.has_byte_offset = offset.has_value();
    // Spec 3.6.2.4: matrix columns start on 4-byte boundaries.
    const int size = component_size(m.component_type);
    if (offset && size > 0 && size < 4 && m.type.starts_with("MAT") && m.byte_offset % 4 != 0)
      context_.issues.at("ACCESSOR_MATRIX_ALIGNMENT", p + "/byteOffset");
  }

  // accessor.sparse (spec 5.1.7). A sparse object missing a required property is dropped, as if
  // absent; one missing inside indices or values keeps the rest.
  void sparse(const Json& o, const std::string& p, AccessorModel& m) {
    read_.check_members(o, p, {"count", "indices", "values", "extensions", "extras"});
    const std::size_t missing_before = read_.missing_count();
    auto count = read_.integer(o, p, "count", true, {1});
    if (count) m.sparse_count = *count;
    const Json* indices = read_.object(o, p, "indices", true);
    const Json* values = read_.object(o, p, "values", true);
    // A count that cannot be read (out of range, not an integer) leaves the sparse object unlinked,
    // as a missing one does: its views are unused (the reference's answer on count 0).
    const bool sparse_valid = read_.missing_count() == missing_before && count;
    if (indices) {
      const std::string ip = p + "/indices";
      const std::size_t nested = read_.missing_count();
      read_.check_members(*indices, ip, {"bufferView", "byteOffset", "componentType", "extensions", "extras"});
      m.sparse_indices_view = read_.index(*indices, ip, "bufferView", true);
      if (auto offset = read_.integer(*indices, ip, "byteOffset", false, {0})) m.sparse_indices_offset = *offset;
      if (auto type = read_.integer(*indices, ip, "componentType", true, {}, {5121, 5123, 5125}))
        m.sparse_indices_component_type = int(*type);
      extensions(*indices, ip, Owner::Other);
      read_.extras(*indices, ip);
      if (read_.missing_count() != nested) m.sparse_indices_view = -1;  // not linked
      read_.set_missing_count(nested);
    }
    if (values) {
      const std::string vp = p + "/values";
      const std::size_t nested = read_.missing_count();
      read_.check_members(*values, vp, {"bufferView", "byteOffset", "extensions", "extras"});
      m.sparse_values_view = read_.index(*values, vp, "bufferView", true);
      if (auto offset = read_.integer(*values, vp, "byteOffset", false, {0})) m.sparse_values_offset = *offset;
      extensions(*values, vp, Owner::Other);
      read_.extras(*values, vp);
      if (read_.missing_count() != nested) m.sparse_values_view = -1;
      read_.set_missing_count(nested);
    }
    extensions(o, p, Owner::Other);
    read_.extras(o, p);
    read_.set_missing_count(missing_before);  // the accessor stays valid
    if (!sparse_valid) {
      m.sparse = false;
      m.sparse_indices_view = m.sparse_values_view = -1;
      return;
    }
    m.sparse = true;
  }

  void animation(const Json& o, const std::string& p, AnimationModel& m) {
    read_.check_members(o, p, {"channels", "samplers", "name", "extensions", "extras"});
    if (auto channels = read_.object_array(o, p, "channels", true, false)) {
      m.channels.resize(channels->size());
      for (std::size_t i = 0; i < channels->size(); ++i) {
        if (!(*channels)[i]) continue;
        const Json& c = *(*channels)[i];
        const std::string cp = p + "/channels/" + std::to_string(i);
        AnimationChannelModel& channel = m.channels[i];
        channel.object = true;
        const NestedScope scope(read_);
        read_.check_members(c, cp, {"sampler", "target", "extensions", "extras"});
        channel.sampler = read_.index(c, cp, "sampler", true);
        if (const Json* target = read_.object(c, cp, "target", true)) {
          const std::string tp = cp + "/target";
          read_.check_members(*target, tp, {"node", "path", "extensions", "extras"});
          channel.node = read_.index(*target, tp, "node");
          channel.target_has_node = present(*target, "node");
          if (auto raw = target->find("path"); raw != target->end() && raw->is_string()) channel.raw_path = *raw;
          auto ext = target->find("extensions");
          channel.pointer_extension = context_.declared("KHR_animation_pointer") && ext != target->end() &&
                                      ext->is_object() && ext->contains("KHR_animation_pointer");
          extensions(*target, tp, Owner::ChannelTarget);
          const bool pointer_declared = context_.declared("KHR_animation_pointer");
          std::optional<std::string> path =
              pointer_declared
                  ? read_.string(*target, tp, "path", true, {"translation", "rotation", "scale", "weights", "pointer"})
                  : read_.string(*target, tp, "path", true, {"translation", "rotation", "scale", "weights"});
          if (path) channel.path = *path;
          read_.extras(*target, tp);
        }
        extensions(c, cp, Owner::Other);
        read_.extras(c, cp);
      }
    }
    if (auto samplers = read_.object_array(o, p, "samplers", true, false)) {
      m.samplers.resize(samplers->size());
      for (std::size_t i = 0; i < samplers->size(); ++i) {
        if (!(*samplers)[i]) continue;
        const Json& s = *(*samplers)[i];
        const std::string sp = p + "/samplers/" + std::to_string(i);
        AnimationSamplerModel& sampler = m.samplers[i];
        sampler.object = true;
        const NestedScope scope(read_);
        read_.check_members(s, sp, {"input", "interpolation", "output", "extensions", "extras"});
        sampler.input = read_.index(s, sp, "input", true);
        if (auto interpolation = read_.string(s, sp, "interpolation", false, {"LINEAR", "STEP", "CUBICSPLINE"}))
          sampler.interpolation = *interpolation;
        sampler.output = read_.index(s, sp, "output", true);
        extensions(s, sp, Owner::Other);
        read_.extras(s, sp);
      }
    }
    read_.string(o, p, "name");
    extensions(o, p, Owner::Animation);
    read_.extras(o, p);
  }

  void buffer(const Json& o, const std::string& p, BufferModel& m) {
    read_.check_members(o, p, {"uri", "byteLength", "name", "extensions", "extras"});
    if (auto length = read_.integer(o, p, "byteLength", true, {1})) m.byte_length = *length;
    if (auto uri = read_.string(o, p, "uri")) {
      m.has_uri = true;
      m.uri = *uri;
      if (context_.glb) context_.issues.at("URI_GLB", p + "/uri");
      m.uri_valid = check_uri(*uri, p + "/uri", true, m.data_uri, m.owned);
      m.data = m.owned;
      m.non_relative = last_uri_non_relative_;
      if (m.uri_valid && m.data_uri) m.data_loaded = true;
    }
    read_.string(o, p, "name");
    current_buffer_ = &m;
    extensions(o, p, Owner::Buffer);
    current_buffer_ = nullptr;
    read_.extras(o, p);
  }

 public:
  // RFC 3986 URIs and RFC 2397 data URIs (the spec's "URIs" section). Returns whether the URI is usable;
  // decodes data URIs into `data`.
  bool check_uri(const std::string& uri, const std::string& pointer, bool is_buffer, bool& is_data,
                 std::vector<std::uint8_t>& data, std::string* data_mime = nullptr) {
    is_data = false;
    last_uri_non_relative_ = false;
    if (uri.starts_with("data:")) {
      is_data = true;
      const std::size_t comma = uri.find(',');
      if (comma == std::string::npos) {
        context_.issues.at("INVALID_URI", pointer, {arg(uri), arg_raw("\nFormatException: Expecting '='\n" + uri)});
        return false;
      }
      const std::string header = uri.substr(5, comma - 5);
      const bool base64 = header.ends_with(";base64");
      const std::string media = base64 ? header.substr(0, header.size() - 7) : header;
      // Media type parameters are name=value pairs (RFC 2397): an empty one is malformed.
      const std::size_t semicolon = media.find(';');
      std::string mime = media.substr(0, semicolon);
      // Media types are case-insensitive (RFC 2045 5.1).
      for (char& c : mime) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (semicolon != std::string::npos) {
        std::string parameters = media.substr(semicolon + 1);
        std::size_t start = 0;
        while (start <= parameters.size()) {
          std::size_t end = parameters.find(';', start);
          if (end == std::string::npos) end = parameters.size();
          const std::string parameter = parameters.substr(start, end - start);
          if (parameter.find('=') == std::string::npos) {
            const std::size_t column = 5 + semicolon + 1 + start;
            context_.issues.at(
                "INVALID_URI", pointer,
                {arg(uri), arg_raw("\nFormatException: Expecting '=' (at character " + std::to_string(column + 1) +
                                   ")\n" + uri + "\n" + std::string(column, ' ') + "^")});
            return false;
          }
          start = end + 1;
        }
      }
      if (data_mime) *data_mime = mime;
      const std::string payload = uri.substr(comma + 1);
      if (base64) {
        Base64Problem problem;
        std::optional<std::vector<std::uint8_t>> decoded = decode_base64(payload, &problem);
        if (!decoded) {
          context_.issues.at("INVALID_URI", pointer, {arg(uri), arg_raw(base64_exception(uri, comma + 1, problem))});
          return false;
        }
        data = std::move(*decoded);
      } else {
        data.assign(payload.begin(), payload.end());
      }
      // A data URI that parses is one in a GLB, whatever its media type says next.
      if (context_.glb) context_.issues.at("DATA_URI_GLB", pointer);
      if (is_buffer && mime != "application/octet-stream" && mime != "application/gltf-buffer") {
        context_.issues.at("BUFFER_DATA_URI_MIME_TYPE_INVALID", pointer, {arg(mime)});
        return false;
      }
      return true;
    }
    // A scheme is letters, digits, '+', '-', '.' before the first ':'; an empty one is invalid.
    const std::size_t colon = uri.find(':');
    const std::size_t slash = uri.find_first_of("/?#");
    if (colon != std::string::npos && (slash == std::string::npos || colon < slash)) {
      if (colon == 0) {
        context_.issues.at(
            "INVALID_URI", pointer,
            {arg(uri), arg_raw("\nFormatException: Invalid empty scheme (at character 1)\n" + uri + "\n^")});
        return false;
      }
      context_.issues.at("NON_RELATIVE_URI", pointer, {arg(uri)});
      last_uri_non_relative_ = true;
      return false;
    }
    // The spec's "URIs" section: a relative path is a path-noscheme, "without scheme, authority, or parameters".
    // An absolute path, an authority (//host), a query or a fragment is named, and the resource
    // is still read as any other (the path policy decides whether it may be opened).
    if (uri.starts_with('/') || uri.find_first_of("?#") != std::string::npos)
      context_.issues.at("NON_RELATIVE_URI", pointer, {arg(uri)});
    return true;
  }

 private:
  // The parser output the reference prints for bad base64 in a data URI, read off constructed URIs
  // against the npm validator: the reason, then the URI with a caret under the character at fault.
  static std::string base64_exception(const std::string& uri, std::size_t payload_start, const Base64Problem& problem) {
    using Kind = Base64Problem::Kind;
    std::string reason;
    switch (problem.kind) {
      case Kind::Character:
        reason = "Invalid base64 data";
        break;
      case Kind::PaddingNotAtEnd:
        reason = "Invalid base64 padding, '=' not at the end";
        break;
      case Kind::PaddingTooLong:
        reason = "Invalid base64 padding, more than two '=' characters";
        break;
      case Kind::PaddedLength:
        reason = "Invalid base64 padding, padded length must be multiple of four, is " +
                 std::to_string(uri.size() - payload_start);
        break;
      case Kind::Length:
        reason = "Invalid base64 encoding length ";
        break;
    }
    const std::size_t column = payload_start + problem.at;
    return "\nFormatException: " + reason + " (at character " + std::to_string(column + 1) + ")\n" + uri + "\n" +
           std::string(column, ' ') + "^";
  }

  void buffer_view(const Json& o, const std::string& p, BufferViewModel& m) {
    read_.check_members(o, p,
                        {"buffer", "byteOffset", "byteLength", "byteStride", "target", "name", "extensions", "extras"});
    if (auto length = read_.integer(o, p, "byteLength", true, {1})) m.byte_length = *length;
    if (auto stride = read_.integer(o, p, "byteStride", false, {4, 252})) {
      if (*stride % 4 != 0) context_.issues.at("VALUE_MULTIPLE_OF", p + "/byteStride", {arg(*stride), arg(4)});
      m.byte_stride = *stride;
      if (m.byte_length > 0 && *stride > m.byte_length)
        context_.issues.at("BUFFER_VIEW_TOO_BIG_BYTE_STRIDE", p + "/byteStride", {arg(*stride), arg(m.byte_length)});
    }
    if (auto target = read_.integer(o, p, "target", false, {}, {34962, 34963})) {
      m.target = int(*target);
      m.usage_target = m.target;
      m.usage_name = m.target == 34962 ? "VertexBuffer" : "IndexBuffer";
    }
    // Spec 3.6.2.3: only vertex attribute data may be strided.
    if (m.byte_stride > 0 && m.target == 34963)
      context_.issues.at("BUFFER_VIEW_INVALID_BYTE_STRIDE", p + "/byteStride");
    m.buffer = read_.index(o, p, "buffer", true);
    if (auto offset = read_.integer(o, p, "byteOffset", false, {0}))
      m.byte_offset = *offset;
    else if (present(o, "byteOffset"))
      m.byte_offset = -1;  // unusable: where its accessors' data starts is unknown
    read_.string(o, p, "name");
    current_buffer_view_ = &m;
    extensions(o, p, Owner::BufferView);
    current_buffer_view_ = nullptr;
    read_.extras(o, p);
  }

  // camera (spec 5.12): only the projection that a valid `type` names is read; the other one, and
  // both when the type is missing or unknown, are left alone (beside ONE_OF_MISMATCH when both are
  // there). Members are judged in the reference's fixed order, each semantic check as soon as its
  // members are read: perspective yfov (and yfov < pi), zfar, znear (and zfar > znear),
  // aspectRatio; orthographic xmag, ymag, zfar, znear, then zfar > znear, then each magnification;
  // then each projection's extensions and extras.
  void camera(const Json& o, const std::string& p) {
    read_.check_members(o, p, {"orthographic", "perspective", "type", "name", "extensions", "extras"});
    if (present(o, "orthographic") && present(o, "perspective"))
      context_.issues.at("ONE_OF_MISMATCH", p, {}, {arg("orthographic"), arg("perspective")});
    const auto type = read_.string(o, p, "type", true, {"orthographic", "perspective"});
    if (type && !present(o, *type)) context_.issues.at("UNDEFINED_PROPERTY", p, {arg(*type)});
    const Json* orthographic = type == "orthographic" ? read_.object(o, p, "orthographic") : nullptr;
    const Json* perspective = type == "perspective" ? read_.object(o, p, "perspective") : nullptr;
    if (orthographic) {
      const std::string op = p + "/orthographic";
      read_.check_members(*orthographic, op, {"xmag", "ymag", "zfar", "znear", "extensions", "extras"});
      const auto xmag = read_.number(*orthographic, op, "xmag", true);
      const auto ymag = read_.number(*orthographic, op, "ymag", true);
      const auto zfar = read_.number(*orthographic, op, "zfar", true, {0, INFINITY, true});
      const auto znear = read_.number(*orthographic, op, "znear", true, {0});
      if (zfar && znear && *zfar <= *znear) context_.issues.at("CAMERA_ZFAR_LEQUAL_ZNEAR", op);
      for (const auto& [name, value] : {std::pair{"xmag", xmag}, std::pair{"ymag", ymag}}) {
        if (value && *value == 0)
          context_.issues.at("CAMERA_XMAG_YMAG_ZERO", op + "/" + name);
        else if (value && *value < 0)
          context_.issues.at("CAMERA_XMAG_YMAG_NEGATIVE", op + "/" + name);
      }
      extensions(*orthographic, op, Owner::Other);
      read_.extras(*orthographic, op);
    }
    if (perspective) {
      const std::string pp = p + "/perspective";
      read_.check_members(*perspective, pp, {"aspectRatio", "yfov", "zfar", "znear", "extensions", "extras"});
      const auto yfov = read_.number(*perspective, pp, "yfov", true, {0, INFINITY, true});
      if (yfov && *yfov >= M_PI) context_.issues.at("CAMERA_YFOV_GEQUAL_PI", pp);
      const auto zfar = read_.number(*perspective, pp, "zfar", false, {0, INFINITY, true});
      const auto znear = read_.number(*perspective, pp, "znear", true, {0, INFINITY, true});
      if (zfar && znear && *zfar <= *znear) context_.issues.at("CAMERA_ZFAR_LEQUAL_ZNEAR", pp);
      read_.number(*perspective, pp, "aspectRatio", false, {0, INFINITY, true});
      extensions(*perspective, pp, Owner::Other);
      read_.extras(*perspective, pp);
    }
    read_.string(o, p, "name");
    extensions(o, p, Owner::Camera);
    read_.extras(o, p);
  }

  void image(const Json& o, const std::string& p, ImageModel& m) {
    read_.check_members(o, p, {"uri", "mimeType", "bufferView", "name", "extensions", "extras"});
    m.buffer_view = read_.index(o, p, "bufferView");
    std::optional<std::string> mime;
    const bool webp = context_.declared("EXT_texture_webp"), basisu = context_.declared("KHR_texture_basisu");
    if (webp && basisu)
      mime = read_.string(o, p, "mimeType", false, {"image/jpeg", "image/png", "image/webp", "image/ktx2"});
    else if (webp)
      mime = read_.string(o, p, "mimeType", false, {"image/jpeg", "image/png", "image/webp"});
    else if (basisu)
      mime = read_.string(o, p, "mimeType", false, {"image/jpeg", "image/png", "image/ktx2"});
    else
      mime = read_.string(o, p, "mimeType", false, {"image/jpeg", "image/png"});
    if (mime)
      m.mime_type = *mime;
    else if (present(o, "mimeType") && o["mimeType"].is_string())
      m.mime_type = o["mimeType"].get<std::string>();
    const bool has_view = present(o, "bufferView"), has_uri = present(o, "uri");
    if (has_view == has_uri) context_.issues.at("ONE_OF_MISMATCH", p, {}, {arg("bufferView"), arg("uri")});
    if (auto uri = read_.string(o, p, "uri")) {
      m.has_uri = true;
      m.uri = *uri;
      // As for buffers: a GLB should carry its images in buffer views, not beside it or in data URIs.
      if (context_.glb) context_.issues.at("URI_GLB", p + "/uri");
      m.uri_valid = check_uri(*uri, p + "/uri", false, m.data_uri, m.data, &m.data_uri_mime);
      // An image data URI names an image type, and its bytes are of that type: bytes that no
      // signature names do not match it either (the reference's URI parser sniffs them).
      const std::string content = m.data_uri ? image_mime_of(m.data) : std::string();
      if (m.uri_valid && m.data_uri && (content.empty() || content != m.data_uri_mime)) {
        context_.issues.at("INVALID_URI", p + "/uri",
                           {arg(*uri), arg_raw("\nThe declared mediatype does not match the embedded content.")});
        m.uri_valid = false;
      }
    }
    if (has_view && !present(o, "mimeType"))
      context_.issues.at("UNSATISFIED_DEPENDENCY", p + "/bufferView", {arg("mimeType")});
    read_.string(o, p, "name");
    extensions(o, p, Owner::Image);
    read_.extras(o, p);
  }

 public:
  // A textureInfo (spec 5.22), normalTextureInfo (5.21.3) or occlusionTextureInfo (5.21.4).
  void texture_info(const Json& owner, const std::string& owner_pointer, std::string_view key, MaterialModel& material,
                    int kind) {
    const Json* info = read_.object(owner, owner_pointer, key);
    if (!info) return;
    const NestedScope scope(read_);
    const std::string p = owner_pointer + "/" + std::string(key);
    if (kind == 1)
      read_.check_members(*info, p, {"index", "texCoord", "scale", "extensions", "extras"});
    else if (kind == 2)
      read_.check_members(*info, p, {"index", "texCoord", "strength", "extensions", "extras"});
    else
      read_.check_members(*info, p, {"index", "texCoord", "extensions", "extras"});
    TextureRef ref;
    ref.pointer = p;
    // The extensions (KHR_texture_transform) before the info's own members, as the reference
    // reports them.
    extensions(*info, p, Owner::TextureInfo);
    ref.index = read_.index(*info, p, "index", true);
    if (auto coord = read_.integer(*info, p, "texCoord", false, {0}))
      ref.tex_coord = *coord;
    else if (present(*info, "texCoord"))
      ref.tex_coord = -1;
    if (kind == 1) read_.number(*info, p, "scale");
    if (kind == 2) read_.number(*info, p, "strength", false, {0, 1});
    read_.extras(*info, p);
    // KHR_texture_transform.texCoord overrides the binding's set for a viewer that knows the
    // extension, and the base set stays for one that does not: the reference needs both (and an
    // undeclared extension's override not at all; its answers on constructed files).
    if (auto ext = info->find("extensions");
        ext != info->end() && ext->is_object() && context_.declared("KHR_texture_transform")) {
      if (auto transform = ext->find("KHR_texture_transform"); transform != ext->end() && transform->is_object()) {
        if (auto coord = transform->find("texCoord"); coord != transform->end())
          if (const auto set = integer_value(*coord); set && *set >= 0) ref.transform_tex_coord = *set;
      }
    }
    // The core normal map gives a tangent space to generate; the textures of extensions that are
    // defined in tangent space (a clearcoat normal map, an anisotropy direction map) need one.
    if (key == "normalTexture") {
      material.has_normal_texture = true;
      material.normal_tex_coord = ref.transform_tex_coord >= 0 ? ref.transform_tex_coord : ref.tex_coord;
    } else if (key == "clearcoatNormalTexture" || key == "anisotropyTexture") {
      material.needs_tangents = true;
    }
    material.textures.push_back(ref);
  }

 private:
  void material(const Json& o, const std::string& p, MaterialModel& m) {
    read_.check_members(o, p,
                        {"pbrMetallicRoughness", "normalTexture", "occlusionTexture", "emissiveTexture",
                         "emissiveFactor", "alphaMode", "alphaCutoff", "doubleSided", "name", "extensions", "extras"});
    if (const Json* pbr = read_.object(o, p, "pbrMetallicRoughness")) {
      const std::string pp = p + "/pbrMetallicRoughness";
      read_.check_members(*pbr, pp,
                          {"baseColorFactor", "baseColorTexture", "metallicFactor", "roughnessFactor",
                           "metallicRoughnessTexture", "extensions", "extras"});
      read_.numbers(*pbr, pp, "baseColorFactor", {4}, {0, 1});
      texture_info(*pbr, pp, "baseColorTexture", m, 0);
      read_.number(*pbr, pp, "metallicFactor", false, {0, 1});
      read_.number(*pbr, pp, "roughnessFactor", false, {0, 1});
      texture_info(*pbr, pp, "metallicRoughnessTexture", m, 0);
      extensions(*pbr, pp, Owner::Other);
      read_.extras(*pbr, pp);
    }
    texture_info(o, p, "normalTexture", m, 1);
    texture_info(o, p, "occlusionTexture", m, 2);
    texture_info(o, p, "emissiveTexture", m, 0);
    read_.numbers(o, p, "emissiveFactor", {3}, {0, 1});
    auto mode = read_.string(o, p, "alphaMode", false, {"OPAQUE", "MASK", "BLEND"});
    read_.number(o, p, "alphaCutoff", false, {0});
    if (present(o, "alphaCutoff") && (!mode || *mode != "MASK"))
      context_.issues.at("MATERIAL_ALPHA_CUTOFF_INVALID_MODE", p + "/alphaCutoff");
    read_.boolean(o, p, "doubleSided");
    read_.string(o, p, "name");
    current_material_ = &m;
    extensions(o, p, Owner::Material);
    current_material_ = nullptr;
    read_.extras(o, p);
  }

  static bool valid_semantic(const std::string& name, bool target, std::string* base, int* set) {
    *set = -1;
    if (name == "POSITION" || name == "NORMAL" || name == "TANGENT") {
      *base = name;
      return true;
    }
    // Spec 3.7.2.1: application-specific semantics start with an underscore, in targets as well.
    if (!name.empty() && name[0] == '_') {
      *base = name;
      return true;
    }
    for (const char* prefix : {"TEXCOORD_", "COLOR_", "JOINTS_", "WEIGHTS_"}) {
      const std::string_view text(prefix);
      if (!name.starts_with(text)) continue;
      const std::string digits = name.substr(text.size());
      if (digits.empty() || digits.size() > 6 || (digits.size() > 1 && digits[0] == '0')) return false;
      if (!std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; })) return false;
      *base = std::string(text.substr(0, text.size() - 1));
      *set = std::stoi(digits);
      if (target && (*base == "JOINTS" || *base == "WEIGHTS")) return false;
      return true;
    }
    return false;
  }

  // A primitive's attributes or a morph target's; `skinned`, for a primitive's, receives
  // PrimitiveModel::skinned.
  std::vector<std::pair<std::string, std::int64_t>> attribute_map(const Json& o, const std::string& p, bool target,
                                                                  bool* skinned = nullptr) {
    std::vector<std::pair<std::string, std::int64_t>> result;
    std::map<std::string, std::vector<int>> sets;
    for (const auto& [name, value] : o.items()) {
      const std::string ap = p + "/" + escape_pointer_token(name);
      std::int64_t index = -1;
      // The name first, then the value: anything but a non-negative integer is an invalid index.
      std::string base;
      int set;
      if (!valid_semantic(name, target, &base, &set)) {
        context_.issues.at("MESH_PRIMITIVE_INVALID_ATTRIBUTE", ap);
      } else if (set >= 0) {
        sets[base].push_back(set);
      }
      const std::int64_t value_index = integer_value(value).value_or(-1);
      if (value_index < 0)
        context_.issues.at("INVALID_INDEX", ap);
      else
        index = value_index;
      result.emplace_back(name, index);
    }
    if (!target) {
      // After the names and before the sets, as the reference reports them.
      auto has = [&](const char* name) { return o.contains(name); };
      if (!has("POSITION")) context_.issues.at("MESH_PRIMITIVE_NO_POSITION", p);
      if (has("TANGENT") && !has("NORMAL")) context_.issues.at("MESH_PRIMITIVE_TANGENT_WITHOUT_NORMAL", p + "/TANGENT");
      std::set<std::string> broken;  // semantics whose sets have a gap: none of their sets counts
      for (auto& [base, list] : sets) {
        std::sort(list.begin(), list.end());
        const bool continuous = list.back() == static_cast<int>(list.size()) - 1;
        if (!continuous) {
          context_.issues.at("MESH_PRIMITIVE_INDEXED_SEMANTIC_CONTINUITY", p,
                             {arg(base), arg(list.back() + 1), arg(static_cast<int>(list.size()))});
          broken.insert(base);
        }
      }
      const auto sets_of = [&](const std::string& base) {
        return sets.contains(base) && !broken.contains(base) ? sets[base].size() : std::size_t{0};
      };
      const std::size_t joints = sets_of("JOINTS"), weights = sets_of("WEIGHTS");
      if (joints != weights)
        context_.issues.at("MESH_PRIMITIVE_JOINTS_WEIGHTS_MISMATCH", p,
                           {arg(static_cast<std::uint64_t>(joints)), arg(static_cast<std::uint64_t>(weights))});
      if (skinned) *skinned = joints > 0 && joints == weights;
    }
    return result;
  }

  void primitive(const Json& o, const std::string& p, PrimitiveModel& m) {
    read_.check_members(o, p, {"attributes", "indices", "material", "mode", "targets", "extensions", "extras"});
    m.pointer = p;
    // A range, not a list: the reference reports a mode outside 0-6 as VALUE_NOT_IN_RANGE (an
    // error). A mode that cannot be read, out of range or not an integer, is unknown (-1): no
    // count is judged by it (no MESH_PRIMITIVE_INCOMPATIBLE_MODE; checked against the npm
    // validator).
    if (auto mode = read_.integer(o, p, "mode", false, {0, 6}))
      m.mode = int(*mode);
    else if (present(o, "mode"))
      m.mode = -1;
    if (const Json* attributes = read_.object(o, p, "attributes", true)) {
      if (attributes->empty()) {
        context_.issues.at("EMPTY_ENTITY", p + "/attributes");
      } else {
        m.attributes = attribute_map(*attributes, p + "/attributes", false, &m.skinned);
      }
    }
    // A targets list that cannot be read whole (not an array, empty, or holding a target that is
    // not an object or is empty) is no targets: counted as none against the other primitives and
    // the weights, its accessors linked by nothing (the reference's reading, checked against the
    // npm validator on constructed files). object_array drops a list with a non-object whole.
    if (auto targets = read_.object_array(o, p, "targets", false, false)) {
      bool readable = true;
      std::vector<std::vector<std::pair<std::string, std::int64_t>>> target_attributes(targets->size());
      for (std::size_t t = 0; t < targets->size(); ++t) {
        const std::string tp = p + "/targets/" + std::to_string(t);
        if ((*targets)[t]->empty()) {
          context_.issues.at("EMPTY_ENTITY", tp);
          readable = false;
        } else {
          target_attributes[t] = attribute_map(*(*targets)[t], tp, true);
        }
      }
      if (readable) {
        m.targets = static_cast<std::int64_t>(targets->size());
        m.target_attributes = std::move(target_attributes);
      }
    }
    m.indices = read_.index(o, p, "indices");
    m.material = read_.index(o, p, "material");
    current_primitive_ = &m;
    extensions(o, p, Owner::Primitive);
    current_primitive_ = nullptr;
    read_.extras(o, p);
  }

  void mesh(const Json& o, const std::string& p, MeshModel& m) {
    read_.check_members(o, p, {"primitives", "weights", "name", "extensions", "extras"});
    auto weights = read_.numbers(o, p, "weights");
    auto primitives = read_.object_array(o, p, "primitives", true, false);
    m.primitives_known = primitives.has_value();
    if (primitives) {
      m.primitives.resize(primitives->size());
      // Spec 3.7.2.2 "Morph Targets": every primitive of a mesh has the same number of targets;
      // each primitive is compared with the first as soon as it is read.
      std::int64_t expected = -3;
      for (std::size_t i = 0; i < primitives->size(); ++i) {
        if (!(*primitives)[i]) continue;
        m.primitives[i].object = true;
        {
          const NestedScope scope(read_);
          primitive(*(*primitives)[i], p + "/primitives/" + std::to_string(i), m.primitives[i]);
        }
        const PrimitiveModel& read = m.primitives[i];
        const std::int64_t count = std::max<std::int64_t>(read.targets, 0);
        if (expected == -3)
          expected = count;
        else if (count != expected)
          context_.issues.at("MESH_PRIMITIVES_UNEQUAL_TARGETS_COUNT",
                             read.targets >= 0 ? read.pointer + "/targets" : read.pointer);
      }
    }
    if (weights) m.weights = static_cast<std::int64_t>(weights->size());
    // Against the first primitive's targets, which the others were compared with (the reference's
    // rule); without readable primitives the number of targets is unknown.
    if (weights && primitives) {
      std::int64_t targets = 0;
      for (const auto& primitive : m.primitives)
        if (primitive.object) {
          targets = std::max<std::int64_t>(primitive.targets, 0);
          break;
        }
      if (targets != m.weights)
        context_.issues.at("MESH_INVALID_WEIGHTS_COUNT", p + "/weights", {arg(m.weights), arg(targets)});
    }
    read_.string(o, p, "name");
    extensions(o, p, Owner::Mesh);
    read_.extras(o, p);
  }

  void node(const Json& o, const std::string& p, NodeModel& m) {
    read_.check_members(o, p,
                        {"camera", "children", "skin", "matrix", "mesh", "rotation", "scale", "translation", "weights",
                         "name", "extensions", "extras"});
    auto matrix = read_.numbers(o, p, "matrix", {16});
    auto translation = read_.numbers(o, p, "translation", {3});
    auto rotation = read_.numbers(o, p, "rotation", {4}, {-1, 1});
    auto scale = read_.numbers(o, p, "scale", {3});
    m.camera = read_.index(o, p, "camera");
    if (auto children = read_.indices(o, p, "children")) m.children = *children;
    m.mesh = read_.index(o, p, "mesh");
    m.skin = read_.index(o, p, "skin");
    // A mesh of the wrong type is as good as none (the reference keeps no value for it).
    const bool has_mesh = present(o, "mesh") && is_integer(o["mesh"]);
    if (present(o, "skin") && !has_mesh) context_.issues.at("UNSATISFIED_DEPENDENCY", p + "/skin", {arg("mesh")});
    if (auto weights = read_.numbers(o, p, "weights")) {
      m.weights = static_cast<std::int64_t>(weights->size());
      if (!has_mesh) context_.issues.at("UNSATISFIED_DEPENDENCY", p + "/weights", {arg("mesh")});
    }
    m.has_matrix = matrix.has_value();  // an invalid matrix is ignored
    m.has_trs = rotation || scale || translation;  // as read: an invalid one is ignored too
    if (matrix) {
      static constexpr double identity[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
      const bool is_identity = std::equal(matrix->begin(), matrix->end(), identity);
      const auto& a = *matrix;  // column-major (spec 3.5.2)
      const double determinant = a[0] * (a[5] * a[10] - a[9] * a[6]) - a[4] * (a[1] * a[10] - a[9] * a[2]) +
                                 a[8] * (a[1] * a[6] - a[5] * a[2]);
      const bool affine = a[3] == 0 && a[7] == 0 && a[11] == 0 && a[15] == 1;
      const bool beyond_float =
          std::any_of(a.begin(), a.end(), [](double v) { return std::fabs(v) > 3.4028234663852886e38; });
      const bool not_trs =
          beyond_float || (affine && determinant != 0 && !(largest_column_cosine(a) <= kShearTolerance));  // NaN fails
      // Both judged: a matrix beside TRS properties is still a default or a non-TRS matrix
      // (the reference reports either after NODE_MATRIX_TRS).
      if (m.has_trs) context_.issues.at("NODE_MATRIX_TRS", p + "/matrix");
      if (is_identity)
        context_.issues.at("NODE_MATRIX_DEFAULT", p + "/matrix");
      else if (!affine || determinant == 0 || not_trs)
        context_.issues.at("NODE_MATRIX_NON_TRS", p + "/matrix");
      m.is_identity_transform = is_identity;
    }
    if (rotation) {
      const auto& q = *rotation;
      const double length = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
      // Spec 5.25: a unit quaternion, within the reference's tolerance.
      if (std::fabs(length - 1.0) > kUnitQuaternionTolerance) context_.issues.at("ROTATION_NON_UNIT", p + "/rotation");
      if (q[0] != 0 || q[1] != 0 || q[2] != 0 || q[3] != 1) m.is_identity_transform = false;
    }
    if (scale && ((*scale)[0] != 1 || (*scale)[1] != 1 || (*scale)[2] != 1)) m.is_identity_transform = false;
    if (translation && ((*translation)[0] != 0 || (*translation)[1] != 0 || (*translation)[2] != 0))
      m.is_identity_transform = false;
    read_.string(o, p, "name");
    current_node_ = &m;
    extensions(o, p, Owner::Node);
    current_node_ = nullptr;
    read_.extras(o, p);
    // Completed by the link pass: a camera or mesh counts only when it resolves.
    // An extensions object that holds no extension (empty, or not an object) gives it nothing.
    const bool has_extension = present(o, "extensions") && o["extensions"].is_object() && !o["extensions"].empty();
    m.empty = m.children.empty() && !has_extension && !present(o, "extras");
  }

  void sampler(const Json& o, const std::string& p, SamplerModel& m) {
    read_.check_members(o, p, {"magFilter", "minFilter", "wrapS", "wrapT", "name", "extensions", "extras"});
    read_.integer(o, p, "magFilter", false, {}, {9728, 9729});
    if (auto filter = read_.integer(o, p, "minFilter", false, {}, {9728, 9729, 9984, 9985, 9986, 9987}))
      m.min_filter = *filter;
    read_.integer(o, p, "wrapS", false, {}, {33071, 33648, 10497});
    read_.integer(o, p, "wrapT", false, {}, {33071, 33648, 10497});
    read_.string(o, p, "name");
    extensions(o, p, Owner::Sampler);
    read_.extras(o, p);
  }

  void scene(const Json& o, const std::string& p, SceneModel& m) {
    read_.check_members(o, p, {"nodes", "name", "extensions", "extras"});
    if (auto list = read_.indices(o, p, "nodes")) m.nodes = *list;
    read_.string(o, p, "name");
    extensions(o, p, Owner::Scene);
    read_.extras(o, p);
  }

  void skin(const Json& o, const std::string& p, SkinModel& m) {
    read_.check_members(o, p, {"inverseBindMatrices", "skeleton", "joints", "name", "extensions", "extras"});
    m.inverse_bind_matrices = read_.index(o, p, "inverseBindMatrices");
    m.skeleton = read_.index(o, p, "skeleton");
    if (auto joints = read_.indices(o, p, "joints", true)) m.joints = *joints;
    read_.string(o, p, "name");
    extensions(o, p, Owner::Skin);
    read_.extras(o, p);
  }

  void texture(const Json& o, const std::string& p, TextureModel& m) {
    read_.check_members(o, p, {"sampler", "source", "name", "extensions", "extras"});
    m.sampler = read_.index(o, p, "sampler");
    m.source = read_.index(o, p, "source");
    read_.string(o, p, "name");
    current_texture_ = &m;
    extensions(o, p, Owner::Texture);
    current_texture_ = nullptr;
    read_.extras(o, p);
  }

  Context& context_;
  SchemaReader read_;
  Document& doc_;
  ExtensionHooks hooks_;
  bool last_uri_non_relative_ = false;  // set by check_uri
  // The object being read, for the extension readers (hooks_).
  MaterialModel* current_material_ = nullptr;
  PrimitiveModel* current_primitive_ = nullptr;
  NodeModel* current_node_ = nullptr;
  TextureModel* current_texture_ = nullptr;
  BufferModel* current_buffer_ = nullptr;
  BufferViewModel* current_buffer_view_ = nullptr;
};

}  // namespace

bool walk_schema(Context& context) { return Walker(context).run(); }

}  // namespace gltf_pbr::structure
