#include "core/draco.hpp"

#include <draco/compression/decode.h>

#include "core/error.hpp"

namespace gltf_pbr {

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

  draco::DecoderBuffer buffer;
  buffer.Init(
      reinterpret_cast<const char*>(model.buffers[static_cast<size_t>(view.buffer)].data.data() + view.byteOffset),
      view.byteLength);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&buffer);
  if (!decoded.ok()) return fail("Draco data does not decode: " + decoded.status().error_msg_string());
  const std::unique_ptr<draco::Mesh> draco_mesh = std::move(decoded).value();
  ++work_counters().meshes_decoded;

  DecodedPrimitive out;
  out.indices.reserve(draco_mesh->num_faces() * 3);
  for (draco::FaceIndex f(0); f < draco_mesh->num_faces(); ++f)
    for (int k = 0; k < 3; ++k) out.indices.push_back(draco_mesh->face(f)[k].value());
  const tinygltf::Value& attributes = extension->second.Get("attributes");
  for (const std::string& semantic : attributes.Keys()) {
    const auto* attribute =
        draco_mesh->GetAttributeByUniqueId(static_cast<uint32_t>(attributes.Get(semantic).GetNumberAsInt()));
    if (!attribute) return fail("attribute " + semantic + " names a Draco attribute id that does not exist");
    const int components = attribute->num_components();
    std::vector<float>& values = out.attributes[semantic];
    values.resize(draco_mesh->num_points() * static_cast<size_t>(components));
    for (draco::PointIndex p(0); p < draco_mesh->num_points(); ++p)
      if (!attribute->ConvertValue<float>(attribute->mapped_index(p), static_cast<int8_t>(components),
                                          values.data() + p.value() * static_cast<size_t>(components)))
        return fail("attribute " + semantic + " cannot be read as float");
    out.components[semantic] = components;
  }
  return out;
}

}  // namespace gltf_pbr
