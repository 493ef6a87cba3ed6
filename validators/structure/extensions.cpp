#include "validators/structure/extensions.hpp"

#include <cmath>
#include <regex>
#include <set>

namespace gltf_pbr::structure {

namespace {

struct ExtensionPlace {
  const char* name;
  std::vector<Owner> owners;  // empty: the extension has no JSON object anywhere
};

const std::vector<ExtensionPlace>& known_extensions() {
  static const std::vector<ExtensionPlace> places = {
      {"KHR_animation_pointer", {Owner::ChannelTarget}},
      {"KHR_draco_mesh_compression", {Owner::Primitive}},
      {"KHR_lights_punctual", {Owner::Root, Owner::Node}},
      {"KHR_materials_anisotropy", {Owner::Material}},
      {"KHR_materials_clearcoat", {Owner::Material}},
      {"KHR_materials_dispersion", {Owner::Material}},
      {"KHR_materials_emissive_strength", {Owner::Material}},
      {"KHR_materials_ior", {Owner::Material}},
      {"KHR_materials_iridescence", {Owner::Material}},
      {"KHR_materials_pbrSpecularGlossiness", {Owner::Material}},
      {"KHR_materials_sheen", {Owner::Material}},
      {"KHR_materials_specular", {Owner::Material}},
      {"KHR_materials_transmission", {Owner::Material}},
      {"KHR_materials_unlit", {Owner::Material}},
      {"KHR_materials_variants", {Owner::Root, Owner::Primitive}},
      {"KHR_materials_volume", {Owner::Material}},
      {"KHR_mesh_quantization", {}},
      {"KHR_node_visibility", {Owner::Node}},
      {"KHR_texture_basisu", {Owner::Texture}},
      {"KHR_texture_transform", {Owner::TextureInfo}},
      {"EXT_texture_webp", {Owner::Texture}},
      {"EXT_meshopt_compression", {Owner::Buffer, Owner::BufferView}},
  };
  return places;
}

const ExtensionPlace* find_place(const std::string& name) {
  for (const auto& place : known_extensions())
    if (name == place.name) return &place;
  return nullptr;
}

constexpr Range kUnit{0, 1};
constexpr Range kNonNegative{0};

class ExtensionReader {
 public:
  ExtensionReader(SchemaReader& read, const ExtensionHooks& hooks)
      : read_(read), issues_(read.issues()), hooks_(hooks) {}

  void read(const std::string& name, const Json& owner_object, const Json& o, const std::string& p) {
    if (name == "KHR_materials_anisotropy") {
      read_.check_members(o, p,
                          {"anisotropyStrength", "anisotropyRotation", "anisotropyTexture", "extensions", "extras"});
      read_.number(o, p, "anisotropyStrength", false, kUnit);
      read_.number(o, p, "anisotropyRotation");
      texture(o, p, "anisotropyTexture");
      tail(o, p);
      same_tex_coord(owner_object, o, p, "anisotropyTexture", "KHR_MATERIALS_ANISOTROPY_ANISOTROPY_TEXTURE_TEXCOORD");
    } else if (name == "KHR_materials_clearcoat") {
      read_.check_members(o, p,
                          {"clearcoatFactor", "clearcoatTexture", "clearcoatRoughnessFactor",
                           "clearcoatRoughnessTexture", "clearcoatNormalTexture", "extensions", "extras"});
      read_.number(o, p, "clearcoatFactor", false, kUnit);
      texture(o, p, "clearcoatTexture");
      read_.number(o, p, "clearcoatRoughnessFactor", false, kUnit);
      texture(o, p, "clearcoatRoughnessTexture");
      texture(o, p, "clearcoatNormalTexture", 1);
      tail(o, p);
      same_tex_coord(owner_object, o, p, "clearcoatNormalTexture",
                     "KHR_MATERIALS_CLEARCOAT_CLEARCOAT_NORMAL_TEXTURE_TEXCOORD");
    } else if (name == "KHR_materials_dispersion") {
      read_.check_members(o, p, {"dispersion", "extensions", "extras"});
      read_.number(o, p, "dispersion", false, kNonNegative);
      tail(o, p);
      // KHR_materials_dispersion: "requires KHR_materials_volume".
      if (!has_sibling(owner_object, "KHR_materials_volume")) at_link("KHR_MATERIALS_DISPERSION_NO_VOLUME", p);
    } else if (name == "KHR_materials_emissive_strength") {
      read_.check_members(o, p, {"emissiveStrength", "extensions", "extras"});
      // A strength of 1, the default, changes nothing, so it is no strength wasted on a black factor.
      const auto strength = read_.number(o, p, "emissiveStrength", false, kNonNegative);
      tail(o, p);
      bool zero = strength && *strength != 1.0;
      auto factor = owner_object.find("emissiveFactor");
      if (factor != owner_object.end() && factor->is_array())
        for (const auto& value : *factor)
          if (!value.is_number() || value.get<double>() != 0) zero = false;
      if (zero) at_link("KHR_MATERIALS_EMISSIVE_STRENGTH_ZERO_FACTOR", p);
    } else if (name == "KHR_materials_ior") {
      read_.check_members(o, p, {"ior", "extensions", "extras"});
      // KHR_materials_ior: ior is 0 (a special value) or at least 1.
      auto ior = o.find("ior");
      if (ior != o.end() && ior->is_number() && ior->get<double>() != 0 && !(ior->get<double>() >= 1))
        issues_.at("VALUE_NOT_IN_RANGE", p + "/ior",
                   {ior->is_number_float() ? arg_double(ior->get<double>()) : arg_raw(ior->dump())});
      else
        read_.number(o, p, "ior");
      tail(o, p);
    } else if (name == "KHR_materials_iridescence") {
      read_.check_members(o, p,
                          {"iridescenceFactor", "iridescenceTexture", "iridescenceIor", "iridescenceThicknessMinimum",
                           "iridescenceThicknessMaximum", "iridescenceThicknessTexture", "extensions", "extras"});
      read_.number(o, p, "iridescenceFactor", false, kUnit);
      texture(o, p, "iridescenceTexture");
      read_.number(o, p, "iridescenceIor", false, {1});
      auto minimum = read_.number(o, p, "iridescenceThicknessMinimum", false, kNonNegative);
      auto maximum = read_.number(o, p, "iridescenceThicknessMaximum", false, kNonNegative);
      texture(o, p, "iridescenceThicknessTexture");
      // A bound that cannot be read takes part in no rule (the reference's reading); an absent one
      // is its default.
      const bool range_known = (minimum || !o.contains("iridescenceThicknessMinimum")) &&
                               (maximum || !o.contains("iridescenceThicknessMaximum"));
      const double min_value = minimum.value_or(100.0), max_value = maximum.value_or(400.0);
      if (o.contains("iridescenceThicknessTexture")) {
        if (range_known && min_value == max_value)
          issues_.at("KHR_MATERIALS_IRIDESCENCE_THICKNESS_TEXTURE_UNUSED", p + "/iridescenceThicknessTexture");
      } else if (minimum) {
        issues_.at("KHR_MATERIALS_IRIDESCENCE_THICKNESS_RANGE_WITHOUT_TEXTURE", p + "/iridescenceThicknessMinimum");
      }
      tail(o, p);  // the reference reads extensions and extras after the rules between properties
    } else if (name == "KHR_materials_pbrSpecularGlossiness") {
      read_.check_members(o, p,
                          {"diffuseFactor", "diffuseTexture", "specularFactor", "glossinessFactor",
                           "specularGlossinessTexture", "extensions", "extras"});
      read_.numbers(o, p, "diffuseFactor", {4}, kUnit);
      texture(o, p, "diffuseTexture");
      read_.numbers(o, p, "specularFactor", {3}, kUnit);
      read_.number(o, p, "glossinessFactor", false, kUnit);
      texture(o, p, "specularGlossinessTexture");
      tail(o, p);
    } else if (name == "KHR_materials_sheen") {
      read_.check_members(o, p,
                          {"sheenColorFactor", "sheenColorTexture", "sheenRoughnessFactor", "sheenRoughnessTexture",
                           "extensions", "extras"});
      read_.numbers(o, p, "sheenColorFactor", {3}, kUnit);
      texture(o, p, "sheenColorTexture");
      read_.number(o, p, "sheenRoughnessFactor", false, kUnit);
      texture(o, p, "sheenRoughnessTexture");
      tail(o, p);
    } else if (name == "KHR_materials_specular") {
      read_.check_members(
          o, p,
          {"specularFactor", "specularTexture", "specularColorFactor", "specularColorTexture", "extensions", "extras"});
      read_.number(o, p, "specularFactor", false, kUnit);
      texture(o, p, "specularTexture");
      read_.numbers(o, p, "specularColorFactor", {3}, kNonNegative);
      texture(o, p, "specularColorTexture");
      tail(o, p);
    } else if (name == "KHR_materials_transmission") {
      read_.check_members(o, p, {"transmissionFactor", "transmissionTexture", "extensions", "extras"});
      read_.number(o, p, "transmissionFactor", false, kUnit);
      texture(o, p, "transmissionTexture");
      tail(o, p);
    } else if (name == "KHR_materials_unlit") {
      read_.check_members(o, p, {"extensions", "extras"});
      tail(o, p);
    } else if (name == "KHR_materials_volume") {
      read_.check_members(
          o, p,
          {"thicknessFactor", "thicknessTexture", "attenuationDistance", "attenuationColor", "extensions", "extras"});
      // The reference's order: the attenuation first.
      read_.numbers(o, p, "attenuationColor", {3}, kUnit);
      read_.number(o, p, "attenuationDistance", false, {0, INFINITY, true});
      const double thickness = read_.number(o, p, "thicknessFactor", false, kNonNegative).value_or(0.0);
      texture(o, p, "thicknessTexture");
      tail(o, p);
      // KHR_materials_volume: it only applies to surfaces that transmit light, and "is not
      // compatible with double-sided materials" in its thin-walled sense.
      // Any transmission extension counts, known or not (KHR_materials_transmission,
      // KHR_materials_diffuse_transmission, vendor ones), and so does any extension this step
      // does not read (undeclared or unsupported): what it holds is unknown, so it cannot be said
      // to let no light through (the reference's rule, checked on constructed files).
      bool transmits = false;
      for (const auto& [sibling, value] : owner_object["extensions"].items())
        if (sibling.find("transmission") != std::string::npos || !read_.context().declared(sibling) ||
            !extension_supported(sibling))
          transmits = true;
      if (!transmits) at_link("KHR_MATERIALS_VOLUME_NO_TRANSMISSION", p);
      auto double_sided = owner_object.find("doubleSided");
      if (thickness > 0 && double_sided != owner_object.end() && double_sided->is_boolean() &&
          double_sided->get<bool>())
        at_link("KHR_MATERIALS_VOLUME_DOUBLE_SIDED", p);
    } else if (name == "KHR_texture_transform") {
      read_.check_members(o, p, {"offset", "rotation", "scale", "texCoord", "extensions", "extras"});
      read_.numbers(o, p, "offset", {2});
      read_.number(o, p, "rotation");
      read_.numbers(o, p, "scale", {2});
      read_.integer(o, p, "texCoord", false, kNonNegative);
      tail(o, p);
    } else if (name == "EXT_texture_webp" || name == "KHR_texture_basisu") {
      read_.check_members(o, p, {"source", "extensions", "extras"});
      const std::int64_t source = read_.index(o, p, "source");
      tail(o, p);
      if (TextureModel* texture = hooks_.texture(); texture && source >= 0)
        texture->extension_sources.emplace_back(p + "/source", source);
    } else if (name == "KHR_node_visibility") {
      read_.check_members(o, p, {"visible", "extensions", "extras"});
      read_.boolean(o, p, "visible");
      tail(o, p);
    } else if (name == "KHR_animation_pointer") {
      read_.check_members(o, p, {"pointer", "extensions", "extras"});
      if (auto pointer = read_.string(o, p, "pointer", true)) {
        static const std::regex pattern(R"(^(?:\/(?:[^/~]|~0|~1)*)*$)");
        if (!std::regex_match(*pointer, pattern))
          issues_.at("PATTERN_MISMATCH", p + "/pointer", {arg(*pointer), arg(R"(^(?:\/(?:[^/~]|~0|~1)*)*$)")});
      }
      tail(o, p);
      // INCOMPLETE_EXTENSION_SUPPORT and the target checks come with the channel's link (links.cpp).
    } else if (name == "KHR_draco_mesh_compression") {
      read_.check_members(o, p, {"bufferView", "attributes", "extensions", "extras"});
      const std::int64_t view = read_.index(o, p, "bufferView", true);
      PrimitiveModel* primitive = hooks_.primitive();
      if (primitive) {
        primitive->draco = true;
        primitive->draco_buffer_view = view;
      }
      if (const Json* attributes = read_.object(o, p, "attributes", true)) {
        for (const auto& [key, value] : attributes->items()) {
          const std::int64_t id = read_.index(*attributes, p + "/attributes", key);
          if (primitive && id >= 0) primitive->draco_attributes[key] = id;
        }
      }
      tail(o, p);
    } else if (name == "EXT_meshopt_compression") {
      if (BufferViewModel* view = hooks_.buffer_view()) {
        meshopt_view(o, p, *view);
      } else if (BufferModel* buffer = hooks_.buffer()) {
        read_.check_members(o, p, {"fallback", "extensions", "extras"});
        buffer->meshopt_fallback = read_.boolean(o, p, "fallback").value_or(false);
        tail(o, p);
      }
    } else if (name == "KHR_lights_punctual") {
      if (hooks_.node()) {
        read_.check_members(o, p, {"light", "extensions", "extras"});
        const std::int64_t light = read_.index(o, p, "light", true);
        tail(o, p);
        hooks_.node()->light = light >= 0 ? light : -2;
        hooks_.node()->light_pointer = p;  // the root's lights are required when the node is linked
      } else {
        lights(o, p);
      }
    } else if (name == "KHR_materials_variants") {
      if (PrimitiveModel* primitive = hooks_.primitive())
        variant_mappings(o, p, *primitive);
      else
        variants(o, p);
    }
  }

 private:
  static bool has_sibling(const Json& owner_object, const char* name) {
    auto extensions = owner_object.find("extensions");
    return extensions != owner_object.end() && extensions->is_object() && extensions->contains(name);
  }

  // Extension textures use the core texCoord; normal-like ones should match normalTexture's set.
  void same_tex_coord(const Json& material, const Json& o, const std::string& p, const char* key, const char* code) {
    auto normal = material.find("normalTexture");
    auto texture = o.find(key);
    if (normal == material.end() || !normal->is_object() || texture == o.end() || !texture->is_object()) return;
    auto coord = [](const Json& info) {
      auto found = info.find("texCoord");
      return found != info.end() ? integer_value(*found).value_or(0) : 0;
    };
    if (coord(*normal) != coord(*texture)) at_link(code, p + "/" + key);
  }

  // A rule between a material's properties: the reference checks it when it links the material,
  // after the whole document is read (and the material's own texture references are resolved).
  void at_link(const char* code, const std::string& pointer) {
    if (MaterialModel* material = hooks_.material())
      material->extension_issues.emplace_back(code, pointer);
    else
      issues_.at(code, pointer);
  }

  void texture(const Json& o, const std::string& p, const char* key, int kind = 0) {
    hooks_.texture_info(o, p, key, kind);
  }

  void tail(const Json& o, const std::string& p) {
    read_extensions(read_, o, p, Owner::Other, hooks_);
    read_.extras(o, p);
  }

  void lights(const Json& o, const std::string& p) {
    read_.check_members(o, p, {"lights", "extensions", "extras"});
    Document& doc = read_.context().doc;
    doc.has_lights_root = true;
    if (auto list = read_.object_array(o, p, "lights", true, false)) {
      doc.lights.resize(list->size());
      for (std::size_t i = 0; i < list->size(); ++i) {
        if (!(*list)[i]) continue;
        doc.lights[i].object = true;
        const Json& light = *(*list)[i];
        const std::string lp = p + "/lights/" + std::to_string(i);
        read_.check_members(light, lp, {"name", "color", "intensity", "spot", "type", "range", "extensions", "extras"});
        read_.string(light, lp, "name");
        read_.numbers(light, lp, "color", {3}, kUnit);
        read_.number(light, lp, "intensity", false, kNonNegative);
        const Json* spot = read_.object(light, lp, "spot");
        auto type = read_.string(light, lp, "type", true, {"directional", "point", "spot"});
        auto range = read_.number(light, lp, "range", false, {0, INFINITY, true});
        // A range that could not be read is reported as such alone, not also as unused.
        if (type == "directional" && range) issues_.at("EXTRA_PROPERTY", lp + "/range");
        if (type == "spot" && !light.contains("spot")) issues_.at("UNDEFINED_PROPERTY", lp, {arg("spot")});
        // Only a spot light's spot is read: for any other type, or one that is not known, it is unused.
        if (type != "spot" && light.contains("spot")) issues_.at("EXTRA_PROPERTY", lp + "/spot");
        if (spot && type == "spot") {
          const std::string sp = lp + "/spot";
          read_.check_members(*spot, sp, {"innerConeAngle", "outerConeAngle", "extensions", "extras"});
          auto inner = read_.number(*spot, sp, "innerConeAngle", false, {0, M_PI / 2, false, true});
          auto outer = read_.number(*spot, sp, "outerConeAngle", false, {0, M_PI / 2, true, false});
          tail(*spot, sp);
          // The angles are compared only as read: a default stands in for an absent one, not for
          // one that was out of range (that is reported already).
          const bool comparable =
              (inner || !spot->contains("innerConeAngle")) && (outer || !spot->contains("outerConeAngle"));
          const double inner_value = inner.value_or(0.0), outer_value = outer.value_or(M_PI / 4);
          if (comparable && outer_value <= inner_value)
            issues_.at("KHR_LIGHTS_PUNCTUAL_LIGHT_SPOT_ANGLES", sp + "/outerConeAngle",
                       {arg_double(inner_value), arg_double(outer_value)});
        }
        tail(light, lp);
      }
    }
    tail(o, p);
  }

  void variants(const Json& o, const std::string& p) {
    read_.check_members(o, p, {"variants", "extensions", "extras"});
    Document& doc = read_.context().doc;
    doc.has_variants_root = true;
    if (auto list = read_.object_array(o, p, "variants", true, false)) {
      doc.variants.resize(list->size());
      for (std::size_t i = 0; i < list->size(); ++i) {
        if (!(*list)[i]) continue;
        doc.variants[i].object = true;
        const std::string vp = p + "/variants/" + std::to_string(i);
        read_.check_members(*(*list)[i], vp, {"name", "extensions", "extras"});
        read_.string(*(*list)[i], vp, "name", true);
        tail(*(*list)[i], vp);
      }
    }
    tail(o, p);
  }

  // The extension's bufferView schema. Its byteStride reads 4 to 252 in steps of 4 there, but the
  // README's rules allow 2 for TRIANGLES and INDICES and up to 256 for ATTRIBUTES (encoders write
  // 2-byte indices): the schema takes 2 to 256 and meshopt_layout_problem the rest, by mode.
  void meshopt_view(const Json& o, const std::string& p, BufferViewModel& view) {
    read_.check_members(
        o, p, {"buffer", "byteOffset", "byteLength", "byteStride", "count", "mode", "filter", "extensions", "extras"});
    view.meshopt_present = true;
    const std::int64_t buffer = read_.index(o, p, "buffer", true);
    const auto offset = read_.integer(o, p, "byteOffset", false, {0});
    const auto length = read_.integer(o, p, "byteLength", true, {1});
    const auto stride = read_.integer(o, p, "byteStride", true, {2, 256});
    const auto count = read_.integer(o, p, "count", true, {1});
    const auto mode = read_.string(o, p, "mode", true, {"ATTRIBUTES", "TRIANGLES", "INDICES"});
    const auto filter = read_.string(o, p, "filter", false, {"NONE", "OCTAHEDRAL", "QUATERNION", "EXPONENTIAL"});
    tail(o, p);
    const bool offset_valid = offset || o.find("byteOffset") == o.end();
    const bool filter_valid = filter || o.find("filter") == o.end();
    if (buffer < 0 || !offset_valid || !length || !stride || !count || !mode || !filter_valid) return;
    // Valid by the schema: read by the one reader of the object, which every other step uses too
    // (the same integers as the schema's: integer_value).
    std::string problem;
    view.meshopt = meshopt_view_from_json(o, problem);
  }

  void variant_mappings(const Json& o, const std::string& p, PrimitiveModel& primitive) {
    read_.check_members(o, p, {"mappings", "extensions", "extras"});
    if (auto list = read_.object_array(o, p, "mappings", true, false)) {
      for (std::size_t i = 0; i < list->size(); ++i) {
        if (!(*list)[i]) continue;
        const Json& mapping = *(*list)[i];
        PrimitiveModel::VariantMapping model;
        model.pointer = p + "/mappings/" + std::to_string(i);
        const std::string& mp = model.pointer;
        read_.check_members(mapping, mp, {"variants", "material", "name", "extensions", "extras"});
        if (auto variants = read_.indices(mapping, mp, "variants", true))
          for (std::size_t v = 0; v < variants->size(); ++v)
            if ((*variants)[v] >= 0) model.variants.emplace_back(mp + "/variants/" + std::to_string(v), (*variants)[v]);
        model.material = read_.index(mapping, mp, "material", true);
        model.material_pointer = mp + "/material";
        read_.string(mapping, mp, "name");
        tail(mapping, mp);
        primitive.variant_mappings.push_back(std::move(model));
      }
    }
    tail(o, p);
  }

  SchemaReader& read_;
  IssueSink& issues_;
  const ExtensionHooks& hooks_;
};

}  // namespace

bool extension_supported(const std::string& name) { return find_place(name) != nullptr; }

void read_extensions(SchemaReader& read, const Json& object, const std::string& pointer, Owner owner,
                     const ExtensionHooks& hooks) {
  auto found = object.find("extensions");
  if (found == object.end()) return;
  const std::string here = pointer + "/extensions";
  IssueSink& issues = read.issues();
  if (!found->is_object()) {
    issues.at("TYPE_MISMATCH", here, {arg_json(*found), arg("object")});
    return;
  }
  Context& context = read.context();
  for (const auto& [name, value] : found->items()) {
    const std::string p = here + "/" + escape_pointer_token(name);
    const ExtensionPlace* place = find_place(name);
    auto& seen = context.doc.extensions_seen;
    if (place && std::find(seen.begin(), seen.end(), name) == seen.end()) seen.push_back(name);
    if (!value.is_object()) issues.at("TYPE_MISMATCH", p, {arg_json(value), arg("object")});
    if (!context.declared(name)) {
      issues.at("UNDECLARED_EXTENSION", p);  // an undeclared object is not read further
      continue;
    }
    if (!place) continue;
    // Placement is judged whatever the value is (a misplaced non-object gets both issues).
    if (std::find(place->owners.begin(), place->owners.end(), owner) == place->owners.end()) {
      issues.at("UNEXPECTED_EXTENSION_OBJECT", p);
      continue;
    }
    // Unlit and specular-glossiness replace the core shading model, so other material extensions
    // may not combine with them (their specifications' "Extension compatibility" sections).
    // Reported before the extension's own content, as the reference does.
    if (owner == Owner::Material && found->size() > 1 &&
        (name == "KHR_materials_unlit" || name == "KHR_materials_pbrSpecularGlossiness"))
      issues.at("MULTIPLE_EXTENSIONS", p);
    // A non-object is read as an empty object (its required properties are then undefined).
    static const Json empty_object = Json::object();
    const Json& body = value.is_object() ? value : empty_object;
    // A required property missing inside an extension invalidates the extension, not its owner.
    const std::size_t missing_before = read.missing_count();
    ExtensionReader(read, hooks).read(name, object, body, p);
    read.set_missing_count(missing_before);
  }
}

}  // namespace gltf_pbr::structure
