// What an encoded image's header says, without decoding it: the format its signature names and, for
// PNG, JPEG and WebP, its size, channels, bit depth and colour space. The one sniffer for every step:
// the structure step's image checks and info block, the texture checks' sizes, the codec choice.
#pragma once
#include <cstdint>
#include <span>
#include <string>

namespace gltf_pbr {

enum class ImageFormat { Unknown, Png, Jpeg, Webp, Ktx2 };

// The format the bytes' signature names (PNG 5.2, JPEG's SOI + marker, RIFF/WEBP, KTX2's identifier).
ImageFormat image_format_of(std::span<const std::uint8_t> bytes);
// Its media type ("image/png", ...), "" for Unknown.
const char* mime_type_of(ImageFormat format);
inline std::string image_mime_of(std::span<const std::uint8_t> bytes) { return mime_type_of(image_format_of(bytes)); }

enum class HeaderProblem {
  None,
  Truncated,  // the stream ends before its header (or, for PNG, its last chunk) does
  Invalid,    // the bytes are not what the format allows; problem_message says how
};

struct ImageHeader {
  ImageFormat format = ImageFormat::Unknown;
  std::int64_t width = -1, height = -1;  // -1 where the header was not read that far
  std::string channels;                  // "rgb", "rgba", "luminance", "luminance-alpha" (the glTF info block's names)
  int bits = 8;
  // The colour space as the glTF info block names it: "srgb", "linear", "custom"; "" where the
  // format says nothing of it (JPEG).
  std::string primaries = "srgb", transfer = "srgb";
  bool unsupported_features = false;  // colour space, pixel aspect or animation glTF 3.8.2 does not cover
  HeaderProblem problem = HeaderProblem::None;
  std::string problem_message;  // for Invalid
};

// How far to read: all of the above, or the size and channels alone, which for PNG is IHDR without
// the walk to IEND (a caller that only plans a decode touches one page of a mapped file).
enum class HeaderDepth { Whole, Size };
// Reads the header of PNG (and walks its chunks to IEND), JPEG (to the start of frame) and WebP;
// KTX2 and unknown formats get only `format`. Bounded by the bytes there are, whatever they claim.
ImageHeader read_image_header(std::span<const std::uint8_t> bytes, HeaderDepth depth = HeaderDepth::Whole);

// Whether a header read without a problem gives a size other than a power of two on either side, 0
// included (IMAGE_NPOT_DIMENSIONS: WebGL 1.0 section 5.13.8 neither mipmaps nor repeats such textures).
inline bool has_npot_dimensions(const ImageHeader& header) {
  const auto power_of_two = [](std::int64_t n) { return n > 0 && (n & (n - 1)) == 0; };
  return header.problem == HeaderProblem::None && header.width >= 0 && header.height >= 0 &&
         (!power_of_two(header.width) || !power_of_two(header.height));
}

}  // namespace gltf_pbr
