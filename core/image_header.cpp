#include "core/image_header.hpp"

#include <cstring>

#include "core/byte_order.hpp"

namespace gltf_pbr {

ImageFormat image_format_of(std::span<const std::uint8_t> bytes) {
  static constexpr std::uint8_t png[8] = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  static constexpr std::uint8_t ktx2[12] = {0xAB, 'K', 'T', 'X', ' ', '2', '0', 0xBB, 0x0D, 0x0A, 0x1A, 0x0A};
  if (bytes.size() >= 8 && std::memcmp(bytes.data(), png, 8) == 0) return ImageFormat::Png;
  if (bytes.size() >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF) return ImageFormat::Jpeg;
  if (bytes.size() >= 12 && std::memcmp(bytes.data(), "RIFF", 4) == 0 && std::memcmp(bytes.data() + 8, "WEBP", 4) == 0)
    return ImageFormat::Webp;
  if (bytes.size() >= 12 && std::memcmp(bytes.data(), ktx2, 12) == 0) return ImageFormat::Ktx2;
  return ImageFormat::Unknown;
}

const char* mime_type_of(ImageFormat format) {
  // In ImageFormat's order.
  static constexpr const char* kMimeTypes[] = {"", "image/png", "image/jpeg", "image/webp", "image/ktx2"};
  return kMimeTypes[static_cast<int>(format)];
}

namespace {

// PNG (ISO/IEC 15948): the signature, then IHDR as the first chunk.
void read_png(std::span<const std::uint8_t> b, HeaderDepth depth, ImageHeader& header) {
  if (b.size() < 33) {
    header.problem = HeaderProblem::Truncated;
    return;
  }
  // Without IHDR first (PNG 11.2.2) nothing of the image can be known; the reference reports
  // nothing for it either (checked against the npm validator): no size, no issue.
  if (big_endian32(b, 8) != 13 || std::memcmp(&b[12], "IHDR", 4) != 0) return;
  header.width = big_endian32(b, 16);
  header.height = big_endian32(b, 20);
  header.bits = b[24];
  switch (b[25]) {
    case 0:
      header.channels = "luminance";
      break;
    case 4:
      header.channels = "luminance-alpha";
      break;
    case 6:
      header.channels = "rgba";
      break;
    default:
      header.channels = "rgb";
      break;
  }
  if (depth == HeaderDepth::Size) return;
  // Walk the chunks to IEND: a stream that ends inside one is truncated.
  std::size_t offset = 8;
  while (true) {
    if (offset + 8 > b.size()) {
      header.problem = HeaderProblem::Truncated;
      return;
    }
    const std::uint64_t length = big_endian32(b, offset);
    const bool end = std::memcmp(&b[offset + 4], "IEND", 4) == 0;
    if (offset + 12 + length > b.size()) {
      header.problem = HeaderProblem::Truncated;
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
    const std::size_t data = offset + 8;  // where the chunk's data starts
    // The same chunks name the colour space the info block reports: an ICC profile is custom
    // primaries and transfer, other chromaticities custom primaries, a gamma of 100000 (1.0) a
    // linear transfer and any other but sRGB's a custom one (PNG 11.3.3.2).
    if (std::memcmp(type, "iCCP", 4) == 0) {
      header.unsupported_features = true;
      header.primaries = header.transfer = "custom";
    }
    if (std::memcmp(type, "pHYs", 4) == 0 && length >= 9 && big_endian32(b, data) != big_endian32(b, data + 4))
      header.unsupported_features = true;
    if (std::memcmp(type, "gAMA", 4) == 0 && length >= 4 && big_endian32(b, data) != 45455) {
      const bool linear = big_endian32(b, data) == 100000;
      if (!linear) header.unsupported_features = true;
      header.transfer = linear ? "linear" : "custom";
    }
    if (std::memcmp(type, "cHRM", 4) == 0 && length >= 32)
      for (int k = 0; k < 8; ++k)
        if (big_endian32(b, data + 4 * k) != kSrgbChromaticities[k]) {
          header.unsupported_features = true;
          header.primaries = "custom";
        }
    // PNG 11.3.2.1: transparency for a palette, grey or RGB image gives it an alpha channel.
    if (std::memcmp(type, "tRNS", 4) == 0) {
      if (header.channels == "luminance") header.channels = "luminance-alpha";
      if (header.channels == "rgb") header.channels = "rgba";
    }
    offset += 12 + length;
  }
}

// JPEG (ITU T.81 annex B): marker segments up to a start-of-frame, which holds the size.
void read_jpeg(std::span<const std::uint8_t> b, ImageHeader& header) {
  std::size_t offset = 2;
  while (true) {
    if (offset + 4 > b.size()) {
      header.problem = HeaderProblem::Truncated;
      return;
    }
    if (b[offset] != 0xFF) {
      header.problem = HeaderProblem::Invalid;
      header.problem_message = "Invalid JPEG marker.";
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
    const std::uint32_t length = big_endian16(b, offset + 2);
    if (length < 2) {
      header.problem = HeaderProblem::Invalid;
      header.problem_message = "Invalid JPEG marker segment length.";
      return;
    }
    const bool frame = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (frame) {
      if (offset + 10 > b.size()) {
        header.problem = HeaderProblem::Truncated;
        return;
      }
      header.bits = b[offset + 4];
      header.height = big_endian16(b, offset + 5);
      header.width = big_endian16(b, offset + 7);
      // A glTF JPEG is grey or colour (JFIF: 1 or 3 components); 4 is CMYK, which renderers do
      // not decode as colour (the reference: IMAGE_DATA_INVALID, no image info).
      const int components = b[offset + 9];
      if (components != 1 && components != 3) {
        header.problem = HeaderProblem::Invalid;
        header.problem_message = "Invalid number of JPEG color channels.";
        return;
      }
      header.channels = components == 1 ? "luminance" : "rgb";
      header.primaries.clear();  // JPEG names no colour space (an ICC profile or Exif aside)
      header.transfer.clear();
      return;
    }
    offset += 2 + length;
  }
}

// WebP (RFC 9649): a RIFF container with one VP8, VP8L or VP8X first chunk.
void read_webp(std::span<const std::uint8_t> b, ImageHeader& header) {
  if (b.size() < 30) {
    header.problem = HeaderProblem::Truncated;
    return;
  }
  header.channels = "rgb";
  if (std::memcmp(&b[12], "VP8 ", 4) == 0) {
    header.width = (b[26] | (b[27] << 8)) & 0x3FFF;
    header.height = (b[28] | (b[29] << 8)) & 0x3FFF;
  } else if (std::memcmp(&b[12], "VP8L", 4) == 0) {
    const std::uint32_t bits = b[21] | (b[22] << 8) | (b[23] << 16) | (std::uint32_t(b[24]) << 24);
    header.width = (bits & 0x3FFF) + 1;
    header.height = ((bits >> 14) & 0x3FFF) + 1;
    if ((bits >> 28) & 1) header.channels = "rgba";
  } else if (std::memcmp(&b[12], "VP8X", 4) == 0) {
    if (b[20] & 0x10) header.channels = "rgba";
    header.width = little_endian24(b, 24) + 1;
    header.height = little_endian24(b, 27) + 1;
  }
}

}  // namespace

ImageHeader read_image_header(std::span<const std::uint8_t> b, HeaderDepth depth) {
  ImageHeader header;
  header.format = image_format_of(b);
  if (header.format == ImageFormat::Png)
    read_png(b, depth, header);
  else if (header.format == ImageFormat::Jpeg)
    read_jpeg(b, header);
  else if (header.format == ImageFormat::Webp)
    read_webp(b, header);
  return header;
}

}  // namespace gltf_pbr
