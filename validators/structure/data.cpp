// Resources and data: buffer bytes (data URIs, external files, the GLB BIN chunk), then accessor
// values against what their users require (glTF 2.0 spec 3.6.2 "Accessors", 3.7.2.1 "Overview"
// of mesh attributes, 3.11 "Animations", 3.7.3 "Skins"). Every read is bounded by the bytes that
// are really there, whatever the JSON claims.
#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/files.hpp"
#include "validators/structure/images.hpp"
#include "validators/structure/structure_internal.hpp"

namespace gltf_pbr::structure {

namespace {

std::optional<std::vector<std::uint8_t>> read_resource(const Context& context, const std::string& uri) {
  const std::filesystem::path path = context.base_dir / percent_decode(uri);
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) return std::nullopt;
  return read_file(path);  // one sized read, not a byte-by-byte stream: external .bin files are large
}

// Reads component `c` of element `e` as a double; the caller has checked the bounds.
template <typename T>
inline double load(const std::uint8_t* base) {
  T value;
  std::memcpy(&value, base, sizeof(T));
  return static_cast<double>(value);
}

class AccessorData {
 public:
  explicit AccessorData(Context& context) : issues_(context.issues), doc_(context.doc) {}

  void run() {
    // One allocation for the largest accessor: its pages are touched once, not per accessor.
    std::uint64_t largest = 0;
    for (const AccessorModel& a : doc_.accessors)
      if (a.object && a.valid && a.fits && a.count > 0)
        largest = std::max(largest, static_cast<std::uint64_t>(a.count) * component_count(a.type));
    values_.reserve(static_cast<std::size_t>(std::min<std::uint64_t>(largest, 1ull << 31)));
    for (std::size_t i = 0; i < doc_.accessors.size(); ++i)
      if (doc_.accessors[i].object && doc_.accessors[i].valid) accessor(i);
  }

 private:
  // The bytes of a buffer view, when its buffer has loaded and the view fits it.
  std::optional<std::span<const std::uint8_t>> view_bytes(std::int64_t index) {
    if (index < 0 || static_cast<std::size_t>(index) >= doc_.buffer_views.size()) return std::nullopt;
    const BufferViewModel& view = doc_.buffer_views[static_cast<std::size_t>(index)];
    if (!view.object || view.buffer < 0 || static_cast<std::size_t>(view.buffer) >= doc_.buffers.size())
      return std::nullopt;
    const BufferModel& buffer = doc_.buffers[static_cast<std::size_t>(view.buffer)];
    if (!buffer.data_loaded || view.byte_length <= 0) return std::nullopt;
    const std::uint64_t end =
        static_cast<std::uint64_t>(view.byte_offset) + static_cast<std::uint64_t>(view.byte_length);
    if (end > buffer.data.size() || (buffer.byte_length > 0 && end > static_cast<std::uint64_t>(buffer.byte_length)))
      return std::nullopt;
    return buffer.data.subspan(static_cast<std::size_t>(view.byte_offset), static_cast<std::size_t>(view.byte_length));
  }

  // Decodes the accessor's values (sparse substitution applied) into `values_`, component-major
  // per element. Returns false when the data is unavailable. Sparse issues are reported only
  // when `report_sparse` (each accessor's own pass), not when it is read as a partner.
  bool decode(const AccessorModel& a, bool report_sparse = true) {
    report_sparse_ = report_sparse;
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
    const std::uint64_t total = static_cast<std::uint64_t>(a.count) * static_cast<std::uint64_t>(components);
    // Without a buffer view the JSON alone sets the count: refuse what no real file could hold.
    if (!bytes && total > (1u << 26)) return false;
    // Every value is written below (or is zero for sparse-only accessors); keep the capacity.
    if (bytes && !a.sparse)
      values_.resize(static_cast<std::size_t>(total));
    else
      values_.assign(static_cast<std::size_t>(total), 0.0);
    if (bytes) {
      const std::int64_t view_stride = doc_.buffer_views[static_cast<std::size_t>(a.buffer_view)].byte_stride;
      const bool matrix_padding = a.type.starts_with("MAT") && size < 4;
      const int rows = a.type == "MAT2" ? 2 : a.type == "MAT3" ? 3 : a.type == "MAT4" ? 4 : components;
      const int column_bytes = matrix_padding ? (rows * size + 3) / 4 * 4 : rows * size;
      const std::int64_t element_bytes = matrix_padding ? column_bytes * (components / rows) : size * components;
      const std::int64_t stride = view_stride > 0 ? view_stride : element_bytes;
      const std::uint8_t* base = bytes->data() + a.byte_offset;
      switch (a.component_type) {
        case 5120:
          fill<std::int8_t>(base, stride, a.count, components, rows, column_bytes);
          break;
        case 5121:
          fill<std::uint8_t>(base, stride, a.count, components, rows, column_bytes);
          break;
        case 5122:
          fill<std::int16_t>(base, stride, a.count, components, rows, column_bytes);
          break;
        case 5123:
          fill<std::uint16_t>(base, stride, a.count, components, rows, column_bytes);
          break;
        case 5125:
          fill<std::uint32_t>(base, stride, a.count, components, rows, column_bytes);
          break;
        case 5126:
          fill<float>(base, stride, a.count, components, rows, column_bytes);
          break;
        default:
          return false;
      }
    }
    if (a.sparse && !apply_sparse(a, components)) return false;
    return true;
  }

  template <typename T>
  void fill(const std::uint8_t* base, std::int64_t stride, std::int64_t count, int components, int rows,
            int column_bytes) {
    double* out = values_.data();
    const int columns = components / rows;
    for (std::int64_t e = 0; e < count; ++e) {
      const std::uint8_t* element = base + e * stride;
      for (int column = 0; column < columns; ++column)
        for (int row = 0; row < rows; ++row) *out++ = load<T>(element + column * column_bytes + row * sizeof(T));
    }
  }

  bool apply_sparse(const AccessorModel& a, int components) {
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
    IssueSink* issues = report_sparse_ ? &issues_ : nullptr;
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
        values_[static_cast<std::size_t>(index * components + c)] = number;
      }
    }
    return true;
  }

  // A value as the reference prints it: floats as doubles, integers as integers.
  static MessageArg value_arg(const AccessorModel& a, double value) {
    return a.component_type == 5126 ? arg_double(value) : arg(static_cast<std::int64_t>(value));
  }

  double normalized(const AccessorModel& a, double value) const {
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

  void accessor(std::size_t i) {
    AccessorModel& a = doc_.accessors[i];
    if (!decode(a)) return;
    const std::string p = "/accessors/" + std::to_string(i);
    const std::string& use = a.usage_pointer.empty() ? p : a.usage_pointer;
    const int components = component_count(a.type);
    const std::size_t count = static_cast<std::size_t>(a.count);
    const bool is_float = a.component_type == 5126;

    std::vector<double> actual_min(components, INFINITY), actual_max(components, -INFINITY);
    bool invalid_float = false;
    const double* value = values_.data();
    for (std::size_t e = 0; e < count; ++e) {
      for (int c = 0; c < components; ++c, ++value) {
        if (is_float && !std::isfinite(*value)) {
          issues_.at("ACCESSOR_INVALID_FLOAT", use,
                     {arg(static_cast<std::uint64_t>(e * components + c)), arg_double(*value)});
          invalid_float = true;
          continue;
        }
        actual_min[c] = std::min(actual_min[c], *value);
        actual_max[c] = std::max(actual_max[c], *value);
      }
    }
    if (!invalid_float) bounds(a, p, actual_min, actual_max);

    using Usage = AccessorModel::Usage;
    switch (a.usage) {
      case Usage::Index:
        index_checks(a, use);
        break;
      case Usage::Vertex:
        vertex_checks(a, use, count, components);
        break;
      case Usage::AnimationInput:
        animation_input(a, use);
        break;
      case Usage::AnimationOutput:
        if (a.animation_path == "rotation" && components == 4) quaternions(a, use, count);
        break;
      case Usage::InverseBindMatrices:
        if (components == 16) inverse_bind_matrices(use, count);
        break;
      default:
        break;
    }
  }

  void bounds(const AccessorModel& a, const std::string& p, const std::vector<double>& actual_min,
              const std::vector<double>& actual_max) {
    const int components = static_cast<int>(actual_min.size());
    const bool is_float = a.component_type == 5126;
    // Declared bounds of float accessors are compared at float precision: the JSON double is what
    // a writer printed for the float it stored.
    auto same = [&](double declared, double actual) {
      return is_float ? static_cast<float>(declared) == static_cast<float>(actual) : declared == actual;
    };
    if (a.has_min && static_cast<int>(a.min.size()) == components) {
      for (int c = 0; c < components; ++c) {
        const std::string pointer = p + "/min/" + std::to_string(c);
        if (!same(a.min[c], actual_min[c]))
          issues_.at("ACCESSOR_MIN_MISMATCH", pointer, {value_arg(a, a.min[c]), value_arg(a, actual_min[c])});
        std::uint64_t below = 0;
        const double declared = is_float ? static_cast<double>(static_cast<float>(a.min[c])) : a.min[c];
        if (actual_min[c] < declared)  // only then can an element lie below: scan for the count
          for (std::size_t k = static_cast<std::size_t>(c); k < values_.size(); k += components)
            if (values_[k] < declared) ++below;
        if (below) issues_.at("ACCESSOR_ELEMENT_OUT_OF_MIN_BOUND", pointer, {arg(below), value_arg(a, a.min[c])});
      }
    }
    if (a.has_max && static_cast<int>(a.max.size()) == components) {
      for (int c = 0; c < components; ++c) {
        const std::string pointer = p + "/max/" + std::to_string(c);
        if (!same(a.max[c], actual_max[c]))
          issues_.at("ACCESSOR_MAX_MISMATCH", pointer, {value_arg(a, a.max[c]), value_arg(a, actual_max[c])});
        std::uint64_t above = 0;
        const double declared = is_float ? static_cast<double>(static_cast<float>(a.max[c])) : a.max[c];
        if (actual_max[c] > declared)
          for (std::size_t k = static_cast<std::size_t>(c); k < values_.size(); k += components)
            if (values_[k] > declared) ++above;
        if (above) issues_.at("ACCESSOR_ELEMENT_OUT_OF_MAX_BOUND", pointer, {arg(above), value_arg(a, a.max[c])});
      }
    }
  }

  void index_checks(const AccessorModel& a, const std::string& use) {
    if (component_count(a.type) != 1) return;
    const double restart = a.component_type == 5121 ? 255.0 : a.component_type == 5123 ? 65535.0 : 4294967295.0;
    for (std::size_t k = 0; k < values_.size(); ++k) {
      const double value = values_[k];
      if (value == restart) {
        issues_.at("ACCESSOR_INDEX_PRIMITIVE_RESTART", use,
                   {arg(static_cast<std::int64_t>(value)), arg(static_cast<std::uint64_t>(k))});
      } else if (a.vertex_limit > 0 && value >= static_cast<double>(a.vertex_limit)) {
        issues_.at(
            "ACCESSOR_INDEX_OOB", use,
            {arg(static_cast<std::uint64_t>(k)), arg(static_cast<std::int64_t>(value)), arg(a.vertex_limit - 1)});
      }
    }
    if (a.primitive_mode == 4 && values_.size() >= 3) {
      std::uint64_t degenerate = 0;
      const std::size_t triangles = values_.size() / 3;
      for (std::size_t t = 0; t < triangles; ++t) {
        const double i0 = values_[3 * t], i1 = values_[3 * t + 1], i2 = values_[3 * t + 2];
        if (i0 == i1 || i1 == i2 || i0 == i2) ++degenerate;
      }
      if (degenerate)
        issues_.at("ACCESSOR_INDEX_TRIANGLE_DEGENERATE", use,
                   {arg(degenerate), arg(static_cast<std::uint64_t>(triangles))});
    }
  }

  void vertex_checks(const AccessorModel& a, const std::string& use, std::size_t count, int components) {
    const std::string& semantic = a.semantic;
    if ((semantic == "NORMAL" && components == 3) || (semantic == "TANGENT" && components == 4)) {
      for (std::size_t e = 0; e < count; ++e) {
        const double* v = &values_[e * components];
        const double x = normalized(a, v[0]), y = normalized(a, v[1]), z = normalized(a, v[2]);
        const double length = std::sqrt(x * x + y * y + z * z);
        const std::uint64_t first = e * components;
        if (std::fabs(length - 1.0) > 0.0005)
          issues_.at("ACCESSOR_VECTOR3_NON_UNIT", use, {arg(first), arg(first + 2), arg_double(length)});
        if (components == 4) {
          const double w = normalized(a, v[3]);
          if (w != 1.0 && w != -1.0)
            issues_.at("ACCESSOR_INVALID_SIGN", use, {arg(first), arg(first + 3), arg_double(w)});
        }
      }
    } else if (semantic.starts_with("COLOR_") && a.component_type == 5126) {
      for (std::size_t k = 0; k < values_.size(); ++k)
        if (values_[k] < 0.0 || values_[k] > 1.0)
          issues_.at("ACCESSOR_NON_CLAMPED", use, {arg(static_cast<std::uint64_t>(k)), arg_double(values_[k])});
    } else if (semantic.starts_with("JOINTS_") && components == 4) {
      joints_checks(a, use, count);
    } else if (semantic.starts_with("WEIGHTS_") && components == 4) {
      weights_checks(a, use, count);
    }
  }

  // Spec 3.7.3.3: weights are non-negative and, over all the primitive's sets, sum to one within
  // the precision of their component type.
  void weights_checks(const AccessorModel& a, const std::string& use, std::size_t count) {
    std::optional<std::vector<double>> earlier_sums = a.weights_sum_here ? sum_earlier_weight_sets(a) : std::nullopt;
    const bool all_float = a.component_type == 5126 && a.earlier_weight_sets.empty();
    const double tolerance = all_float ? 5e-4 : 1.0 / 255.0;
    for (std::size_t e = 0; e < count; ++e) {
      double sum = earlier_sums ? (*earlier_sums)[e] : 0.0;
      for (int c = 0; c < 4; ++c) {
        const double w = normalized(a, values_[e * 4 + c]);
        if (w < 0)
          issues_.at("ACCESSOR_WEIGHTS_NEGATIVE", use,
                     {arg(static_cast<std::uint64_t>(e * 4 + c)), arg(c), value_arg(a, values_[e * 4 + c])});
        sum += w;
      }
      if (earlier_sums && std::fabs(sum - 1.0) > tolerance)
        issues_.at(
            "ACCESSOR_WEIGHTS_NON_NORMALIZED", use,
            {arg(static_cast<std::uint64_t>(e * 4)), arg(static_cast<std::uint64_t>(e * 4 + 3)), arg_double(sum)});
    }
  }

  // Per vertex, the sum of the weights in the primitive's earlier WEIGHTS_n sets (zeros when there
  // are none); nullopt when one of them cannot be read or does not match, so the sum is unknown.
  // `values_` is left holding `a`'s values.
  std::optional<std::vector<double>> sum_earlier_weight_sets(const AccessorModel& a) {
    std::vector<double> sums(static_cast<std::size_t>(a.count), 0.0);
    if (a.earlier_weight_sets.empty()) return sums;
    const std::vector<double> own = values_;
    bool known = true;
    for (std::int64_t index : a.earlier_weight_sets) {
      const AccessorModel* earlier =
          index >= 0 && static_cast<std::size_t>(index) < doc_.accessors.size() ? &doc_.accessors[index] : nullptr;
      known = earlier && earlier->object && earlier->count == a.count && component_count(earlier->type) == 4 &&
              decode(*earlier, false);
      if (!known) break;
      for (std::size_t k = 0; k < values_.size(); ++k) sums[k / 4] += normalized(*earlier, values_[k]);
    }
    values_ = own;
    return known ? std::optional(std::move(sums)) : std::nullopt;
  }

  // Spec 3.7.3.3: a vertex names each joint at most once among its non-zero weights, every joint
  // index is inside its skin's joints, and a zero weight should pair with joint 0.
  void joints_checks(const AccessorModel& a, const std::string& use, std::size_t count) {
    std::vector<double> joints = values_;
    std::vector<double> weights;
    if (a.paired_weights >= 0 && static_cast<std::size_t>(a.paired_weights) < doc_.accessors.size()) {
      const AccessorModel& partner = doc_.accessors[static_cast<std::size_t>(a.paired_weights)];
      if (partner.object && partner.count == a.count && component_count(partner.type) == 4 && decode(partner, false))
        weights = values_;
    }
    values_ = std::move(joints);
    std::vector<double> seen;
    for (std::size_t e = 0; e < count; ++e) {
      seen.clear();
      for (int c = 0; c < 4; ++c) {
        const std::size_t k = e * 4 + static_cast<std::size_t>(c);
        const double joint = values_[k];
        const bool zero_weight = !weights.empty() && weights[k] == 0.0;
        if (zero_weight) {
          if (joint != 0)
            issues_.at("ACCESSOR_JOINTS_USED_ZERO_WEIGHT", use,
                       {arg(static_cast<std::uint64_t>(k)), arg(c), arg(static_cast<std::int64_t>(joint))});
          continue;
        }
        if (a.joint_count >= 0 && joint >= static_cast<double>(a.joint_count))
          issues_.at("ACCESSOR_JOINTS_INDEX_OOB", use,
                     {arg(static_cast<std::uint64_t>(k)), arg(c), arg(static_cast<std::int64_t>(joint)),
                      arg(a.joint_count - 1), arg(a.skin)});
        if (!weights.empty() && std::find(seen.begin(), seen.end(), joint) != seen.end())
          issues_.at("ACCESSOR_JOINTS_INDEX_DUPLICATE", use,
                     {arg(static_cast<std::uint64_t>(k)), arg(c), arg(static_cast<std::int64_t>(joint))});
        seen.push_back(joint);
      }
    }
  }

  void animation_input(const AccessorModel& a, const std::string& use) {
    if (component_count(a.type) != 1 || a.component_type != 5126) return;
    // Spec 3.11: times are non-negative and strictly increasing. A negative time is reported once
    // and not used as the predecessor of the next (the reference compares against the last valid
    // time, starting from 0).
    double previous = 0.0;
    for (std::size_t k = 0; k < values_.size(); ++k) {
      const double value = values_[k];
      if (value < 0) {
        issues_.at("ACCESSOR_ANIMATION_INPUT_NEGATIVE", use, {arg(static_cast<std::uint64_t>(k)), arg_double(value)});
        continue;
      }
      if (k > 0 && value <= previous)
        issues_.at("ACCESSOR_ANIMATION_INPUT_NON_INCREASING", use,
                   {arg(static_cast<std::uint64_t>(k)), arg_double(value), arg_double(previous)});
      previous = value;
    }
  }

  void quaternions(const AccessorModel& a, const std::string& use, std::size_t count) {
    const bool cubic = a.interpolation == "CUBICSPLINE";
    for (std::size_t e = 0; e < count; ++e) {
      if (cubic && e % 3 != 1) continue;  // in- and out-tangents need not be unit
      const double* q = &values_[e * 4];
      double sum = 0;
      for (int c = 0; c < 4; ++c) sum += normalized(a, q[c]) * normalized(a, q[c]);
      const double length = std::sqrt(sum);
      if (std::fabs(length - 1.0) > 0.0005)
        issues_.at(
            "ACCESSOR_ANIMATION_SAMPLER_OUTPUT_NON_NORMALIZED_QUATERNION", use,
            {arg(static_cast<std::uint64_t>(e * 4)), arg(static_cast<std::uint64_t>(e * 4 + 3)), arg_double(length)});
    }
  }

  void inverse_bind_matrices(const std::string& use, std::size_t count) {
    // Spec 3.7.3.1: inverse bind matrices are affine; their last row is (0, 0, 0, 1).
    static constexpr int last_row[4] = {3, 7, 11, 15};
    for (std::size_t e = 0; e < count; ++e) {
      for (int r = 0; r < 4; ++r) {
        const std::size_t k = e * 16 + static_cast<std::size_t>(last_row[r]);
        const double expected = r == 3 ? 1.0 : 0.0;
        if (values_[k] != expected)
          issues_.at("ACCESSOR_INVALID_IBM", use,
                     {arg(static_cast<std::uint64_t>(k)), arg(last_row[r]), arg_double(values_[k])});
      }
    }
  }

  IssueSink& issues_;
  Document& doc_;
  std::vector<double> values_;
  bool report_sparse_ = true;
};

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
      if (context.glb && i == 0 && context.glb_bin) {
        buffer.data = *context.glb_bin;
        buffer.data_loaded = true;
        resource["storage"] = "glb";
        // Spec 4.4.3.3: the BIN chunk is byteLength padded to 4 bytes; more is waste.
        const std::int64_t padded = (buffer.byte_length + 3) / 4 * 4;
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
      if (auto data = read_resource(context, buffer.uri)) {
        buffer.owned = std::move(*data);
        buffer.data = buffer.owned;
        buffer.data_loaded = true;
      } else {
        context.issues.at("IO_ERROR", p + "/uri", {arg_raw("Resource not found (" + buffer.uri + ").")});
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
  check_images(context);
  AccessorData(context).run();
  check_draco(context);
}

}  // namespace gltf_pbr::structure
