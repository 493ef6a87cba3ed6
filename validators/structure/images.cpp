#include "validators/structure/images.hpp"

#include <cstring>
#include <fstream>

#include "core/image_header.hpp"

namespace gltf_pbr::structure {

namespace {


// The textureInfo keys whose texture holds colour (sRGB) data: glTF 2.0 section 3.9.2 (base colour,
// emissive), KHR_materials_sheen (sheenColorTexture), KHR_materials_specular (specularColorTexture),
// the archived KHR_materials_pbrSpecularGlossiness (diffuse, specular-glossiness RGB). Every other
// material texture is non-colour data (normals, occlusion, roughness, factors).
bool colour_texture(std::string_view texture_info_pointer) {
  const std::string_view key = texture_info_pointer.substr(texture_info_pointer.rfind('/') + 1);
  for (std::string_view colour : {"baseColorTexture", "emissiveTexture", "sheenColorTexture", "specularColorTexture",
                                  "diffuseTexture", "specularGlossinessTexture"})
    if (key == colour) return true;
  return false;
}

// Spec 5.26 sampler.minFilter: 9984-9987 minify through mipmaps. A texture with no sampler, or a
// sampler with no minFilter, leaves filtering to the client ("auto filtering"), which may mipmap.
bool minifies_with_mipmaps(const Document& doc, const TextureModel& texture) {
  if (texture.sampler < 0 || static_cast<std::size_t>(texture.sampler) >= doc.samplers.size()) return true;
  const std::int64_t filter = doc.samplers[static_cast<std::size_t>(texture.sampler)].min_filter;
  return filter < 0 || (filter >= 9984 && filter <= 9987);
}

// Each image's uses by materials, through a texture's source or an extension's (KHR_texture_basisu).
std::vector<ImageUse> image_uses(const Document& doc) {
  std::vector<ImageUse> uses(doc.images.size());
  for (const MaterialModel& material : doc.materials)
    for (const TextureRef& ref : material.textures) {
      if (ref.index < 0 || static_cast<std::size_t>(ref.index) >= doc.textures.size()) continue;
      const TextureModel& texture = doc.textures[static_cast<std::size_t>(ref.index)];
      auto note = [&](std::int64_t image) {
        if (image < 0 || static_cast<std::size_t>(image) >= uses.size()) return;
        ImageUse& use = uses[static_cast<std::size_t>(image)];
        std::string& by = colour_texture(ref.pointer) ? use.colour : use.non_colour;
        if (by.empty()) by = ref.pointer;
        if (use.mipmapped.empty() && minifies_with_mipmaps(doc, texture))
          use.mipmapped = "/textures/" + std::to_string(ref.index);
      };
      note(texture.source);
      for (const auto& [pointer, image] : texture.extension_sources) note(image);
    }
  return uses;
}

}  // namespace

void check_images(Context& context) {
  Document& doc = context.doc;
  IssueSink& issues = context.issues;
  const std::vector<ImageUse> uses = image_uses(doc);
  for (std::size_t i = 0; i < doc.images.size(); ++i) {
    ImageModel& image = doc.images[i];
    if (!image.object) continue;
    const std::string p = "/images/" + std::to_string(i);
    nlohmann::ordered_json resource;
    resource["pointer"] = p;
    std::span<const std::uint8_t> bytes;
    std::shared_ptr<const MappedFile> file;
    std::optional<std::string> declared = image.mime_type;
    bool have = false;
    std::string storage;
    // With both a bufferView and a URI (ONE_OF_MISMATCH), the bytes are the view's, as the
    // reference reads them; a view with a stride (IMAGE_BUFFER_VIEW_WITH_BYTESTRIDE) is read too.
    const bool in_view =
        image.buffer_view >= 0 && static_cast<std::size_t>(image.buffer_view) < doc.buffer_views.size();
    if (in_view) {
      storage = "buffer-view";
      if (auto view_bytes = buffer_view_bytes(doc, image.buffer_view)) {
        bytes = *view_bytes;
        have = true;
      }
    } else if (image.has_uri) {
      if (!image.uri_valid) {
        context.resources.push_back(std::move(resource));
        continue;
      }
      if (image.data_uri) {
        storage = "data-uri";
        bytes = image.data;
        have = true;
        if (!declared && !image.data_uri_mime.empty()) declared = image.data_uri_mime;
      } else {
        storage = "external";
        if (context.options.validate_resources) {
          if ((file = read_resource(context, image.uri, p + "/uri"))) {
            bytes = file->bytes();
            have = true;
          }
        }
      }
    }
    ImageHeader header;
    if (have) header = read_image_header(bytes);
    const std::string mime = mime_type_of(header.format);
    image.detected_mime = mime;
    if (!mime.empty() && header.problem == HeaderProblem::None) resource["mimeType"] = mime;
    if (!storage.empty()) resource["storage"] = storage;
    if (storage == "external") resource["uri"] = image.uri;
    if (have) {
      if (mime.empty()) {
        issues.at("IMAGE_UNRECOGNIZED_FORMAT", p);
      } else if (header.problem == HeaderProblem::Truncated) {
        // A stream that ends inside what the header check reads tells nothing else (the
        // reference's answer: no media type compared).
        issues.at("IMAGE_UNEXPECTED_EOS", p);
      } else {
        auto enabled = [&](const char* extension) {
          const auto& seen = context.doc.extensions_seen;
          return context.declared(extension) || std::find(seen.begin(), seen.end(), extension) != seen.end();
        };
        if ((header.format == ImageFormat::Webp && !enabled("EXT_texture_webp")) ||
            (header.format == ImageFormat::Ktx2 && !enabled("KHR_texture_basisu")))
          issues.at("IMAGE_NON_ENABLED_MIME_TYPE", p, {arg(mime)});
        if (declared && *declared != mime)
          issues.at("IMAGE_MIME_TYPE_INVALID", in_view ? p + "/bufferView" : p + "/uri", {arg(mime), arg(*declared)});
        if (header.problem == HeaderProblem::Invalid)
          issues.at("IMAGE_DATA_INVALID", p, {arg_raw(header.problem_message)});
        if (header.problem == HeaderProblem::None && header.unsupported_features)
          issues.at("IMAGE_FEATURES_UNSUPPORTED", p);
        if (header.format == ImageFormat::Ktx2)  // ours: the reference stops at the signature
          for (const Ktx2Finding& finding : check_ktx2(bytes, uses[i]))
            issues.at(finding.code, p, {arg_raw(finding.reason)});
        if (header.problem == HeaderProblem::None && header.width >= 0) {
          nlohmann::ordered_json& info = resource["image"];
          info = {{"width", header.width}, {"height", header.height}, {"format", header.channels}};
          if (!header.primaries.empty()) info["primaries"] = header.primaries;
          if (!header.transfer.empty()) info["transfer"] = header.transfer;
          info["bits"] = header.bits;
          if (has_npot_dimensions(header))
            issues.at("IMAGE_NPOT_DIMENSIONS", p, {arg(header.width), arg(header.height)});
        }
      }
    }
    context.resources.push_back(std::move(resource));
  }
}

// Spec 3.8.2: a texture's own source is PNG or JPEG; other formats come through extensions, whose
// sources are of their one type (EXT_texture_webp: WebP; KHR_texture_basisu: KTX2), where the
// extension is declared. The reference judges these after every image has been read, from the type
// the image declares (its mimeType, else its valid data URI's media type) or else the type its
// bytes have, the texture's own source first (checked against the npm validator).
void check_texture_sources(Context& context) {
  const Document& doc = context.doc;
  const auto type_of = [&](std::int64_t source) -> const std::string* {
    if (source < 0 || static_cast<std::size_t>(source) >= doc.images.size()) return nullptr;
    const ImageModel& image = doc.images[static_cast<std::size_t>(source)];
    if (!image.object) return nullptr;
    // A declared mimeType counts even when it is "" (then no type is valid); a URI that is
    // invalid (INVALID_URI) declares nothing.
    if (image.mime_type) return &*image.mime_type;
    const std::string& mime =
        image.uri_valid && !image.data_uri_mime.empty() ? image.data_uri_mime : image.detected_mime;
    return mime.empty() ? nullptr : &mime;
  };
  for (std::size_t i = 0; i < doc.textures.size(); ++i) {
    const TextureModel& texture = doc.textures[i];
    if (!texture.object) continue;
    const std::string p = "/textures/" + std::to_string(i);
    if (const std::string* mime = type_of(texture.source); mime && *mime != "image/png" && *mime != "image/jpeg")
      context.issues.at("TEXTURE_INVALID_IMAGE_MIME_TYPE", p + "/source", {arg(*mime)},
                        {arg("image/jpeg"), arg("image/png")});
    for (const auto& [pointer, source] : texture.extension_sources) {
      const bool webp = pointer.find("/EXT_texture_webp/") != std::string::npos;
      if (!context.declared(webp ? "EXT_texture_webp" : "KHR_texture_basisu")) continue;
      const char* expected = webp ? "image/webp" : "image/ktx2";
      if (const std::string* mime = type_of(source); mime && *mime != expected)
        context.issues.at("TEXTURE_INVALID_IMAGE_MIME_TYPE", pointer, {arg(*mime)}, {arg(expected)});
    }
  }
}

}  // namespace gltf_pbr::structure
