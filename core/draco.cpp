#include "core/draco.hpp"

#include <draco/compression/decode.h>

#include "core/error.hpp"

namespace gltf_pbr {

FileResources::DracoMesh decode_draco_mesh(std::span<const std::uint8_t> compressed) {
  draco::DecoderBuffer buffer;
  buffer.Init(reinterpret_cast<const char*>(compressed.data()), compressed.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) return {nullptr, decoded.status().error_msg_string()};
  ++work_counters().meshes_decoded;
  return {std::shared_ptr<const draco::Mesh>(std::move(decoded).value()), {}};
}

std::optional<std::vector<float>> draco_attribute_values(const draco::Mesh& mesh, std::int64_t unique_id,
                                                         int& components) {
  if (unique_id < 0 || unique_id > UINT32_MAX) return std::nullopt;
  const draco::PointAttribute* attribute = mesh.GetAttributeByUniqueId(static_cast<std::uint32_t>(unique_id));
  if (!attribute) return std::nullopt;
  components = attribute->num_components();
  std::vector<float> values(mesh.num_points() * static_cast<std::size_t>(components));
  for (draco::PointIndex p(0); p < mesh.num_points(); ++p)
    if (!attribute->ConvertValue<float>(attribute->mapped_index(p), static_cast<int8_t>(components),
                                        values.data() + p.value() * static_cast<std::size_t>(components)))
      return std::nullopt;
  return values;
}

DecodedPrimitive decode_draco_primitive(const Asset& asset, int mesh_index, int primitive_index) {
  const tinygltf::Model& model = asset.model;
  const std::string where =
      pointer("meshes", mesh_index) + pointer("primitives", primitive_index) + "/extensions/KHR_draco_mesh_compression";
  auto fail = [&](const std::string& why) -> DecodedPrimitive { throw InputError(asset.path.string(), where, why); };
  const auto& primitive =
      model.meshes.at(static_cast<size_t>(mesh_index)).primitives.at(static_cast<size_t>(primitive_index));
  const auto extension = primitive.extensions.find("KHR_draco_mesh_compression");
  if (extension == primitive.extensions.end()) return fail("primitive is not Draco-compressed");
  const tinygltf::Value& view_value = extension->second.Get("bufferView");
  if (!view_value.IsInt()) return fail("bufferView is missing");
  const int view_index = view_value.GetNumberAsInt();
  if (view_index < 0 || static_cast<size_t>(view_index) >= model.bufferViews.size())
    return fail("bufferView is out of range");
  const auto& view = model.bufferViews[static_cast<size_t>(view_index)];
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size() ||
      view.byteOffset + view.byteLength > model.buffers[static_cast<size_t>(view.buffer)].data.size())
    return fail("bufferView lies outside its buffer");

  const std::span<const std::uint8_t> compressed(
      model.buffers[static_cast<size_t>(view.buffer)].data.data() + view.byteOffset, view.byteLength);
  const FileResources::DracoMesh decoded =
      asset.resources ? asset.resources->draco_mesh(compressed) : decode_draco_mesh(compressed);
  if (!decoded.mesh) return fail("Draco data does not decode: " + decoded.problem);
  const draco::Mesh* draco_mesh = decoded.mesh.get();

  DecodedPrimitive out;
  out.indices.reserve(draco_mesh->num_faces() * 3);
  for (draco::FaceIndex f(0); f < draco_mesh->num_faces(); ++f)
    for (int k = 0; k < 3; ++k) out.indices.push_back(draco_mesh->face(f)[k].value());
  const tinygltf::Value& attributes = extension->second.Get("attributes");
  for (const std::string& semantic : attributes.Keys()) {
    const int id = attributes.Get(semantic).GetNumberAsInt();
    if (id < 0 || !draco_mesh->GetAttributeByUniqueId(static_cast<uint32_t>(id)))
      return fail("attribute " + semantic + " names a Draco attribute id that does not exist");
    int components = 0;
    std::optional<std::vector<float>> values = draco_attribute_values(*draco_mesh, id, components);
    if (!values) return fail("attribute " + semantic + " cannot be read as float");
    out.attributes[semantic] = std::move(*values);
    out.components[semantic] = components;
  }
  return out;
}

}  // namespace gltf_pbr
