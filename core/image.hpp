// Pixel access through OpenImageIO: decoding only when a step needs texels, and PNG encoding.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/files.hpp"

namespace gltf_pbr {

// Decoded pixels as stored (no colour conversion), channels interleaved, read normalised to
// [0, 1] through value()/at(). They are kept at the encoded precision: an 8-bit image holds one
// byte per value (a 2048² RGBA map takes 16 MB, not 64 as floats), 16-bit two, anything else
// (half, float) a float. Exactly one of the three vectors is filled.
struct Pixels {
  int width = 0, height = 0, channels = 0;
  int bits = 8;  // bits per channel in the encoded image
  std::vector<std::uint8_t> bytes;
  std::vector<std::uint16_t> shorts;
  std::vector<float> floats;

  std::size_t size() const { return !bytes.empty() ? bytes.size() : !shorts.empty() ? shorts.size() : floats.size(); }
  // Value i (texel i / channels, channel i % channels) in [0, 1] for integer images.
  float value(std::size_t i) const {
    if (!bytes.empty()) return static_cast<float>(bytes[i]) / 255.0f;
    if (!shorts.empty()) return static_cast<float>(shorts[i]) / 65535.0f;
    return floats[i];
  }
  float at(int x, int y, int c) const {
    return value((static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x)) *
                     static_cast<size_t>(channels) +
                 static_cast<size_t>(c));
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
