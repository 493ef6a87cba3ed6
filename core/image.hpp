// Pixel access: decoding only when a step needs texels, and PNG/JPEG encoding. The codec is picked
// from the bytes' signature: libspng and TurboJPEG for PNG and JPEG (core/codecs.hpp), the
// OpenImageIO module for any other format and for filtered resizing, loaded only then.
#pragma once
#include <compare>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/files.hpp"
#include "core/texel_buffer.hpp"

namespace gltf_pbr {

// Texel bytes that a decoder or a bake fills completely right after allocating them
// (core/texel_buffer.hpp: not zeroed first, pages kept for reuse where that pays).
using TexelBytes = TexelBuffer<std::uint8_t>;

// Decoded pixels as stored (no colour conversion), channels interleaved, read normalised to
// [0, 1] through value()/at(). They are kept at the encoded precision: an 8-bit image holds one
// byte per value (a 2048² RGBA map takes 16 MB, not 64 as floats), 16-bit two, anything else
// (half, float) a float. Exactly one of the three vectors is filled.
struct Pixels {
  int width = 0, height = 0, channels = 0;
  int bits = 8;  // bits per channel in the encoded image
  TexelBytes bytes;
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

// The largest image decoded, in pixels: a header above it is refused before anything is allocated,
// so a 69-byte PNG that claims 60000x60000 costs nothing. 16384² is the largest texture current GPUs
// sample; `--max-image-pixels` moves it. Set once at start-up, before any decode.
inline constexpr std::uint64_t kDefaultMaxImagePixels = 16384ull * 16384ull;
void set_max_image_pixels(std::uint64_t pixels);
std::uint64_t max_image_pixels();

// Decodes PNG/JPEG/... bytes; alpha is kept unassociated (OpenImageIO would premultiply it).
// Counts into work_counters().images_decoded. Throws std::runtime_error naming `name_for_errors`
// and the reason: a corrupt or truncated stream, an image above max_image_pixels().
Pixels decode_image(std::span<const std::uint8_t> encoded, const std::string& name_for_errors);

// decode_image through OpenImageIO whatever the format: the reference the lean codecs are tested
// against (loads the module; no pixel limit, no counting).
Pixels decode_image_with_openimageio(std::span<const std::uint8_t> encoded);

// Resamples to width x height (OpenImageIO's filtered resize); a no-op when the size matches.
Pixels resize(const Pixels& pixels, int width, int height);

// The texel grid that a material's textures are baked and judged on (DESIGN.md, "Textures": the
// larger input resolution), each dimension on its own: 16384x1 beside 1x16384 is 16384². A texture
// of another size is read through `resize` to it, by the bake and by the material checks alike.
// 1 x 1 without textures (null entries are skipped).
struct TexelGrid {
  int width = 1, height = 1;
};
TexelGrid bake_grid(std::span<const Pixels* const> textures);

// Encodes 8-bit PNG; `channels` is 1-4, interleaved; `compression_level` is libdeflate's, 0-12
// (the tool and the library offer 0-9).
Bytes encode_png(std::span<const std::uint8_t> texels, int width, int height, int channels, int compression_level);
// The same for texels the caller gives up: they are freed once filtered, before the deflate, so a
// large map is not held twice while it compresses (Avocado at 4096²: 50 MB less at the peak).
Bytes encode_png(TexelBytes&& texels, int width, int height, int channels, int compression_level);

// encode_png in its two steps, for a caller with other work for the pool while an image
// compresses: filter_png picks the colour type and converts and filters the rows on the whole
// pool; deflate_png compresses them on the calling thread (libdeflate compresses a buffer whole)
// and writes the file.
struct FilteredPng {
  Bytes head;                            // signature, IHDR, PLTE and tRNS
  std::unique_ptr<std::uint8_t[]> rows;  // the filtered rows, `size` bytes
  std::size_t size = 0;
};
FilteredPng filter_png(std::span<const std::uint8_t> texels, int width, int height, int channels);
FilteredPng filter_png(TexelBytes&& texels, int width, int height, int channels);  // freed once filtered
// A palette image from a caller that knows its colours without a scan: a palette index a texel
// (rows top to bottom) and at most 256 colours, RGBA packed little-end first (an alpha below 255
// writes tRNS). The same file filter_png writes for those texels when it finds those colours in
// that order (first appearance).
FilteredPng filter_palette_png(std::span<const std::uint8_t> indices, std::span<const std::uint32_t> palette, int width,
                               int height);
Bytes deflate_png(FilteredPng&& filtered, int compression_level);

// A palette PNG's colours (PNG spec 11.2.3 PLTE, with 11.3.2.1 tRNS's alphas; 255 where it gives
// none), RGBA packed little-end first; std::nullopt for any other image or a PNG whose chunks do
// not read.
std::optional<std::vector<std::uint32_t>> png_palette(std::span<const std::uint8_t> png);
// The same palette PNG with `palette` (as many colours as its own) in place of its PLTE and tRNS
// (tRNS written only when a colour is not opaque): its image data and every other chunk byte for
// byte, so each texel is the new colour of its index. std::nullopt where png_palette would be.
std::optional<Bytes> png_with_palette(std::span<const std::uint8_t> png, std::span<const std::uint32_t> palette);

// Encodes 8-bit baseline JPEG (1 or 3 channels) at `quality` 1-100.
Bytes encode_jpeg(std::span<const std::uint8_t> texels, int width, int height, int channels, int quality);

// The identity of an image's encoded bytes: their XXH3-128 and their size. Two images with one key
// hold the same bytes (a collision is ~2^-64 likely even across millions of images).
struct ImageContentKey {
  std::uint64_t low = 0, high = 0, size = 0;
  auto operator<=>(const ImageContentKey&) const = default;
};
ImageContentKey image_content_key(std::span<const std::uint8_t> encoded);

struct Asset;

// Decoded images, each decoded at most once and only when asked for. Found by their encoded
// bytes, so an image one step has decoded, or baked without loss, is not decoded again by a later
// step of the same run: the conversion's pixels serve the preview's scene. Safe to share between
// threads.
class DecodedImages {
 public:
  // Image `image` of `asset`, decoded on first ask; the reference lives as long as this object.
  // Throws std::runtime_error naming the image when it cannot be decoded.
  const Pixels& get(const Asset& asset, int image);
  void keep(const ImageContentKey& key, std::shared_ptr<const Pixels> pixels);
  void forget(const ImageContentKey& key);                               // unless get() has handed it out
  std::shared_ptr<const Pixels> find(const ImageContentKey& key) const;  // null when not held
  void clear();  // gives the memory back (get()'s references end here)

 private:
  mutable std::mutex mutex_;
  std::map<ImageContentKey, std::shared_ptr<const Pixels>> by_content_;
  std::map<std::pair<const Asset*, int>, const Pixels*> by_image_;  // get()'s: no hash per texel read
};

// The functions the OpenImageIO module (core/image_oiio.cpp) provides; core/image.cpp loads it.
struct ImageCodec {
  Pixels (*decode)(std::span<const std::uint8_t> encoded, std::uint64_t max_pixels);
  Pixels (*resample)(const Pixels& pixels, int width, int height);
};

}  // namespace gltf_pbr
