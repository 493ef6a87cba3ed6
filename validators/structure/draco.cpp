// KHR_draco_mesh_compression: the reference validator cannot look inside Draco data, we can. Each
// compressed primitive is decoded with libdraco (only when StructureOptions::decode_draco), a
// failure is DRACO_DECODE_FAILED (our code, rules/structure.json), and the decoded attributes get
// the data checks plain accessors get, loosened by the quantization step: declared bounds, unit
// normals, clamped colours, and degenerate triangles.
#include <draco/compression/decode.h>

#include <cmath>

#include "core/draco.hpp"

#include "validators/structure/images.hpp"

namespace gltf_pbr::structure {

namespace {

void check_decoded_attribute(Context& context, const AccessorModel& accessor, std::size_t accessor_index,
                             const std::string& semantic, const std::string& pointer, const std::vector<float>& values,
                             int components) {
  IssueSink& issues = context.issues;
  if (components <= 0) return;
  const std::size_t count = values.size() / static_cast<std::size_t>(components);
  std::vector<double> low(components, INFINITY), high(components, -INFINITY);
  for (std::size_t k = 0; k < values.size(); ++k) {
    const int c = static_cast<int>(k % components);
    low[c] = std::min<double>(low[c], values[k]);
    high[c] = std::max<double>(high[c], values[k]);
  }
  // Draco quantizes attributes, so decoded extremes differ from the declared (pre-compression)
  // ones by up to a quantization step: exact MIN/MAX_MISMATCH would flag every compressed asset.
  // Only values beyond the declared bounds by more than an 8-bit step of the range are reported.
  const std::string accessor_pointer = "/accessors/" + std::to_string(accessor_index);
  if (accessor.has_min && accessor.has_max && static_cast<int>(accessor.min.size()) == components &&
      static_cast<int>(accessor.max.size()) == components) {
    for (int c = 0; c < components; ++c) {
      const double tolerance = (accessor.max[c] - accessor.min[c]) / 256.0 + 1e-6;
      if (low[c] >= accessor.min[c] - tolerance) continue;
      std::uint64_t below = 0;
      for (std::size_t k = static_cast<std::size_t>(c); k < values.size(); k += static_cast<std::size_t>(components))
        if (values[k] < accessor.min[c] - tolerance) ++below;
      issues.at("ACCESSOR_ELEMENT_OUT_OF_MIN_BOUND", accessor_pointer + "/min/" + std::to_string(c),
                {arg(below), arg_double(accessor.min[c])});
    }
    for (int c = 0; c < components; ++c) {
      const double tolerance = (accessor.max[c] - accessor.min[c]) / 256.0 + 1e-6;
      if (high[c] <= accessor.max[c] + tolerance) continue;
      std::uint64_t above = 0;
      for (std::size_t k = static_cast<std::size_t>(c); k < values.size(); k += static_cast<std::size_t>(components))
        if (values[k] > accessor.max[c] + tolerance) ++above;
      issues.at("ACCESSOR_ELEMENT_OUT_OF_MAX_BOUND", accessor_pointer + "/max/" + std::to_string(c),
                {arg(above), arg_double(accessor.max[c])});
    }
  }
  if (semantic == "NORMAL" && components == 3) {
    for (std::size_t e = 0; e < count; ++e) {
      const float* v = &values[e * 3];
      const double length = std::sqrt(double(v[0]) * v[0] + double(v[1]) * v[1] + double(v[2]) * v[2]);
      // Octahedral normal quantization keeps unit length only to a few bits: a looser bound.
      if (std::fabs(length - 1.0) > 0.01)
        issues.at(
            "ACCESSOR_VECTOR3_NON_UNIT", pointer,
            {arg(static_cast<std::uint64_t>(e * 3)), arg(static_cast<std::uint64_t>(e * 3 + 2)), arg_double(length)});
    }
  } else if (semantic.starts_with("COLOR_")) {
    for (std::size_t k = 0; k < values.size(); ++k)
      if (values[k] < 0.0f || values[k] > 1.0f)
        issues.at("ACCESSOR_NON_CLAMPED", pointer, {arg(static_cast<std::uint64_t>(k)), arg_double(values[k])});
  }
}

void check_primitive(Context& context, const PrimitiveModel& primitive) {
  Document& doc = context.doc;
  const std::string p = primitive.pointer + "/extensions/KHR_draco_mesh_compression";
  auto bytes = buffer_view_bytes(doc, primitive.draco_buffer_view);
  if (!bytes) return;  // unresolved or unloaded: reported elsewhere
  const FileResources::DracoMesh decoded = context.files.draco_mesh(*bytes);
  if (!decoded.mesh) {
    context.issues.at("DRACO_DECODE_FAILED", p, {arg_raw(decoded.problem)});
    return;
  }
  const draco::Mesh* mesh = decoded.mesh.get();
  for (const auto& [semantic, id] : primitive.draco_attributes) {
    if (id < 0 || id > UINT32_MAX || !mesh->GetAttributeByUniqueId(static_cast<std::uint32_t>(id))) {
      context.issues.at("DRACO_DECODE_FAILED", p + "/attributes/" + escape_pointer_token(semantic),
                        {arg_raw("no Draco attribute with unique id " + std::to_string(id))});
      continue;
    }
    int components = 0;
    const std::optional<std::vector<float>> read = draco_attribute_values(*mesh, id, components);
    if (!read) continue;
    const std::vector<float>& values = *read;
    for (const auto& [name, index] : primitive.attributes) {
      if (name != semantic || index < 0 || static_cast<std::size_t>(index) >= doc.accessors.size()) continue;
      const AccessorModel& accessor = doc.accessors[static_cast<std::size_t>(index)];
      if (accessor.object)
        check_decoded_attribute(context, accessor, static_cast<std::size_t>(index), semantic,
                                primitive.pointer + "/attributes/" + escape_pointer_token(semantic), values,
                                components);
    }
  }
  if (primitive.indices >= 0) {
    std::uint64_t degenerate = 0;
    for (draco::FaceIndex f(0); f < mesh->num_faces(); ++f) {
      const auto& face = mesh->face(f);
      if (face[0] == face[1] || face[1] == face[2] || face[0] == face[2]) ++degenerate;
    }
    if (degenerate)
      context.issues.at("ACCESSOR_INDEX_TRIANGLE_DEGENERATE", primitive.pointer + "/indices",
                        {arg(degenerate), arg(static_cast<std::uint64_t>(mesh->num_faces()))});
  }
}

}  // namespace

void check_draco(Context& context) {
  if (!context.options.decode_draco) return;
  for (const MeshModel& mesh : context.doc.meshes)
    for (const PrimitiveModel& primitive : mesh.primitives)
      if (primitive.object && primitive.draco) check_primitive(context, primitive);
}

}  // namespace gltf_pbr::structure
