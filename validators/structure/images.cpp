#include "validators/structure/images.hpp"

#include <cstring>
#include <fstream>

namespace gltf_pbr::structure {

std::string image_mime_of(std::span<const std::uint8_t> bytes) {
  static constexpr std::uint8_t png[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  static constexpr std::uint8_t ktx2[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
  if (bytes.size() >= 8 && std::memcmp(bytes.data(), png, 8) == 0) return "image/png";
  if (bytes.size() >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF) return "image/jpeg";
  if (bytes.size() >= 12 && std::memcmp(bytes.data(), "RIFF", 4) == 0 && std::memcmp(bytes.data() + 8, "WEBP", 4) == 0)
    return "image/webp";
  if (bytes.size() >= 12 && std::memcmp(bytes.data(), ktx2, 12) == 0) return "image/ktx2";
  return {};
}

namespace {

struct ImageHeader {
  std::string mime;  // "" when not recognised
  std::int64_t width = -1, height = -1;
  std::string format;  // "rgb", "rgba", "luminance", "luminance-alpha"
  int bits = 8;
  // The info block's colour space: "srgb", "linear", "custom"; "" where the format says nothing
  // of it (JPEG: the reference leaves both out).
  std::string primaries = "srgb", transfer = "srgb";
  bool unsupported_features = false;  // colour space, pixel aspect or animation the spec does not cover
  std::string error_code;             // IMAGE_UNEXPECTED_EOS, IMAGE_DATA_INVALID
  std::string error_message;          // for IMAGE_DATA_INVALID
};

std::uint32_t big_endian32(const std::uint8_t* p) {
  return (std::uint32_t(p[0]) << 24) | (std::uint32_t(p[1]) << 16) | (std::uint32_t(p[2]) << 8) | p[3];
}
std::uint32_t big_endian16(const std::uint8_t* p) { return (std::uint32_t(p[0]) << 8) | p[1]; }
std::uint32_t little_endian24(const std::uint8_t* p) {
  return std::uint32_t(p[0]) | (std::uint32_t(p[1]) << 8) | (std::uint32_t(p[2]) << 16);
}

// PNG (ISO/IEC 15948): the signature, then IHDR as the first chunk.
void read_png(std::span<const std::uint8_t> b, ImageHeader& header) {
  header.mime = "image/png";
  if (b.size() < 33) {
    header.error_code = "IMAGE_UNEXPECTED_EOS";
    return;
  }
  // Without IHDR first (PNG 11.2.2) nothing of the image can be known; the reference reports
  // nothing for it either (checked against the npm validator): no size, no issue.
  if (big_endian32(&b[8]) != 13 || std::memcmp(&b[12], "IHDR", 4) != 0) return;
  header.width = big_endian32(&b[16]);
  header.height = big_endian32(&b[20]);
  header.bits = b[24];
  switch (b[25]) {
    case 0:
      header.format = "luminance";
      break;
    case 4:
      header.format = "luminance-alpha";
      break;
    case 6:
      header.format = "rgba";
      break;
    default:
      header.format = "rgb";
      break;
  }
  // Walk the chunks to IEND: a stream that ends inside one is truncated.
  std::size_t offset = 8;
  while (true) {
    if (offset + 8 > b.size()) {
      header.error_code = "IMAGE_UNEXPECTED_EOS";
      return;
    }
    const std::uint64_t length = big_endian32(&b[offset]);
    const bool end = std::memcmp(&b[offset + 4], "IEND", 4) == 0;
    if (offset + 12 + length > b.size()) {
      header.error_code = "IMAGE_UNEXPECTED_EOS";
      return;
    }
    if (end) return;
    // Spec 3.8.2: PNG colour is sRGB; an ICC profile, chromaticities other than sRGB's (PNG
    // 11.3.3.1, the exact values PNG gives for sRGB), a gamma other than sRGB's 45455 or the
    // neutral 100000, and non-square pixels are colour space information a glTF renderer
    // ignores. What the reference counts, checked value by value against the npm validator:
    // it does not count an APNG animation control chunk (acTL).
    static constexpr std::uint32_t kSrgbChromaticities[8] = {31270, 32900, 64000, 33000, 30000, 60000, 15000, 6000};
    const auto* type = &b[offset + 4];
    const auto* data = &b[offset + 8];
    // The same chunks name the colour space the info block reports: an ICC profile is custom
    // primaries and transfer, other chromaticities custom primaries, a gamma of 100000 (1.0) a
    // linear transfer and any other but sRGB's a custom one (PNG 11.3.3.2).
    if (std::memcmp(type, "iCCP", 4) == 0) {
      header.unsupported_features = true;
      header.primaries = header.transfer = "custom";
    }
    if (std::memcmp(type, "pHYs", 4) == 0 && length >= 9 && big_endian32(data) != big_endian32(data + 4))
      header.unsupported_features = true;
    if (std::memcmp(type, "gAMA", 4) == 0 && length >= 4 && big_endian32(data) != 45455) {
      const bool linear = big_endian32(data) == 100000;
      if (!linear) header.unsupported_features = true;
      header.transfer = linear ? "linear" : "custom";
    }
    if (std::memcmp(type, "cHRM", 4) == 0 && length >= 32)
      for (int k = 0; k < 8; ++k)
        if (big_endian32(data + 4 * k) != kSrgbChromaticities[k]) {
          header.unsupported_features = true;
          header.primaries = "custom";
        }
    // PNG 11.3.2.1: transparency for a palette, grey or RGB image gives it an alpha channel.
    if (std::memcmp(type, "tRNS", 4) == 0) {
      if (header.format == "luminance") header.format = "luminance-alpha";
      if (header.format == "rgb") header.format = "rgba";
    }
    offset += 12 + length;
  }
}

// JPEG (ITU T.81 annex B): marker segments up to a start-of-frame, which holds the size.
void read_jpeg(std::span<const std::uint8_t> b, ImageHeader& header) {
  header.mime = "image/jpeg";
  std::size_t offset = 2;
  while (true) {
    if (offset + 4 > b.size()) {
      header.error_code = "IMAGE_UNEXPECTED_EOS";
      return;
    }
    if (b[offset] != 0xFF) {
      header.error_code = "IMAGE_DATA_INVALID";
      header.error_message = "Invalid JPEG marker.";
      return;
    }
    const std::uint8_t marker = b[offset + 1];
    if (marker == 0xFF) {
      ++offset;
      continue;
    }
    if (marker == 0xD8 || (marker >= 0xD0 && marker <= 0xD7) || marker == 0x01) {
      offset += 2;
      continue;
    }
    const std::uint32_t length = big_endian16(&b[offset + 2]);
    if (length < 2) {
      header.error_code = "IMAGE_DATA_INVALID";
      header.error_message = "Invalid JPEG marker segment length.";
      return;
    }
    const bool frame = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (frame) {
      if (offset + 10 > b.size()) {
        header.error_code = "IMAGE_UNEXPECTED_EOS";
        return;
      }
      header.bits = b[offset + 4];
      header.height = big_endian16(&b[offset + 5]);
      header.width = big_endian16(&b[offset + 7]);
      // A glTF JPEG is grey or colour (JFIF: 1 or 3 components); 4 is CMYK, which renderers do
      // not decode as colour (the reference: IMAGE_DATA_INVALID, no image info).
      const int components = b[offset + 9];
      if (components != 1 && components != 3) {
        header.error_code = "IMAGE_DATA_INVALID";
        header.error_message = "Invalid number of JPEG color channels.";
        return;
      }
      header.format = components == 1 ? "luminance" : "rgb";
      header.primaries.clear();  // JPEG names no colour space (an ICC profile or Exif aside)
      header.transfer.clear();
      return;
    }
    offset += 2 + length;
  }
}

// WebP (RFC 9649): a RIFF container with one VP8, VP8L or VP8X first chunk.
void read_webp(std::span<const std::uint8_t> b, ImageHeader& header) {
  header.mime = "image/webp";
  if (b.size() < 30) {
    header.error_code = "IMAGE_UNEXPECTED_EOS";
    return;
  }
  header.format = "rgb";
  if (std::memcmp(&b[12], "VP8 ", 4) == 0) {
    header.width = (b[26] | (b[27] << 8)) & 0x3FFF;
    header.height = (b[28] | (b[29] << 8)) & 0x3FFF;
  } else if (std::memcmp(&b[12], "VP8L", 4) == 0) {
    const std::uint32_t bits = b[21] | (b[22] << 8) | (b[23] << 16) | (std::uint32_t(b[24]) << 24);
    header.width = (bits & 0x3FFF) + 1;
    header.height = ((bits >> 14) & 0x3FFF) + 1;
    if ((bits >> 28) & 1) header.format = "rgba";
  } else if (std::memcmp(&b[12], "VP8X", 4) == 0) {
    if (b[20] & 0x10) header.format = "rgba";
    header.width = little_endian24(&b[24]) + 1;
    header.height = little_endian24(&b[27]) + 1;
  }
}

ImageHeader read_header(std::span<const std::uint8_t> b) {
  ImageHeader header;
  const std::string mime = image_mime_of(b);
  if (mime == "image/png")
    read_png(b, header);
  else if (mime == "image/jpeg")
    read_jpeg(b, header);
  else if (mime == "image/webp")
    read_webp(b, header);
  else if (mime == "image/ktx2")
    header.mime = mime;
  return header;
}

bool power_of_two(std::int64_t value) { return value > 0 && (value & (value - 1)) == 0; }

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
    std::string declared = image.mime_type;
    bool have = false;
    std::string storage;
    if (image.has_uri) {
      if (!image.uri_valid) {
        context.resources.push_back(std::move(resource));
        continue;
      }
      if (image.data_uri) {
        storage = "data-uri";
        bytes = image.data;
        have = true;
        if (declared.empty()) declared = image.data_uri_mime;
      } else {
        storage = "external";
        if (context.options.validate_resources) {
          if ((file = read_resource(context, image.uri, p + "/uri"))) {
            bytes = file->bytes();
            have = true;
          }
        }
      }
    } else if (image.buffer_view >= 0 && static_cast<std::size_t>(image.buffer_view) < doc.buffer_views.size()) {
      storage = "buffer-view";
      // Strided views cannot hold an image (IMAGE_BUFFER_VIEW_WITH_BYTESTRIDE): not read.
      if (doc.buffer_views[static_cast<std::size_t>(image.buffer_view)].byte_stride == 0)
        if (auto view_bytes = buffer_view_bytes(doc, image.buffer_view)) {
          bytes = *view_bytes;
          have = true;
        }
    }
    ImageHeader header;
    if (have) header = read_header(bytes);
    image.detected_mime = header.mime;
    if (!header.mime.empty() && header.error_code.empty()) resource["mimeType"] = header.mime;
    if (!storage.empty()) resource["storage"] = storage;
    if (storage == "external") resource["uri"] = image.uri;
    if (have) {
      if (header.mime.empty()) {
        issues.at("IMAGE_UNRECOGNIZED_FORMAT", p);
      } else {
        auto enabled = [&](const char* extension) {
          const auto& seen = context.doc.extensions_seen;
          return context.declared(extension) || std::find(seen.begin(), seen.end(), extension) != seen.end();
        };
        if ((header.mime == "image/webp" && !enabled("EXT_texture_webp")) ||
            (header.mime == "image/ktx2" && !enabled("KHR_texture_basisu")))
          issues.at("IMAGE_NON_ENABLED_MIME_TYPE", p, {arg(header.mime)});
        if (!declared.empty() && declared != header.mime)
          issues.at("IMAGE_MIME_TYPE_INVALID", image.has_uri ? p + "/uri" : p + "/bufferView",
                    {arg(header.mime), arg(declared)});
        if (header.error_code == "IMAGE_DATA_INVALID")
          issues.at("IMAGE_DATA_INVALID", p, {arg_raw(header.error_message)});
        else if (!header.error_code.empty())
          issues.at(header.error_code, p);
        if (header.error_code.empty() && header.unsupported_features) issues.at("IMAGE_FEATURES_UNSUPPORTED", p);
        if (header.mime == "image/ktx2")  // ours: the reference stops at the signature
          for (const Ktx2Finding& finding : check_ktx2(bytes, uses[i]))
            issues.at(finding.code, p, {arg_raw(finding.reason)});
        if (header.error_code.empty() && header.width >= 0) {
          nlohmann::ordered_json& info = resource["image"];
          info = {{"width", header.width}, {"height", header.height}, {"format", header.format}};
          if (!header.primaries.empty()) info["primaries"] = header.primaries;
          if (!header.transfer.empty()) info["transfer"] = header.transfer;
          info["bits"] = header.bits;
          if (!power_of_two(header.width) || !power_of_two(header.height))
            issues.at("IMAGE_NPOT_DIMENSIONS", p, {arg(header.width), arg(header.height)});
        }
      }
    }
    context.resources.push_back(std::move(resource));
  }
}

// Spec 3.8.2: a texture's own source is PNG or JPEG; other formats come through extensions. The
// reference judges this after every image has been read, from the type the image declares (its
// mimeType, else its data URI's media type) or else the type its bytes have (checked against the
// npm validator).
void check_texture_sources(Context& context) {
  const Document& doc = context.doc;
  for (std::size_t i = 0; i < doc.textures.size(); ++i) {
    const TextureModel& texture = doc.textures[i];
    if (!texture.object || texture.source < 0 || static_cast<std::size_t>(texture.source) >= doc.images.size())
      continue;
    const ImageModel& image = doc.images[static_cast<std::size_t>(texture.source)];
    if (!image.object) continue;
    const std::string& mime = !image.mime_type.empty()       ? image.mime_type
                              : !image.data_uri_mime.empty() ? image.data_uri_mime
                                                             : image.detected_mime;
    if (!mime.empty() && mime != "image/png" && mime != "image/jpeg")
      context.issues.at("TEXTURE_INVALID_IMAGE_MIME_TYPE", "/textures/" + std::to_string(i) + "/source", {arg(mime)},
                        {arg("image/jpeg"), arg("image/png")});
  }
}

}  // namespace gltf_pbr::structure
