// Shared state of the structure validator's passes (validators/structure/*.cpp). The passes run in
// the order the Khronos glTF-Validator reports in: GLB container, JSON parse, schema walk (with the
// checks that need one object only), links (references, bounds, usages), unused objects, then
// resources (buffers, images) and accessor data.
#pragma once
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/files.hpp"
#include "core/json.hpp"
#include "core/json_pointer.hpp"
#include "core/meshopt.hpp"
#include "core/report.hpp"
#include "rules/issue_sink.hpp"
#include "rules/rule_set.hpp"
#include "validators/structure/structure.hpp"

namespace gltf_pbr::structure {

// How far from unit length a vector may be (the spec gives no tolerance; the reference's, found by
// bisection on its answers to constructed files): a NORMAL or a TANGENT's xyz passes at 0.00674
// and fails at 0.006745; a quaternion (a node's rotation, an animation's rotation output) passes at
// 0.007688 and fails at 0.00769, either side of 1 (tests/structure, UnitLength).
constexpr double kUnitVector3Tolerance = 0.006742;
constexpr double kUnitQuaternionTolerance = 0.007689;

using Json = JsonDocument;

// Arguments of the catalogue's templates (Rule::format fills them): numbers follow Dart's printing
// (the reference runs on the Dart VM: integral doubles print as "1.0"), strings are quoted where the
// template quotes them.
MessageArg arg(std::string_view text);  // a string
MessageArg arg(std::int64_t value);
MessageArg arg(std::uint64_t value);
MessageArg arg(int value);
MessageArg arg_double(double value);
MessageArg arg_json(const Json& value);  // a JSON value as the reference prints it
MessageArg arg_raw(std::string text);    // never quoted

std::string format_double(double value);


struct Document;
struct AccessorModel;
// The bytes of buffer view `index` when its buffer has loaded and the view lies inside it (and
// inside the buffer's declared byteLength); std::nullopt otherwise, and for a view whose offset is
// unusable (-1). A compressed view's bytes are its decoded ones (EXT_meshopt_compression), once the
// data pass decoded them.
std::optional<std::span<const std::uint8_t>> buffer_view_bytes(const Document& doc, std::int64_t index);
// Accessor `index` when it names a JSON object of the document, else nullptr.
const AccessorModel* accessor_object(const Document& doc, std::int64_t index);

// The set number n of a semantic PREFIXn ("TEXCOORD_1" → 1), when n is written the schema's way.
std::optional<int> set_number(const std::string& name, std::string_view prefix);

// ---- The document model the schema walk fills and the later passes read. Indices are -1 when
// absent or invalid; every entity remembers whether it was a JSON object (non-objects are reported
// once and skipped afterwards) and whether anything references it (UNUSED_OBJECT).

// What every entity of the model records: whether it was a JSON object, whether it has every
// required property (only then is it linked and checked), and whether anything references it.
struct EntityModel {
  bool object = false;
  bool valid = true;
  bool used = false;
};

struct AccessorModel : EntityModel {
  std::int64_t buffer_view = -1;
  std::int64_t byte_offset = 0;
  bool has_byte_offset = false;
  bool offset_unusable = false;  // a byteOffset of the wrong type or range
  int component_type = 0;        // 0: absent or invalid
  std::int64_t count = -1;
  std::string type;  // "" when absent or invalid
  bool normalized = false;
  bool has_min = false, has_max = false;
  std::vector<double> min, max;
  bool sparse = false;
  std::int64_t sparse_count = 0;
  std::int64_t sparse_indices_view = -1, sparse_indices_offset = 0;
  int sparse_indices_component_type = 0;
  std::int64_t sparse_values_view = -1, sparse_values_offset = 0;
  // Usage, for the data checks: where the first use is and what it asks of the values.
  enum class Usage { None, Vertex, Index, AnimationInput, AnimationOutput, InverseBindMatrices, Other };
  Usage usage = Usage::None;
  std::string semantic;        // first mesh attribute semantic (NORMAL, TANGENT, COLOR_0, ...)
  // A mesh attribute found outside its semantic's format table: its values are not judged as that
  // semantic's (a NORMAL of bytes that are not normalized has no unit length to check).
  bool semantic_format_invalid = false;
  std::string usage_pointer;   // pointer of the first use that carries a data check
  std::string animation_path;  // for AnimationOutput
  std::string interpolation;
  // Indices: each primitive that draws with them, in document order. Spec 3.7.2.1 bounds an index by
  // the vertices of the primitive that reads it, so each is checked against its own.
  struct IndexUse {
    std::string pointer;
    std::int64_t vertex_limit = -1;  // -1: unknown
    int mode = 4;
  };
  std::vector<IndexUse> index_uses;
  bool fits = false;  // the link pass found it inside its buffer view
  // Every use that reads it as its first use does (a mesh attribute with the first semantic, an
  // animation sampler's input, a channel of the first path reading its output): the reference
  // checks each element once for each of them (a NORMAL shared by two primitives, or key times
  // shared by two samplers, are reported at both).
  std::vector<std::string> data_uses;

  // glTF 2.0 section 3.7.2.1: indices are unsigned scalars, not normalized. Only such an accessor's
  // values are index-checked (the npm validator checks a float one's none, whatever they hold).
  bool has_index_format() const {
    return type == "SCALAR" && !normalized &&
           (component_type == 5121 || component_type == 5123 || component_type == 5125);
  }
};

struct BufferViewModel : EntityModel {
  std::int64_t buffer = -1;
  std::int64_t byte_offset = 0;
  std::int64_t byte_length = -1;
  std::int64_t byte_stride = 0;
  int target = 0;
  int usage_target = 0;  // 34962 vertex, 34963 index; links.cpp kViewUsageIbm, kViewUsageOther
  std::string usage_name;
  int accessor_uses = 0;  // attribute accessors referencing it (MESH_PRIMITIVE_ACCESSOR_WITHOUT_BYTESTRIDE)
  // EXT_meshopt_compression: whether the view has the extension, its content when that is valid,
  // and the decoded bytes once the data pass decoded them (meshopt.cpp).
  bool meshopt_present = false;
  std::optional<MeshoptView> meshopt;
  std::optional<std::vector<std::uint8_t>> decoded;
};

struct BufferModel : EntityModel {
  bool has_uri = false;
  bool uri_valid = false;
  bool data_uri = false;
  bool non_relative = false;  // named by an absolute URI: reported, never fetched
  bool meshopt_fallback = false;  // EXT_meshopt_compression {"fallback": true}
  std::string uri;
  std::int64_t byte_length = -1;
  std::vector<std::uint8_t> owned;            // decoded data URI
  std::shared_ptr<const MappedFile> file;     // external file, mapped through FileResources
  std::span<const std::uint8_t> data;         // the bytes: `owned`, `file`, or the GLB BIN chunk (not copied)
  bool data_loaded = false;
};

struct TextureRef {
  std::string pointer;  // of the textureInfo object
  std::int64_t index = -1;
  std::int64_t tex_coord = 0;             // -1: unreadable (a fraction, a string): no set is needed
  std::int64_t transform_tex_coord = -1;  // KHR_texture_transform's set, where it is declared and read
};

struct MaterialModel : EntityModel {
  std::vector<TextureRef> textures;  // in the order the reference lists texture bindings
  bool has_normal_texture = false;
  bool needs_tangents = false;  // a texture defined in tangent space (clearcoat normal, anisotropy)
  std::int64_t normal_tex_coord = 0;
  // (code, pointer) of what its extensions' rules found: reported when the material is linked.
  std::vector<std::pair<std::string, std::string>> extension_issues;
};

struct PrimitiveModel {
  bool object = false;
  std::string pointer;
  std::vector<std::pair<std::string, std::int64_t>> attributes;  // JSON order
  std::int64_t indices = -1;
  std::int64_t material = -1;
  int mode = 4;               // -1: present but not an integer in 0-6: no count judged, indices read as triangles
  std::int64_t targets = -1;  // -1: no targets property, or one that cannot be read whole
  // As many JOINTS_n as WEIGHTS_n sets, at least one, each semantic's sets numbered from 0 without
  // a gap (spec 3.7.3.1): what a skin can bind.
  bool skinned = false;
  std::vector<std::vector<std::pair<std::string, std::int64_t>>> target_attributes;
  bool draco = false;
  std::int64_t draco_buffer_view = -1;
  std::map<std::string, std::int64_t> draco_attributes;
  // KHR_materials_variants mappings, in document order; each is linked as a whole.
  struct VariantMapping {
    std::string pointer;
    std::vector<std::pair<std::string, std::int64_t>> variants;  // (pointer, variant index)
    std::string material_pointer;
    std::int64_t material = -1;
  };
  std::vector<VariantMapping> variant_mappings;
};

struct MeshModel : EntityModel {
  std::vector<PrimitiveModel> primitives;
  bool primitives_known = false;  // its primitives array could be read
  std::int64_t weights = -1;
  // The skin of the last node, in node order, that draws this mesh with a skin: the joints are
  // checked against it.
  std::int64_t skin = -1;
  std::int64_t joint_count = -1;
};

struct NodeModel : EntityModel {
  std::int64_t camera = -1, skin = -1, mesh = -1, light = -1;
  std::string light_pointer;  // of its KHR_lights_punctual object, when it has one
  std::vector<std::int64_t> children;
  bool has_matrix = false, has_trs = false;
  bool is_identity_transform = true;
  std::int64_t weights = -1;
  std::int64_t parent = -1;
  bool empty = false;
  bool joint = false;
};

struct SkinModel : EntityModel {
  std::int64_t inverse_bind_matrices = -1, skeleton = -1;
  std::vector<std::int64_t> joints;
  bool has_common_root = true;  // set when linked
};

struct AnimationSamplerModel : EntityModel {
  std::int64_t input = -1, output = -1;
  std::string interpolation = "LINEAR";
};
struct AnimationChannelModel {
  bool object = false;
  std::int64_t sampler = -1, node = -1;
  std::string path;
  bool pointer_extension = false;  // a declared KHR_animation_pointer object on the target
  bool target_has_node = false;
  std::string raw_path;  // target.path as written, when a string
};
struct AnimationModel {
  bool object = false;
  bool valid = true;
  std::vector<AnimationSamplerModel> samplers;
  std::vector<AnimationChannelModel> channels;
};

struct ImageModel : EntityModel {
  std::string uri;
  bool has_uri = false, uri_valid = false, data_uri = false;
  // mimeType when it is a string, "" and types out of the list included (the reference keeps them
  // as declared).
  std::optional<std::string> mime_type;
  std::string data_uri_mime;
  std::string detected_mime;  // what its bytes are, when they were read and recognised
  std::int64_t buffer_view = -1;
  std::vector<std::uint8_t> data;  // decoded data URI
};

struct TextureModel : EntityModel {
  std::int64_t sampler = -1, source = -1;
  std::vector<std::pair<std::string, std::int64_t>> extension_sources;  // pointer, image index
};

struct SimpleModel : EntityModel {};

struct SceneModel : EntityModel {
  std::vector<std::int64_t> nodes;  // the roots
};

struct SamplerModel : EntityModel {
  std::int64_t min_filter = -1;  // -1: undefined (the client chooses)
};

struct Document {
  std::vector<AccessorModel> accessors;
  std::vector<AnimationModel> animations;
  std::vector<BufferModel> buffers;
  std::vector<BufferViewModel> buffer_views;
  std::vector<SimpleModel> cameras;
  std::vector<ImageModel> images;
  std::vector<MaterialModel> materials;
  std::vector<MeshModel> meshes;
  std::vector<NodeModel> nodes;
  std::vector<SamplerModel> samplers;
  std::vector<SceneModel> scenes;
  std::int64_t scene = -1;
  std::vector<SkinModel> skins;
  std::vector<TextureModel> textures;
  std::vector<SimpleModel> lights;
  std::vector<SimpleModel> variants;
  bool has_lights_root = false, has_variants_root = false;
  std::vector<std::string> extensions_used;
  std::vector<std::string> extensions_seen;  // known extension objects met anywhere, declared or not
  std::vector<std::string> extensions_required;
  std::string version;
};

// A reference to check in the link pass: pointer, index and which collection it targets.
struct Context {
  Context(const RuleSet& rules, Report& report_, const StructureOptions& options_, FileResources& resources_)
      : issues(rules, report_), report(report_), options(options_), files(resources_) {}
  IssueSink issues;
  Report& report;
  const StructureOptions& options;
  FileResources& files;  // external files and Draco meshes, shared with the loader (core/resources.hpp)
  bool glb = false;
  std::optional<std::span<const std::uint8_t>> glb_bin;  // the GLB BIN chunk, when present
  bool glb_bin_chunk = false;                            // a BIN chunk header was read (its data may be cut short)
  // GLB issues found where the stream ends (data cut short, a length that does not add up): the
  // reference reads the container as a stream and validates the JSON chunk as soon as it has it,
  // so these follow the document's schema, link and unused issues.
  struct OffsetIssue {
    std::string code;
    std::uint64_t offset;
    std::vector<MessageArg> args;
  };
  std::vector<OffsetIssue> glb_end_issues;
  // The GLB stream ended inside a chunk's header or data: its resources cannot be trusted.
  bool glb_ended_inside_chunk = false;
  Json root;
  JsonFlawsSeen json_flaws;  // what the reader saw; kept with the tree for the loader
  Document doc;
  nlohmann::ordered_json resources = nlohmann::ordered_json::array();  // info.resources, in order
  bool declared(std::string_view extension) const;
};

// The external resource `uri` (at `pointer`), through the file's resources and their path policy.
// A missing file is the reference's IO_ERROR "Resource not found"; a URI the policy refuses is an
// IO_ERROR saying why, and its file is never opened. Null in both cases.
std::shared_ptr<const MappedFile> read_resource(Context& context, const std::string& uri, const std::string& pointer);

// ---- Passes.
// Splits a GLB into its JSON and BIN chunks, reporting container issues by byte offset. Returns the
// JSON text to parse, or nullopt when there is none (the reference then stops).
std::optional<std::span<const std::uint8_t>> read_glb(std::span<const std::uint8_t> bytes, Context& context,
                                                      bool& empty_json_ended);
// Parses JSON text into context.root, reporting INVALID_JSON; false when unreadable.
bool parse_json(std::span<const std::uint8_t> text, Context& context);
bool walk_schema(Context& context);      // false: stop (no usable asset)      // schema.cpp
void check_links(Context& context);      // links.cpp
void report_unused(Context& context);    // links.cpp
void check_resources(Context& context);  // data.cpp: buffers, images, accessor data
void fill_info(Context& context);        // info.cpp

// Accessor helpers shared by links and data.
int component_size(int component_type);
int component_count(const std::string& type);
const char* component_type_name(int component_type);

}  // namespace gltf_pbr::structure
