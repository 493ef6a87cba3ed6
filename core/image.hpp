// Pixel access through OpenImageIO: decoding only when a step needs texels, and PNG encoding.
#pragma once
#include <span>
#include <string>
#include <vector>

#include "core/files.hpp"

namespace gltf_pbr {

// Decoded pixels as stored (no colour conversion), normalised to [0, 1], channels interleaved.
struct Pixels {
  int width = 0, height = 0, channels = 0;
  int bits = 8;  // bits per channel in the encoded image
  std::vector<float> values;
  float at(int x, int y, int c) const {
    return values[(static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) *
                      static_cast<size_t>(channels) +
                  static_cast<size_t>(c)];
  }
};

// Decodes PNG/JPEG/... bytes; alpha is kept unassociated (OpenImageIO would premultiply it).
// Counts into work_counters().images_decoded. Throws std::runtime_error with OIIO's reason.
Pixels decode_image(std::span<const std::uint8_t> encoded, const std::string& name_for_errors);

// Resamples to width x height (OpenImageIO's filtered resize); a no-op when the size matches.
Pixels resize(const Pixels& pixels, int width, int height);

// Encodes 8-bit PNG; `channels` is 1-4, interleaved.
Bytes encode_png(std::span<const std::uint8_t> texels, int width, int height, int channels, int compression_level);

// Encodes 8-bit baseline JPEG (1 or 3 channels) at `quality` 1-100.
Bytes encode_jpeg(std::span<const std::uint8_t> texels, int width, int height, int channels, int quality);

// True when the bytes carry a JPEG signature.
bool is_jpeg(std::span<const std::uint8_t> encoded);

// The functions the OpenImageIO module (core/image_oiio.cpp) provides; core/image.cpp loads it.
struct ImageCodec {
  Pixels (*decode)(std::span<const std::uint8_t> encoded, const std::string& name_for_errors);
  Pixels (*resample)(const Pixels& pixels, int width, int height);
  Bytes (*encode_png)(std::span<const std::uint8_t> texels, int width, int height, int channels, int compression_level);
  Bytes (*encode_jpeg)(std::span<const std::uint8_t> texels, int width, int height, int channels, int quality);
};

}  // namespace gltf_pbr
