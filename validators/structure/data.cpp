// Resources and data: buffer bytes (data URIs, external files, the GLB BIN chunk), then accessor
// values against what their users require (glTF 2.0 spec 3.6.2 "Accessors", 3.7.2.1 "Overview"
// of mesh attributes, 3.11 "Animations", 3.7.3 "Skins"). Every read is bounded by the bytes that
// are really there, whatever the JSON claims.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#include "core/files.hpp"
#include "validators/structure/images.hpp"
#include "validators/structure/structure_internal.hpp"

namespace gltf_pbr::structure {

std::shared_ptr<const MappedFile> read_resource(Context& context, const std::string& uri, const std::string& pointer) {
  const FileResources::External& external = context.files.external(uri);
  if (external.resolved.status == UriStatus::Refused)
    context.issues.at("IO_ERROR", pointer, {arg_raw(external.resolved.problem + ".")});
  else if (!external.file)
    context.issues.at("IO_ERROR", pointer, {arg_raw("Resource not found (" + uri + ").")});
  return external.file;
}

namespace {

// Reads one component at `base` as a double; the caller has checked the bounds.
template <typename T>
inline double load(const std::uint8_t* base) {
  T value;
  std::memcpy(&value, base, sizeof(T));
  return static_cast<double>(value);
}

using Values = std::vector<double>;

// Accessor values are read in chunks of this many elements (a multiple of 3, so a chunk of
// triangle indices holds whole triangles): memory stays flat whatever the accessor's size, and a
// chunk stays in cache between its decode and its checks.
constexpr std::int64_t kChunkElements = 3 * 16384;

class AccessorData {
 public:
  explicit AccessorData(Context& context) : issues_(context.issues), doc_(context.doc) {}

  void run() {
    for (std::size_t i = 0; i < doc_.accessors.size(); ++i)
      if (doc_.accessors[i].object && doc_.accessors[i].valid) accessor(i);
    skinning();
  }

 private:
  std::optional<std::span<const std::uint8_t>> view_bytes(std::int64_t index) const {
    return buffer_view_bytes(doc_, index);
  }

  // Decodes elements [first, first + count) of the accessor (sparse substitution applied) into
  // `out`, component-major per element. Returns false when the data is unavailable. Sparse
  // accessors are decoded whole (first 0, count all), and their issues reported only when
  // `report_sparse` (the accessor's own first pass), not when it is read again or as a partner.
  bool decode(const AccessorModel& a, bool report_sparse, std::int64_t first, std::int64_t count, Values& out) {
    const int components = component_count(a.type);
    const int size = component_size(a.component_type);
    if (components == 0 || size == 0 || a.count <= 0) return false;
    std::optional<std::span<const std::uint8_t>> bytes;
    if (a.buffer_view >= 0) {
      if (!a.fits) return false;
      bytes = view_bytes(a.buffer_view);
      if (!bytes) return false;
    } else if (!a.sparse) {
      return false;  // all zeros: nothing to check
    }
    // count and components come from the JSON: a product that does not fit is no real accessor.
    std::uint64_t total = 0;
    if (__builtin_mul_overflow(static_cast<std::uint64_t>(count), static_cast<std::uint64_t>(components), &total) ||
        total > std::numeric_limits<std::size_t>::max() / sizeof(double))
      return false;
    // Without a buffer view the JSON alone sets the count: refuse what no real file could hold.
    if (!bytes && total > (1u << 26)) return false;
    // Every value is written below (or is zero for sparse-only accessors).
    if (bytes && !a.sparse)
      out.resize(static_cast<std::size_t>(total));
    else
      out.assign(static_cast<std::size_t>(total), 0.0);
    if (bytes) {
      const std::int64_t view_stride = doc_.buffer_views[static_cast<std::size_t>(a.buffer_view)].byte_stride;
      const bool matrix_padding = a.type.starts_with("MAT") && size < 4;
      const int rows = a.type == "MAT2" ? 2 : a.type == "MAT3" ? 3 : a.type == "MAT4" ? 4 : components;
      const int column_bytes = matrix_padding ? (rows * size + 3) / 4 * 4 : rows * size;
      const std::int64_t element_bytes = matrix_padding ? column_bytes * (components / rows) : size * components;
      const std::int64_t stride = view_stride > 0 ? view_stride : element_bytes;
      const std::uint8_t* base = bytes->data() + a.byte_offset + first * stride;
      switch (a.component_type) {
        case 5120:
          fill<std::int8_t>(base, stride, count, components, rows, column_bytes, out);
          break;
        case 5121:
          fill<std::uint8_t>(base, stride, count, components, rows, column_bytes, out);
          break;
        case 5122:
          fill<std::int16_t>(base, stride, count, components, rows, column_bytes, out);
          break;
        case 5123:
          fill<std::uint16_t>(base, stride, count, components, rows, column_bytes, out);
          break;
        case 5125:
          fill<std::uint32_t>(base, stride, count, components, rows, column_bytes, out);
          break;
        case 5126:
          fill<float>(base, stride, count, components, rows, column_bytes, out);
          break;
        default:
          return false;
      }
    }
    if (a.sparse && !apply_sparse(a, components, report_sparse, out)) return false;
    return true;
  }

  template <typename T>
  static void fill(const std::uint8_t* base, std::int64_t stride, std::int64_t count, int components, int rows,
                   int column_bytes, Values& values) {
    double* out = values.data();
    if (rows == components && stride == static_cast<std::int64_t>(sizeof(T)) * components) {
      // Tightly packed (most vertex data and all indices): one straight run of components.
      const std::int64_t total = count * components;
      for (std::int64_t k = 0; k < total; ++k) out[k] = load<T>(base + k * static_cast<std::int64_t>(sizeof(T)));
      return;
    }
    const int columns = components / rows;
    for (std::int64_t e = 0; e < count; ++e) {
      const std::uint8_t* element = base + e * stride;
      for (int column = 0; column < columns; ++column)
        for (int row = 0; row < rows; ++row) *out++ = load<T>(element + column * column_bytes + row * sizeof(T));
    }
  }

  bool apply_sparse(const AccessorModel& a, int components, bool report, Values& out) {
    auto indices = view_bytes(a.sparse_indices_view);
    auto values = view_bytes(a.sparse_values_view);
    const int index_size = component_size(a.sparse_indices_component_type);
    const int value_size = component_size(a.component_type);
    if (!indices || !values || index_size == 0) return false;
    const std::uint64_t n = static_cast<std::uint64_t>(a.sparse_count);
    if (n > indices->size() || n > values->size()) return false;  // cannot fit: no products overflow below
    if (static_cast<std::uint64_t>(a.sparse_indices_offset) + n * index_size > indices->size()) return false;
    if (static_cast<std::uint64_t>(a.sparse_values_offset) + n * components * value_size > values->size()) return false;
    const std::string pointer = "/accessors/" + std::to_string(&a - doc_.accessors.data()) + "/sparse";
    IssueSink* issues = report ? &issues_ : nullptr;
    std::int64_t previous = -1;
    for (std::uint64_t k = 0; k < n; ++k) {
      const std::uint8_t* at = indices->data() + a.sparse_indices_offset + k * index_size;
      const std::int64_t index = static_cast<std::int64_t>(index_size == 1   ? load<std::uint8_t>(at)
                                                           : index_size == 2 ? load<std::uint16_t>(at)
                                                                             : load<std::uint32_t>(at));
      if (index <= previous && issues)
        issues->at("ACCESSOR_SPARSE_INDICES_NON_INCREASING", pointer,
                   {arg(static_cast<std::uint64_t>(k)), arg(index), arg(previous)});
      if (index >= a.count) {
        if (issues)
          issues->at("ACCESSOR_SPARSE_INDEX_OOB", pointer,
                     {arg(static_cast<std::uint64_t>(k)), arg(index), arg(a.count)});
        previous = index;
        continue;
      }
      previous = index;
      const std::uint8_t* value = values->data() + a.sparse_values_offset + k * components * value_size;
      for (int c = 0; c < components; ++c) {
        const std::uint8_t* v = value + c * value_size;
        double number = 0;
        switch (a.component_type) {
          case 5120:
            number = load<std::int8_t>(v);
            break;
          case 5121:
            number = load<std::uint8_t>(v);
            break;
          case 5122:
            number = load<std::int16_t>(v);
            break;
          case 5123:
            number = load<std::uint16_t>(v);
            break;
          case 5125:
            number = load<std::uint32_t>(v);
            break;
          case 5126:
            number = load<float>(v);
            break;
        }
        const auto slot = static_cast<std::size_t>(index) * static_cast<std::size_t>(components) + c;
        if (slot < out.size()) out[slot] = number;  // out holds the whole accessor (sparse is decoded whole)
      }
    }
    return true;
  }

  // A value as the reference prints it: floats as doubles, integers as integers.
  static MessageArg value_arg(const AccessorModel& a, double value) {
    return a.component_type == 5126 ? arg_double(value) : arg(static_cast<std::int64_t>(value));
  }

  static double normalized(const AccessorModel& a, double value) {
    if (!a.normalized) return value;
    switch (a.component_type) {
      case 5120:
        return std::max(value / 127.0, -1.0);
      case 5121:
        return value / 255.0;
      case 5122:
        return std::max(value / 32767.0, -1.0);
      case 5123:
        return value / 65535.0;
      default:
        return value;
    }
  }

  // State carried from chunk to chunk by the usage checks.
  struct Carry {
    std::vector<std::uint64_t> degenerate_triangles;  // for each of an index accessor's uses
    double previous_time = 0.0;
    // Index issues past the report's listing of their code, the first included (added when found):
    // counted here and the rest added at the end as one count (n indices shared by u primitives may
    // hold n u of them).
    std::uint64_t unlisted_out_of_range = 0, unlisted_restarts = 0;
    std::vector<double> sorted_limits;  // the uses' vertex counts, for counting past the listing
  };

  void accessor(std::size_t i) {
    const AccessorModel& a = doc_.accessors[i];
    const std::string p = "/accessors/" + std::to_string(i);
    const std::string& use = a.usage_pointer.empty() ? p : a.usage_pointer;
    const int components = component_count(a.type);
    const bool is_float = a.component_type == 5126;
    if (components == 0 || a.count <= 0) return;
    // Sparse data is substituted over the whole accessor, so sparse accessors are read in one piece.
    const std::int64_t chunk = a.sparse ? a.count : kChunkElements;

    // Pass 1: invalid floats in element order, and the actual bounds for the declared ones.
    // Declared bounds of float accessors are compared at float precision: the JSON double is
    // what a writer printed for the float it stored.
    auto as_stored = [&](double declared) {
      return is_float ? static_cast<double>(static_cast<float>(declared)) : declared;
    };
    const bool min_declared = a.has_min && static_cast<int>(a.min.size()) == components;
    const bool max_declared = a.has_max && static_cast<int>(a.max.size()) == components;
    std::array<double, 16> actual_min, actual_max, declared_min, declared_max;
    std::array<std::uint64_t, 16> below{}, above{};
    for (int c = 0; c < components; ++c) {
      actual_min[c] = INFINITY;
      actual_max[c] = -INFINITY;
      declared_min[c] = min_declared ? as_stored(a.min[c]) : -INFINITY;
      declared_max[c] = max_declared ? as_stored(a.max[c]) : INFINITY;
    }
    const bool usage = has_usage_checks(a);
    // Only floats can hold invalid values and only declared bounds can be broken: without either,
    // pass 1 has nothing to say and the usage checks run alone (sparse issues are reported by the
    // first decode, so a sparse accessor always has one).
    const bool pass_one = is_float || min_declared || max_declared || a.sparse;
    const bool one_chunk = chunk >= a.count;
    for (std::int64_t first = 0; pass_one && first < a.count; first += chunk) {
      const std::int64_t n = std::min(chunk, a.count - first);
      if (!decode(a, first == 0, first, n, values_)) return;
      const double* value = values_.data();
      for (std::int64_t e = first; e < first + n; ++e) {
        for (int c = 0; c < components; ++c, ++value) {
          const double v = *value;
          // The actual bounds start at the first element, whatever it holds, and take a value
          // only where it compares below or above them: a NaN first element leaves NaN bounds,
          // a later one is passed over (the reference's answers on constructed files).
          if (e == 0) {
            actual_min[c] = actual_max[c] = v;
          } else {
            if (v < actual_min[c]) actual_min[c] = v;
            if (v > actual_max[c]) actual_max[c] = v;
          }
          // An invalid float is the accessor's own fault: named at the accessor, whoever uses it.
          if (is_float && !std::isfinite(v)) {
            issues_.at("ACCESSOR_INVALID_FLOAT", p,
                       {arg(static_cast<std::uint64_t>(e * components + c)), arg_double(v)});
            continue;
          }
          below[c] += v < declared_min[c];
          above[c] += v > declared_max[c];
        }
      }
    }
    // Pass 2: what the accessor's user requires, chunk by chunk in element order. A single
    // chunk already decoded by pass 1 is checked as it is.
    Carry carry;
    for (std::int64_t first = 0; usage && first < a.count; first += chunk) {
      const std::int64_t n = std::min(chunk, a.count - first);
      if (!(pass_one && one_chunk) && !decode(a, !pass_one && first == 0, first, n, values_)) return;
      usage_checks(a, use, static_cast<std::size_t>(first), static_cast<std::size_t>(n), carry);
    }
    // The declared bounds are judged once every element is seen: after the elements' own issues,
    // as the reference reports them (checked against the npm validator).
    bounds(a, p, components, actual_min, actual_max, below, above);
    if (usage && a.usage == AccessorModel::Usage::Index && !a.index_uses.empty()) {  // the first was added
      const std::string& pointer = a.index_uses.front().pointer;
      if (carry.unlisted_out_of_range > 1)
        issues_.at_unlisted("ACCESSOR_INDEX_OOB", pointer, carry.unlisted_out_of_range - 1);
      if (carry.unlisted_restarts > 1)
        issues_.at_unlisted("ACCESSOR_INDEX_PRIMITIVE_RESTART", pointer, carry.unlisted_restarts - 1);
    }
    if (usage && a.usage == AccessorModel::Usage::Index)
      for (std::size_t u = 0; u < carry.degenerate_triangles.size(); ++u)
        if (carry.degenerate_triangles[u])
          issues_.at("ACCESSOR_INDEX_TRIANGLE_DEGENERATE", a.index_uses[u].pointer,
                     {arg(carry.degenerate_triangles[u]), arg(static_cast<std::uint64_t>(a.count / 3))});
  }

  static bool has_usage_checks(const AccessorModel& a) {
    using Usage = AccessorModel::Usage;
    const int components = component_count(a.type);
    const std::string& semantic = a.semantic;
    switch (a.usage) {
      case Usage::Index:
        return components == 1;
      case Usage::Vertex:
        // JOINTS_n and WEIGHTS_n are checked together, per primitive, by skinning() afterwards.
        return (semantic == "NORMAL" && components == 3) || (semantic == "TANGENT" && components == 4) ||
               (semantic.starts_with("COLOR_") && a.component_type == 5126);
      case Usage::AnimationInput:
        return components == 1 && a.component_type == 5126;
      case Usage::AnimationOutput:
        return a.animation_path == "rotation" && components == 4;
      case Usage::InverseBindMatrices:  // another format is already SKIN_IBM_INVALID_FORMAT: not read
        return components == 16 && a.component_type == 5126;
      default:
        return false;
    }
  }

  // `values_` holds elements [first, first + count).
  void usage_checks(const AccessorModel& a, const std::string& use, std::size_t first, std::size_t count,
                    Carry& carry) {
    using Usage = AccessorModel::Usage;
    switch (a.usage) {
      case Usage::Index:
        if (a.has_index_format()) index_checks(a, first, carry);
        break;
      case Usage::Vertex:
        vertex_checks(a, first, count);
        break;
      case Usage::AnimationInput:
        animation_input(a.data_uses.empty() ? std::span(&use, 1) : std::span(a.data_uses), first, carry);
        break;
      case Usage::AnimationOutput:
        quaternions(a, a.data_uses.empty() ? std::span(&use, 1) : std::span(a.data_uses), first, count);
        break;
      case Usage::InverseBindMatrices:
        inverse_bind_matrices(use, first, count);
        break;
      default:
        break;
    }
  }

  void bounds(const AccessorModel& a, const std::string& p, int components, const std::array<double, 16>& actual_min,
              const std::array<double, 16>& actual_max, const std::array<std::uint64_t, 16>& below,
              const std::array<std::uint64_t, 16>& above) {
    const bool is_float = a.component_type == 5126;
    auto same = [&](double declared, double actual) {
      return is_float ? static_cast<float>(declared) == static_cast<float>(actual) : declared == actual;
    };
    if (a.has_min && static_cast<int>(a.min.size()) == components) {
      for (int c = 0; c < components; ++c) {
        const std::string pointer = p + "/min/" + std::to_string(c);
        if (!same(a.min[c], actual_min[c]))
          issues_.at("ACCESSOR_MIN_MISMATCH", pointer, {value_arg(a, a.min[c]), value_arg(a, actual_min[c])});
        if (below[c]) issues_.at("ACCESSOR_ELEMENT_OUT_OF_MIN_BOUND", pointer, {arg(below[c]), value_arg(a, a.min[c])});
      }
    }
    if (a.has_max && static_cast<int>(a.max.size()) == components) {
      for (int c = 0; c < components; ++c) {
        const std::string pointer = p + "/max/" + std::to_string(c);
        if (!same(a.max[c], actual_max[c]))
          issues_.at("ACCESSOR_MAX_MISMATCH", pointer, {value_arg(a, a.max[c]), value_arg(a, actual_max[c])});
        if (above[c]) issues_.at("ACCESSOR_ELEMENT_OUT_OF_MAX_BOUND", pointer, {arg(above[c]), value_arg(a, a.max[c])});
      }
    }
  }

  // Each element against each primitive that draws with the accessor, element by element (the
  // reference's order), each use with its own vertex count and mode.
  void index_checks(const AccessorModel& a, std::size_t first, Carry& carry) {
    const double restart = a.component_type == 5121 ? 255.0 : a.component_type == 5123 ? 65535.0 : 4294967295.0;
    if (a.index_uses.empty()) return;
    carry.degenerate_triangles.resize(a.index_uses.size());
    // Once a code's listing is full the report only counts it (it never empties again): the first
    // issue past it is added, to take its place in the report, and the rest are counted.
    const auto listed = [&](const char* code, std::uint64_t& unlisted, const std::string& pointer) {
      if (unlisted > 0) return ++unlisted, false;
      if (!issues_.listing_full(code)) return true;
      issues_.at_unlisted(code, pointer, 1);
      unlisted = 1;
      return false;
    };
    if (carry.sorted_limits.empty()) {
      for (const AccessorModel::IndexUse& use : a.index_uses)
        carry.sorted_limits.push_back(use.vertex_limit >= 0 ? static_cast<double>(use.vertex_limit) : INFINITY);
      std::sort(carry.sorted_limits.begin(), carry.sorted_limits.end());
    }
    const std::uint64_t uses = a.index_uses.size();
    for (std::size_t k = 0; k < values_.size(); ++k) {
      const double value = values_[k];
      // With both codes only counted, an element costs a search, not a pass over every use (n
      // indices drawn by u primitives are n u checks otherwise).
      if (carry.unlisted_out_of_range > 0 && (carry.unlisted_restarts > 0 || value != restart)) {
        carry.unlisted_out_of_range +=
            static_cast<std::uint64_t>(std::upper_bound(carry.sorted_limits.begin(), carry.sorted_limits.end(), value) -
                                       carry.sorted_limits.begin());
        if (value == restart) carry.unlisted_restarts += uses;
        continue;
      }
      if (value < carry.sorted_limits.front() && value != restart) continue;  // in range for every use
      for (const AccessorModel::IndexUse& use : a.index_uses) {
        const double limit = use.vertex_limit >= 0 ? static_cast<double>(use.vertex_limit) : INFINITY;  // -1: unknown
        // A restart value is also out of bounds when the vertices do not reach it: both are
        // reported, in this order (checked against the npm validator).
        if (value >= limit && listed("ACCESSOR_INDEX_OOB", carry.unlisted_out_of_range, use.pointer))
          issues_.at("ACCESSOR_INDEX_OOB", use.pointer,
                     {arg(static_cast<std::uint64_t>(first + k)), arg(static_cast<std::int64_t>(value)),
                      arg(use.vertex_limit - 1)});
        if (value == restart && listed("ACCESSOR_INDEX_PRIMITIVE_RESTART", carry.unlisted_restarts, use.pointer))
          issues_.at("ACCESSOR_INDEX_PRIMITIVE_RESTART", use.pointer,
                     {arg(static_cast<std::int64_t>(value)), arg(static_cast<std::uint64_t>(first + k))});
      }
    }
    // Chunks hold whole triangles (kChunkElements is a multiple of 3; a whole accessor is one
    // chunk), counted once for every use that draws triangles.
    const bool triangles = std::any_of(a.index_uses.begin(), a.index_uses.end(),
                                       [](const AccessorModel::IndexUse& use) { return use.mode == 4; });
    if (!triangles || a.count < 3) return;
    std::uint64_t degenerate = 0;
    for (std::size_t t = 0; t + 2 < values_.size(); t += 3) {
      const double i0 = values_[t], i1 = values_[t + 1], i2 = values_[t + 2];
      degenerate += i0 == i1 || i1 == i2 || i0 == i2;
    }
    for (std::size_t u = 0; u < a.index_uses.size(); ++u)
      if (a.index_uses[u].mode == 4) carry.degenerate_triangles[u] += degenerate;
  }

  // Each element is checked for every attribute that reads the accessor, in element order.
  void vertex_checks(const AccessorModel& a, std::size_t first, std::size_t count) {
    const std::string& semantic = a.semantic;
    const int components = component_count(a.type);
    const std::vector<std::string>& uses = a.data_uses;
    if (a.semantic_format_invalid) return;
    if ((semantic == "NORMAL" && components == 3) || (semantic == "TANGENT" && components == 4)) {
      for (std::size_t e = 0; e < count; ++e) {
        const double* v = &values_[e * components];
        const double x = normalized(a, v[0]), y = normalized(a, v[1]), z = normalized(a, v[2]);
        const double length = std::sqrt(x * x + y * y + z * z);
        const std::uint64_t index = (first + e) * components;
        const double w = components == 4 ? normalized(a, v[3]) : 1.0;
        // Check by check, each at every use.
        if (std::fabs(length - 1.0) > kUnitVector3Tolerance)
          for (const std::string& use : uses)
            issues_.at("ACCESSOR_VECTOR3_NON_UNIT", use, {arg(index), arg(index + 2), arg_double(length)});
        if (w != 1.0 && w != -1.0)
          for (const std::string& use : uses)
            issues_.at("ACCESSOR_INVALID_SIGN", use, {arg(index), arg(index + 3), arg_double(w)});
      }
    } else if (semantic.starts_with("COLOR_") && a.component_type == 5126) {
      for (std::size_t k = 0; k < values_.size(); ++k)
        if (values_[k] < 0.0 || values_[k] > 1.0)
          for (const std::string& use : uses)
            issues_.at("ACCESSOR_NON_CLAMPED", use,
                       {arg(static_cast<std::uint64_t>(first * components + k)), arg_double(values_[k])});
    }
  }

  // One JOINTS_n/WEIGHTS_n pair of a skinned primitive, with the elements it holds: a window of
  // the current chunk, or (when either accessor is sparse, decoded whole) all of them.
  struct SkinSet {
    const AccessorModel* joints;
    const AccessorModel* weights;
    std::string joints_pointer, weights_pointer;
    Values joint_values, weight_values;
    std::int64_t held_first = 0, held_count = 0;
    bool whole() const { return joints->sparse || weights->sparse; }
  };
  struct SkinnedPrimitive {
    std::vector<SkinSet> sets;  // by set number
    std::int64_t count = 0;     // vertices
    std::int64_t skin = -1, joint_count = -1;
    double sum = 0;  // the current vertex's weights that passed their checks
  };

  // Whether decode() can read the accessor: in its buffer view, or sparse over zeros.
  static bool readable(const AccessorModel& a) {
    return a.object && a.valid && component_count(a.type) == 4 && (a.buffer_view >= 0 ? a.fits : a.sparse);
  }

  // Makes `set` hold elements [first, first + n) (a whole set once); false when they cannot be read.
  bool hold(SkinSet& set, std::int64_t first, std::int64_t n) {
    if (set.whole()) {
      if (set.held_count > 0) return true;
      first = 0, n = set.joints->count;
    }
    if (!decode(*set.joints, false, first, n, set.joint_values) ||
        !decode(*set.weights, false, first, n, set.weight_values))
      return false;
    set.held_first = first, set.held_count = n;
    return true;
  }

  // Spec 3.7.3.3: a vertex names each joint of its skin at most once among its non-zero weights,
  // a zero weight pairs with joint 0, weights are not negative, and all the vertex's weights, over
  // every set, sum to one within the component type's precision. The reference runs these checks
  // after every accessor's own, vertex by vertex across all skinned primitives (a primitive's
  // component checks, set by set, then each primitive's sum, reported at every WEIGHTS_n), and a
  // weight whose joint or value was reported is left out of the sum.
  void skinning() {
    std::vector<SkinnedPrimitive> primitives;
    for (const MeshModel& mesh : doc_.meshes) {
      if (!mesh.object || mesh.skin < 0) continue;
      for (const PrimitiveModel& primitive : mesh.primitives) {
        if (!primitive.object || !primitive.skinned) continue;        // what a skin binds (PrimitiveModel::skinned)
        std::map<int, std::pair<std::int64_t, std::int64_t>> by_set;  // set → (JOINTS, WEIGHTS)
        for (const auto& [name, index] : primitive.attributes) {
          const std::string& semantic = name;
          if (auto set = set_number(semantic, "JOINTS_")) by_set.try_emplace(*set, -1, -1).first->second.first = index;
          if (auto set = set_number(semantic, "WEIGHTS_"))
            by_set.try_emplace(*set, -1, -1).first->second.second = index;
        }
        SkinnedPrimitive skinned{{}, -1, mesh.skin, mesh.joint_count, 0.0};
        // Joints are unsigned integers (32-bit ones too, though the format allows 8 and 16: the
        // link pass reports that) and weights floats or normalized unsigned integers; other data
        // is not read as joints or weights.
        bool usable = !by_set.empty();
        for (const auto& [set, pair] : by_set) {
          const AccessorModel* joints = accessor_object(doc_, pair.first);
          const AccessorModel* weights = accessor_object(doc_, pair.second);
          usable =
              usable && joints && weights && readable(*joints) && readable(*weights) &&
              (joints->component_type == 5121 || joints->component_type == 5123 || joints->component_type == 5125) &&
              (weights->component_type == 5126 || weights->component_type == 5121 || weights->component_type == 5123) &&
              joints->count == weights->count && (skinned.count < 0 || joints->count == skinned.count);
          if (!usable) break;
          skinned.count = joints->count;
          const std::string attributes = primitive.pointer + "/attributes/";
          SkinSet pair_of_set{joints,
                              weights,
                              attributes + "JOINTS_" + std::to_string(set),
                              attributes + "WEIGHTS_" + std::to_string(set),
                              {},
                              {},
                              0,
                              0};
          skinned.sets.push_back(std::move(pair_of_set));
        }
        if (usable && skinned.count > 0) primitives.push_back(std::move(skinned));
      }
    }
    // Memory stays bounded however many primitives there are: a chunk holds at most
    // kSkinWindow set-elements over all chunked sets (sparse sets are held whole, as in accessor()).
    constexpr std::int64_t kSkinWindow = std::int64_t{1} << 20;
    std::int64_t chunked_sets = 0, vertices = 0;
    for (const SkinnedPrimitive& primitive : primitives) {
      vertices = std::max(vertices, primitive.count);
      for (const SkinSet& set : primitive.sets) chunked_sets += !set.whole();
    }
    const std::int64_t chunk =
        std::clamp<std::int64_t>(kSkinWindow / std::max<std::int64_t>(chunked_sets, 1), 1, kChunkElements);
    std::vector<double> used;
    for (std::int64_t first = 0; first < vertices && !primitives.empty(); first += chunk) {
      // Finished primitives leave; a primitive whose data cannot be read leaves too (its sums would be wrong).
      std::erase_if(primitives, [&](SkinnedPrimitive& primitive) {
        if (first >= primitive.count) return true;
        const std::int64_t n = std::min(chunk, primitive.count - first);
        for (SkinSet& set : primitive.sets)
          if (!hold(set, first, n)) return true;
        return false;
      });
      const std::int64_t end = std::min(vertices, first + chunk);
      for (std::int64_t vertex = first; vertex < end; ++vertex) {
        for (SkinnedPrimitive& primitive : primitives) {
          if (vertex >= primitive.count) continue;
          used.clear();
          primitive.sum = 0;
          // Component by component, each set in turn within one (the reference's order: with two
          // sets, the first component of JOINTS_1 comes before the second of JOINTS_0).
          for (int c = 0; c < 4; ++c) {
            for (const SkinSet& set : primitive.sets) {
              const std::size_t local = static_cast<std::size_t>(vertex - set.held_first) * 4;
              const std::uint64_t index = static_cast<std::uint64_t>(vertex) * 4 + static_cast<std::uint64_t>(c);
              const double joint = set.joint_values[local + c];
              const double raw_weight = set.weight_values[local + c];
              const double weight = normalized(*set.weights, raw_weight);
              bool left_out = false;
              // The skin's range first, whatever the weight; then a zero weight's joint; then repeats.
              if (primitive.joint_count >= 0 && joint >= static_cast<double>(primitive.joint_count)) {
                issues_.at("ACCESSOR_JOINTS_INDEX_OOB", set.joints_pointer,
                           {arg(index), arg(c), arg(static_cast<std::int64_t>(joint)), arg(primitive.joint_count - 1),
                            arg(primitive.skin)});
                left_out = true;
              } else if (weight == 0.0) {
                if (joint != 0)
                  issues_.at("ACCESSOR_JOINTS_USED_ZERO_WEIGHT", set.joints_pointer,
                             {arg(index), arg(c), arg(static_cast<std::int64_t>(joint))});
              } else if (std::find(used.begin(), used.end(), joint) != used.end()) {
                issues_.at("ACCESSOR_JOINTS_INDEX_DUPLICATE", set.joints_pointer,
                           {arg(index), arg(c), arg(static_cast<std::int64_t>(joint))});
                left_out = true;
              } else {
                used.push_back(joint);
              }
              if (weight < 0) {
                issues_.at("ACCESSOR_WEIGHTS_NEGATIVE", set.weights_pointer,
                           {arg(index), arg(c), value_arg(*set.weights, raw_weight)});
                left_out = true;
              }
              if (!left_out) primitive.sum += weight;
            }
          }
        }
        for (const SkinnedPrimitive& primitive : primitives) {
          if (vertex >= primitive.count) continue;
          // Float weights are exact to about 5e-4 after a writer's rounding; normalized integers
          // to one step of an unsigned byte (spec 3.7.3.3 "within the precision of the type").
          const bool float_weights = primitive.sets.size() == 1 && primitive.sets[0].weights->component_type == 5126;
          const double tolerance = float_weights ? 5e-4 : 1.0 / 255.0;
          if (std::fabs(primitive.sum - 1.0) <= tolerance) continue;
          const std::uint64_t index = static_cast<std::uint64_t>(vertex) * 4;
          for (const SkinSet& set : primitive.sets)
            issues_.at("ACCESSOR_WEIGHTS_NON_NORMALIZED", set.weights_pointer,
                       {arg(index), arg(index + 3), arg_double(primitive.sum)});
        }
      }
    }
  }

  void animation_input(std::span<const std::string> uses, std::size_t first, Carry& carry) {
    // Spec 3.11: times are non-negative and strictly increasing. A negative time is reported once
    // and not used as the predecessor of the next (the reference compares against the last valid
    // time, starting from 0).
    for (std::size_t k = 0; k < values_.size(); ++k) {
      const double value = values_[k];
      const std::uint64_t index = first + k;
      if (value < 0) {
        for (const std::string& use : uses)
          issues_.at("ACCESSOR_ANIMATION_INPUT_NEGATIVE", use, {arg(index), arg_double(value)});
        continue;
      }
      if (index > 0 && value <= carry.previous_time)
        for (const std::string& use : uses)
          issues_.at("ACCESSOR_ANIMATION_INPUT_NON_INCREASING", use,
                     {arg(index), arg_double(value), arg_double(carry.previous_time)});
      carry.previous_time = value;
    }
  }

  void quaternions(const AccessorModel& a, std::span<const std::string> uses, std::size_t first, std::size_t count) {
    const bool cubic = a.interpolation == "CUBICSPLINE";
    for (std::size_t e = 0; e < count; ++e) {
      const std::uint64_t element = first + e;
      if (cubic && element % 3 != 1) continue;  // in- and out-tangents need not be unit
      const double* q = &values_[e * 4];
      double sum = 0;
      for (int c = 0; c < 4; ++c) sum += normalized(a, q[c]) * normalized(a, q[c]);
      const double length = std::sqrt(sum);
      if (std::fabs(length - 1.0) > kUnitQuaternionTolerance)
        for (const std::string& use : uses)
          issues_.at("ACCESSOR_ANIMATION_SAMPLER_OUTPUT_NON_NORMALIZED_QUATERNION", use,
                     {arg(element * 4), arg(element * 4 + 3), arg_double(length)});
    }
  }

  void inverse_bind_matrices(const std::string& use, std::size_t first, std::size_t count) {
    // Spec 3.7.3.1: inverse bind matrices are affine; their last row is (0, 0, 0, 1).
    static constexpr int last_row[4] = {3, 7, 11, 15};
    for (std::size_t e = 0; e < count; ++e) {
      for (int r = 0; r < 4; ++r) {
        const std::size_t k = e * 16 + static_cast<std::size_t>(last_row[r]);
        const double expected = r == 3 ? 1.0 : 0.0;
        if (values_[k] != expected)
          issues_.at("ACCESSOR_INVALID_IBM", use,
                     {arg(static_cast<std::uint64_t>(first * 16 + k)), arg(last_row[r]), arg_double(values_[k])});
      }
    }
  }

  IssueSink& issues_;
  Document& doc_;
  Values values_;  // the chunk being checked
};

}  // namespace

std::optional<std::span<const std::uint8_t>> buffer_view_bytes(const Document& doc, std::int64_t index) {
  if (index < 0 || static_cast<std::size_t>(index) >= doc.buffer_views.size()) return std::nullopt;
  const BufferViewModel& view = doc.buffer_views[static_cast<std::size_t>(index)];
  if (view.object && view.meshopt_present)
    return view.decoded ? std::optional<std::span<const std::uint8_t>>(*view.decoded) : std::nullopt;
  if (!view.object || view.byte_offset < 0 || view.buffer < 0 ||
      static_cast<std::size_t>(view.buffer) >= doc.buffers.size())
    return std::nullopt;
  const BufferModel& buffer = doc.buffers[static_cast<std::size_t>(view.buffer)];
  if (!buffer.data_loaded || view.byte_length <= 0) return std::nullopt;
  const std::uint64_t end = static_cast<std::uint64_t>(view.byte_offset) + static_cast<std::uint64_t>(view.byte_length);
  if (end > buffer.data.size() || (buffer.byte_length > 0 && end > static_cast<std::uint64_t>(buffer.byte_length)))
    return std::nullopt;
  return buffer.data.subspan(static_cast<std::size_t>(view.byte_offset), static_cast<std::size_t>(view.byte_length));
}

const AccessorModel* accessor_object(const Document& doc, std::int64_t index) {
  if (index < 0 || static_cast<std::size_t>(index) >= doc.accessors.size()) return nullptr;
  const AccessorModel& accessor = doc.accessors[static_cast<std::size_t>(index)];
  return accessor.object ? &accessor : nullptr;
}

namespace {

void load_buffers(Context& context) {
  Document& doc = context.doc;
  for (std::size_t i = 0; i < doc.buffers.size(); ++i) {
    BufferModel& buffer = doc.buffers[i];
    if (!buffer.object) continue;
    const std::string p = "/buffers/" + std::to_string(i);
    nlohmann::ordered_json resource;
    resource["pointer"] = p;
    resource["mimeType"] = "application/gltf-buffer";
    if (!buffer.has_uri) {
      // Spec 4.4.3.2: in a GLB, the first buffer without a uri is the BIN chunk; the reference
      // finds one missing as it loads the buffers, after the unused objects.
      if (context.glb && i == 0 && !context.glb_bin_chunk) context.issues.at("BUFFER_MISSING_GLB_DATA", p);
      if (context.glb && i == 0 && context.glb_bin) {
        buffer.data = *context.glb_bin;
        buffer.data_loaded = true;
        resource["storage"] = "glb";
        // Spec 4.4.3.3: the BIN chunk is byteLength padded to 4 bytes; more is waste.
        const std::int64_t padded =
            buffer.byte_length > 0 ? (std::min<std::int64_t>(buffer.byte_length, INT64_MAX - 3) + 3) / 4 * 4 : 0;
        if (buffer.byte_length > 0 && static_cast<std::int64_t>(buffer.data.size()) > padded)
          context.issues.at("BUFFER_GLB_CHUNK_TOO_BIG", p,
                            {arg(static_cast<std::int64_t>(buffer.data.size()) - padded)});
      }
    } else if (buffer.uri_valid && buffer.data_uri) {
      resource["storage"] = "data-uri";
    } else if (buffer.non_relative) {
      resource["storage"] = "external";  // non-relative: named, never fetched
      resource["uri"] = buffer.uri;
    } else if (buffer.uri_valid && context.options.validate_resources) {
      resource["storage"] = "external";
      resource["uri"] = buffer.uri;
      if ((buffer.file = read_resource(context, buffer.uri, p + "/uri"))) {
        buffer.data = buffer.file->bytes();
        buffer.data_loaded = true;
      }
    }
    if (buffer.data_loaded && buffer.byte_length > 0) {
      if (static_cast<std::int64_t>(buffer.data.size()) < buffer.byte_length)
        context.issues.at("BUFFER_BYTE_LENGTH_MISMATCH", p,
                          {arg(static_cast<std::uint64_t>(buffer.data.size())), arg(buffer.byte_length)});
      resource["byteLength"] = buffer.data.size();
    }
    context.resources.push_back(std::move(resource));
  }
}

}  // namespace

void check_resources(Context& context) {
  load_buffers(context);
  decode_meshopt_views(context);
  check_images(context);
  AccessorData(context).run();
  check_texture_sources(context);
  check_draco(context);
}

}  // namespace gltf_pbr::structure
