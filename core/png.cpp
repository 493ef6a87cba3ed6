// PNG through libspng: decode with the tRNS chunk as alpha (as OpenImageIO did), and encode in the
// smallest lossless colour type with the sub filter and zlib's run-length strategy, which DESIGN.md
// measured at a third of OpenImageIO's encode time for smaller files on baked maps.
#include <spng.h>
#include <zlib.h>

#include <algorithm>
#include <memory>
#include <stdexcept>
#include <vector>

#include "core/codecs.hpp"

namespace gltf_pbr::codecs {
namespace {

using Context = std::unique_ptr<spng_ctx, decltype(&spng_ctx_free)>;

void check(int status, const char* what) {
  if (status != 0) throw std::runtime_error(std::string(what) + ": " + spng_strerror(status));
}

// The largest chunk and the most chunk data kept (text, ICC profiles): enough for any real
// profile, and a bound whatever a chunk's length field claims.
constexpr std::size_t kChunkLimit = 16u << 20;

}  // namespace

std::string too_large(std::uint64_t width, std::uint64_t height, std::uint64_t max_pixels) {
  return "image is " + std::to_string(width) + "x" + std::to_string(height) + " = " + std::to_string(width * height) +
         " pixels, above the limit of " + std::to_string(max_pixels) + " (--max-image-pixels)";
}

Pixels decode_png(std::span<const std::uint8_t> encoded, std::uint64_t max_pixels) {
  Context ctx(spng_ctx_new(0), &spng_ctx_free);
  if (!ctx) throw std::bad_alloc();
  check(spng_set_chunk_limits(ctx.get(), kChunkLimit, kChunkLimit), "PNG");
  check(spng_set_png_buffer(ctx.get(), encoded.data(), encoded.size()), "PNG");
  spng_ihdr header{};
  check(spng_get_ihdr(ctx.get(), &header), "PNG header");
  if (static_cast<std::uint64_t>(header.width) * header.height > max_pixels)
    throw std::runtime_error(too_large(header.width, header.height, max_pixels));
  spng_trns transparency{};
  const bool has_trns = spng_get_trns(ctx.get(), &transparency) == 0;
  const bool wide = header.bit_depth == 16;

  // Channels as stored (PNG spec 11.2.2 IHDR colour types), tRNS adding an alpha channel.
  Pixels pixels;
  pixels.width = static_cast<int>(header.width);
  pixels.height = static_cast<int>(header.height);
  pixels.bits = wide ? 16 : 8;
  // spng converts to G8, GA8/GA16 (grey sources only), RGB8, RGBA8 and RGBA16; the rest is read
  // as stored (SPNG_FMT_PNG: the file's channels and depth, 16-bit samples in host order).
  int format = SPNG_FMT_PNG;
  switch (header.color_type) {
    case SPNG_COLOR_TYPE_GRAYSCALE:
      pixels.channels = has_trns ? 2 : 1;
      if (has_trns)
        format = wide ? SPNG_FMT_GA16 : SPNG_FMT_GA8;
      else if (!wide)
        format = SPNG_FMT_G8;  // also unpacks 1-, 2- and 4-bit grey
      break;
    case SPNG_COLOR_TYPE_GRAYSCALE_ALPHA:
      pixels.channels = 2;
      break;
    case SPNG_COLOR_TYPE_INDEXED:
      pixels.channels = has_trns ? 4 : 3;
      format = has_trns ? SPNG_FMT_RGBA8 : SPNG_FMT_RGB8;
      break;
    case SPNG_COLOR_TYPE_TRUECOLOR:
      pixels.channels = has_trns ? 4 : 3;
      if (has_trns) format = wide ? SPNG_FMT_RGBA16 : SPNG_FMT_RGBA8;
      break;
    default:  // SPNG_COLOR_TYPE_TRUECOLOR_ALPHA
      pixels.channels = 4;
      break;
  }
  std::size_t size = 0;
  check(spng_decoded_image_size(ctx.get(), format, &size), "PNG");
  const int flags = has_trns ? SPNG_DECODE_TRNS : 0;
  if (wide) {
    pixels.shorts.resize(size / 2);
    check(spng_decode_image(ctx.get(), pixels.shorts.data(), size, format, flags), "PNG data");
  } else {
    pixels.bytes.resize(size);
    check(spng_decode_image(ctx.get(), pixels.bytes.data(), size, format, flags), "PNG data");
  }
  return pixels;
}

namespace {

// Texel t of `channels` 8-bit channels as RGBA packed little-end first: grey repeats, a missing
// alpha is opaque (how PNG readers expand it).
std::uint32_t packed_rgba(const std::uint8_t* t, int channels) {
  const bool colour = channels >= 3, alpha = channels == 2 || channels == 4;
  const std::uint32_t r = t[0], g = colour ? t[1] : r, b = colour ? t[2] : r, a = alpha ? t[channels - 1] : 255;
  return r | g << 8 | b << 16 | a << 24;
}

// What a set of 8-bit texels needs (PNG spec 11.2.2): whether every texel is grey (R = G = B),
// whether the alpha channel is all 255, and the distinct colours when there are at most 256.
struct ColourUse {
  bool grey = true, opaque = true;
  std::vector<std::uint32_t> palette;  // RGBA packed; empty when more than 256 colours occur
};

ColourUse colour_use(std::span<const std::uint8_t> texels, int channels) {
  ColourUse use;
  // Open addressing over 1024 slots holds 256 colours with few collisions. A slot holds its
  // colour shifted up by one with the low bit set, so that 0 can mark it empty.
  std::vector<std::uint64_t> slots(1024, 0);
  bool few = true;
  const std::size_t count = texels.size() / static_cast<std::size_t>(channels);
  for (std::size_t i = 0; i < count && (few || use.grey || use.opaque); ++i) {
    const std::uint32_t rgba = packed_rgba(&texels[i * static_cast<std::size_t>(channels)], channels);
    const std::uint32_t r = rgba & 0xFF, g = rgba >> 8 & 0xFF, b = rgba >> 16 & 0xFF;
    use.grey = use.grey && r == g && g == b;
    use.opaque = use.opaque && rgba >> 24 == 0xFF;
    if (!few) continue;
    const std::uint64_t key = (static_cast<std::uint64_t>(rgba) << 1) | 1;
    for (std::size_t slot = (rgba * 2654435761u) >> 22;; slot = (slot + 1) & 1023) {
      if (slots[slot] == key) break;
      if (slots[slot] == 0) {
        slots[slot] = key;
        use.palette.push_back(rgba);
        few = use.palette.size() <= 256;
        break;
      }
    }
  }
  if (!few) use.palette.clear();
  return use;
}

}  // namespace

Bytes encode_png(std::span<const std::uint8_t> texels, int width, int height, int channels, int compression_level) {
  if (channels < 1 || channels > 4) throw std::runtime_error("PNG encoder: " + std::to_string(channels) + " channels");
  if (width < 1 || height < 1 ||
      texels.size() !=
          static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * static_cast<std::size_t>(channels))
    throw std::runtime_error("PNG encoder: " + std::to_string(texels.size()) + " bytes for " + std::to_string(width) +
                             "x" + std::to_string(height) + "x" + std::to_string(channels));
  Context ctx(spng_ctx_new(SPNG_CTX_ENCODER), &spng_ctx_free);
  if (!ctx) throw std::bad_alloc();
  check(spng_set_option(ctx.get(), SPNG_ENCODE_TO_BUFFER, 1), "PNG encoder");
  check(spng_set_option(ctx.get(), SPNG_IMG_COMPRESSION_LEVEL, compression_level), "PNG encoder");
  check(spng_set_option(ctx.get(), SPNG_IMG_COMPRESSION_STRATEGY, Z_RLE), "PNG encoder");

  // The smallest lossless form, one byte a texel where it can be: grey when R = G = B and no alpha
  // is needed, else a palette (with tRNS for alpha) when at most 256 colours occur, else grey with
  // alpha, else the channels as given. An opaque alpha channel is left out (it reads back as 1).
  // Baked maps of a few colours (BoxTexturedNonPowerOfTwo's) shrink to a fraction.
  const ColourUse use = colour_use(texels, channels);
  const std::size_t count = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const bool colour = channels >= 3, alpha = channels == 2 || channels == 4;
  const bool keep_alpha = alpha && !use.opaque;
  std::vector<std::uint8_t> converted;
  auto gather = [&](int out_channels, auto&& write) {
    converted.resize(count * static_cast<std::size_t>(out_channels));
    for (std::size_t i = 0; i < count; ++i)
      write(&texels[i * static_cast<std::size_t>(channels)], &converted[i * static_cast<std::size_t>(out_channels)]);
  };
  spng_ihdr header{};
  header.width = static_cast<std::uint32_t>(width);
  header.height = static_cast<std::uint32_t>(height);
  header.bit_depth = 8;
  std::span<const std::uint8_t> image = texels;
  spng_plte plte{};
  spng_trns trns{};
  if (use.grey && !keep_alpha) {
    header.color_type = SPNG_COLOR_TYPE_GRAYSCALE;
    if (channels != 1) gather(1, [](const std::uint8_t* in, std::uint8_t* out) { out[0] = in[0]; });
  } else if (!use.palette.empty() && (colour || keep_alpha)) {
    header.color_type = SPNG_COLOR_TYPE_INDEXED;
    plte.n_entries = static_cast<std::uint32_t>(use.palette.size());
    std::vector<std::pair<std::uint32_t, std::uint8_t>> sorted;
    for (std::size_t k = 0; k < use.palette.size(); ++k) {
      const std::uint32_t rgba = use.palette[k];
      plte.entries[k] = {static_cast<std::uint8_t>(rgba), static_cast<std::uint8_t>(rgba >> 8),
                         static_cast<std::uint8_t>(rgba >> 16), 0};
      trns.type3_alpha[k] = static_cast<std::uint8_t>(rgba >> 24);
      sorted.emplace_back(rgba, static_cast<std::uint8_t>(k));
    }
    std::sort(sorted.begin(), sorted.end());
    gather(1, [&](const std::uint8_t* in, std::uint8_t* out) {
      const std::pair<std::uint32_t, std::uint8_t> colour_at(packed_rgba(in, channels), 0);
      out[0] = std::lower_bound(sorted.begin(), sorted.end(), colour_at)->second;
    });
    if (keep_alpha) trns.n_type3_entries = plte.n_entries;
  } else if (use.grey) {
    header.color_type = SPNG_COLOR_TYPE_GRAYSCALE_ALPHA;
    if (channels != 2)
      gather(2, [&](const std::uint8_t* in, std::uint8_t* out) { out[0] = in[0], out[1] = in[channels - 1]; });
  } else if (alpha && !keep_alpha) {
    header.color_type = SPNG_COLOR_TYPE_TRUECOLOR;  // colour: the grey cases are above
    gather(3, [](const std::uint8_t* in, std::uint8_t* out) { out[0] = in[0], out[1] = in[1], out[2] = in[2]; });
  } else {
    static constexpr std::uint8_t kColourType[] = {SPNG_COLOR_TYPE_GRAYSCALE, SPNG_COLOR_TYPE_GRAYSCALE_ALPHA,
                                                   SPNG_COLOR_TYPE_TRUECOLOR, SPNG_COLOR_TYPE_TRUECOLOR_ALPHA};
    header.color_type = kColourType[channels - 1];
  }
  if (!converted.empty()) image = converted;
  // PNG spec 12.8: palette images compress best unfiltered; the others with the sub filter.
  check(
      spng_set_option(ctx.get(), SPNG_FILTER_CHOICE,
                      header.color_type == SPNG_COLOR_TYPE_INDEXED ? SPNG_FILTER_CHOICE_NONE : SPNG_FILTER_CHOICE_SUB),
      "PNG encoder");
  check(spng_set_ihdr(ctx.get(), &header), "PNG encoder");  // before PLTE and tRNS, as in the file
  if (header.color_type == SPNG_COLOR_TYPE_INDEXED) {
    check(spng_set_plte(ctx.get(), &plte), "PNG encoder");
    if (trns.n_type3_entries > 0) check(spng_set_trns(ctx.get(), &trns), "PNG encoder");
  }
  check(spng_encode_image(ctx.get(), image.data(), image.size(), SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE), "PNG encoder");
  std::size_t size = 0;
  int status = 0;
  std::unique_ptr<void, decltype(&std::free)> buffer(spng_get_png_buffer(ctx.get(), &size, &status), &std::free);
  check(status, "PNG encoder");
  const auto* begin = static_cast<const std::uint8_t*>(buffer.get());
  return Bytes(begin, begin + size);
}

}  // namespace gltf_pbr::codecs
