// PNG: decode through libspng with the tRNS chunk as alpha (as OpenImageIO did), the common
// layouts' image data inflated by libdeflate (decode_png says why); encode in the smallest lossless
// colour type with the Average filter, deflated by libdeflate (deflate_png says why). The encoder
// writes the chunks itself: libspng deflates through zlib.
#include <libdeflate.h>
#include <spng.h>

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

#include "core/asset.hpp"
#include "core/byte_order.hpp"
#include "core/codecs.hpp"
#include "core/parallel.hpp"
#include "core/texel_buffer.hpp"

namespace gltf_pbr::codecs {
namespace {

using Context = std::unique_ptr<spng_ctx, decltype(&spng_ctx_free)>;

void check(int status, const char* what) {
  if (status != 0) throw std::runtime_error(std::string(what) + ": " + spng_strerror(status));
}

// The largest chunk and the most chunk data kept (text, ICC profiles): enough for any real
// profile, and a bound whatever a chunk's length field claims.
constexpr std::size_t kChunkLimit = 16u << 20;

// The image data (PNG spec 10.1: the IDAT chunks' data joined, one zlib stream) in `joined`, or
// in place when it is one chunk; the CRC-32 of each chunk up to the last IDAT checked (PNG spec
// 5.3). Empty where the chunks are not laid out as the spec says (no IDAT, a chunk running past
// the end or with a bad CRC): libspng then reads the file and names what is wrong.
std::span<const std::uint8_t> image_data(std::span<const std::uint8_t> png, std::vector<std::uint8_t>& joined) {
  std::vector<std::span<const std::uint8_t>> parts;
  std::size_t total = 0;
  for (std::size_t at = 8; at + 12 <= png.size();) {
    const std::uint8_t* const type = &png[at + 4];
    const bool idat = std::memcmp(type, "IDAT", 4) == 0;
    if (!idat && (!parts.empty() || std::memcmp(type, "IEND", 4) == 0)) break;  // PNG spec 5.6: IDATs are consecutive
    const std::size_t length = big_endian32(png, at);
    if (length > 0x7FFFFFFFu || length > png.size() - at - 12) return {};
    if (libdeflate_crc32(0, type, 4 + length) != big_endian32(png, at + 8 + length)) return {};
    if (idat) parts.emplace_back(type + 4, length), total += length;
    at += 12 + length;
  }
  if (parts.size() <= 1) return parts.empty() ? std::span<const std::uint8_t>() : parts[0];
  joined.reserve(total);
  advise_huge_pages(joined.data(), total);
  for (const auto part : parts) joined.insert(joined.end(), part.begin(), part.end());
  return joined;
}

// The reconstruction of one row (PNG spec 9.2-9.4) of `row_bytes`, `Bpp` bytes a pixel, from
// `in` (its filtered bytes, after the filter type) and `above` (the row above, reconstructed; zeros
// for the first row). `out` may lie below `in` in one buffer: each byte is read before any byte at
// or above it is written. False for an unknown filter type.
template <std::size_t Bpp>
bool unfilter_row(std::uint8_t type, const std::uint8_t* in, const std::uint8_t* above, std::uint8_t* out,
                  std::size_t row_bytes) {
  const std::size_t first = std::min(Bpp, row_bytes);  // the bytes with no pixel to their left
  switch (type) {
    case 0:  // None
      std::memmove(out, in, row_bytes);
      return true;
    case 1:  // Sub: the byte a pixel to the left
      std::memmove(out, in, first);
      for (std::size_t i = first; i < row_bytes; ++i) out[i] = static_cast<std::uint8_t>(in[i] + out[i - Bpp]);
      return true;
    case 2:  // Up: the byte above
      for (std::size_t i = 0; i < row_bytes; ++i) out[i] = static_cast<std::uint8_t>(in[i] + above[i]);
      return true;
    case 3:  // Average of the left and upper bytes, rounded down
      for (std::size_t i = 0; i < first; ++i) out[i] = static_cast<std::uint8_t>(in[i] + (above[i] >> 1));
      for (std::size_t i = first; i < row_bytes; ++i)
        out[i] = static_cast<std::uint8_t>(in[i] + ((out[i - Bpp] + above[i]) >> 1));
      return true;
    case 4:  // Paeth: of left, above and upper left, the one nearest left + above - upper left
      for (std::size_t i = 0; i < first; ++i) out[i] = static_cast<std::uint8_t>(in[i] + above[i]);
      for (std::size_t i = first; i < row_bytes; ++i) {
        const int a = out[i - Bpp], b = above[i], c = above[i - Bpp];
        const int pa = std::abs(b - c), pb = std::abs(a - c), pc = std::abs(a + b - 2 * c);
        const int predicted = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
        out[i] = static_cast<std::uint8_t>(in[i] + predicted);
      }
      return true;
    default:
      return false;
  }
}

// Reconstructs `height` rows in place: filtered row y (its type byte first) lies at
// y * (row_bytes + 1) and its texels go to y * row_bytes, below what is still to be read.
template <std::size_t Bpp>
bool unfilter_rows(std::uint8_t* data, std::size_t row_bytes, std::size_t height) {
  const std::vector<std::uint8_t> zeros(row_bytes, 0);
  for (std::size_t y = 0; y < height; ++y) {
    const std::uint8_t* const filtered = data + y * (row_bytes + 1);
    const std::uint8_t* const above = y == 0 ? zeros.data() : data + (y - 1) * row_bytes;
    if (!unfilter_row<Bpp>(filtered[0], filtered + 1, above, data + y * row_bytes, row_bytes)) return false;
  }
  return true;
}

// The texels of a non-interlaced 8-bit image of `channels` bytes a pixel, inflated by libdeflate
// and reconstructed; false where the data is not a whole, valid image of that size (the caller
// then decodes with libspng, which names the fault).
bool inflate_and_unfilter(std::span<const std::uint8_t> png, std::size_t width, std::size_t height,
                          std::size_t channels, TexelBytes& texels) {
  std::vector<std::uint8_t> joined;
  const std::span<const std::uint8_t> stream = image_data(png, joined);
  if (stream.empty()) return false;
  const std::size_t row_bytes = width * channels;
  texels.resize(height * (row_bytes + 1));  // the filtered rows, reconstructed in place
  const std::unique_ptr<libdeflate_decompressor, decltype(&libdeflate_free_decompressor)> inflater(
      libdeflate_alloc_decompressor(), &libdeflate_free_decompressor);
  if (!inflater) throw std::bad_alloc();
  // Exactly the image's size, and the Adler-32 checked (RFC 1950); data after the stream is ignored.
  if (libdeflate_zlib_decompress(inflater.get(), stream.data(), stream.size(), texels.data(), texels.size(), nullptr) !=
      LIBDEFLATE_SUCCESS)
    return false;
  // By bytes a pixel: `channels` is 1 to 4 here (8-bit grey, grey + alpha, RGB, RGBA).
  static constexpr bool (*kUnfilter[])(std::uint8_t*, std::size_t, std::size_t) = {unfilter_rows<1>, unfilter_rows<2>,
                                                                                   unfilter_rows<3>, unfilter_rows<4>};
  if (!kUnfilter[channels - 1](texels.data(), row_bytes, height)) return false;
  texels.resize(height * row_bytes);
  ++work_counters().png_streams_inflated;
  return true;
}

}  // namespace

std::string too_large(std::uint64_t width, std::uint64_t height, std::uint64_t max_pixels) {
  return "image is " + std::to_string(width) + "x" + std::to_string(height) + " = " + std::to_string(width * height) +
         " pixels, above the limit of " + std::to_string(max_pixels) + " (--max-image-pixels)";
}

Pixels decode_png(std::span<const std::uint8_t> encoded, std::uint64_t max_pixels, PngInflater inflater) {
  Context ctx(spng_ctx_new(0), &spng_ctx_free);
  if (!ctx) throw std::bad_alloc();
  check(spng_set_chunk_limits(ctx.get(), kChunkLimit, kChunkLimit), "PNG");
  check(spng_set_png_buffer(ctx.get(), encoded.data(), encoded.size()), "PNG");
  spng_ihdr header{};
  check(spng_get_ihdr(ctx.get(), &header), "PNG header");
  if (static_cast<std::uint64_t>(header.width) * header.height > max_pixels)
    throw std::runtime_error(too_large(header.width, header.height, max_pixels));
  spng_trns transparency{};
  // Reading tRNS reads every chunk before the first IDAT: a fault there (an unknown critical chunk,
  // a second IHDR, a PLTE of a wrong length) is the file's error, which the libdeflate path below
  // would not see.
  const int trns = spng_get_trns(ctx.get(), &transparency);
  if (trns != 0 && trns != SPNG_ECHUNKAVAIL) check(trns, "PNG");
  const bool has_trns = trns == 0;
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
  // libdeflate inflates image data 2.4-3.6 times as fast as the zlib inside libspng (the 4096²
  // Avocado maps: 108 against 45 ms, 51 against 14; the larger one's decode is the conversion's
  // critical path). So the common layout (8 bits a sample, not interlaced, no palette or tRNS) is
  // inflated and reconstructed here; the rest, and any file whose chunks or stream that path
  // refuses, goes to libspng, which decodes it or names what is wrong.
  if (inflater == PngInflater::Libdeflate && header.bit_depth == 8 && header.interlace_method == 0 && !has_trns &&
      header.color_type != SPNG_COLOR_TYPE_INDEXED &&
      inflate_and_unfilter(encoded, header.width, header.height, static_cast<std::size_t>(pixels.channels),
                           pixels.bytes))
    return pixels;
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
// whether the alpha channel is all 255, and the distinct colours when there are at most 256, with
// the palette index of each. Scanned in parts on the thread pool, each part until nothing is left
// for it to learn; the parts' colours join in part order, which is the order of first appearance
// in the whole image, so the palette does not depend on the thread count.
class ColourUse {
 public:
  ColourUse(std::span<const std::uint8_t> texels, int channels) {
    constexpr std::size_t kPartTexels = 1u << 18;
    const std::size_t count = texels.size() / static_cast<std::size_t>(channels);
    std::vector<Part> parts((count + kPartTexels - 1) / kPartTexels);
    parallel_dynamic(static_cast<std::int64_t>(parts.size()), [&](std::int64_t index) {
      const std::size_t first = static_cast<std::size_t>(index) * kPartTexels;
      parts[static_cast<std::size_t>(index)].scan(texels, channels, first, std::min(count, first + kPartTexels));
    });
    bool few = true;
    for (const Part& part : parts) {
      grey = grey && part.grey, opaque = opaque && part.opaque, few = few && part.few;
      for (std::size_t c = 0; few && c < part.colours.size(); ++c) few = add(part.colours[c]);
    }
    if (!few) palette.clear();
  }

  bool grey = true, opaque = true;
  std::vector<std::uint32_t> palette;  // RGBA packed, by first appearance; empty above 256 colours

  // The palette index of a colour that occurs.
  std::uint8_t index_of(std::uint32_t rgba) const { return static_cast<std::uint8_t>(slots_.at(rgba) >> 33); }

 private:
  // Open addressing over 1024 slots holds 256 colours with few collisions. A slot holds its
  // colour shifted up by one with the low bit set, so that 0 can mark it empty, and its index above.
  class Slots {
   public:
    std::uint64_t& at(std::uint32_t rgba) { return slots_[slot_of(rgba)]; }
    std::uint64_t at(std::uint32_t rgba) const { return slots_[slot_of(rgba)]; }

   private:
    std::size_t slot_of(std::uint32_t rgba) const {
      const std::uint64_t key = static_cast<std::uint64_t>(rgba) << 1 | 1;
      std::size_t slot = (rgba * 2654435761u) >> 22;
      while (slots_[slot] != 0 && (slots_[slot] & 0x1FFFFFFFFull) != key) slot = (slot + 1) & 1023;
      return slot;
    }
    std::vector<std::uint64_t> slots_ = std::vector<std::uint64_t>(1024, 0);
  };

  // One part's findings: its colours by first appearance while there are at most 256.
  struct Part {
    bool grey = true, opaque = true, few = true;
    std::vector<std::uint32_t> colours;
    void scan(std::span<const std::uint8_t> texels, int channels, std::size_t first, std::size_t end) {
      const bool alpha = channels == 2 || channels == 4;
      Slots seen;
      // Neighbouring texels mostly repeat a colour: only a change is looked up.
      std::uint32_t last = 0;
      bool has_last = false;
      // Until nothing is left to learn: without an alpha channel, every texel is opaque.
      for (std::size_t i = first; i < end && (few || grey || (alpha && opaque)); ++i) {
        const std::uint32_t rgba = packed_rgba(&texels[i * static_cast<std::size_t>(channels)], channels);
        if (has_last && rgba == last) continue;
        last = rgba, has_last = true;
        const std::uint32_t r = rgba & 0xFF, g = rgba >> 8 & 0xFF, b = rgba >> 16 & 0xFF;
        grey = grey && r == g && g == b;
        opaque = opaque && rgba >> 24 == 0xFF;
        if (!few) continue;
        std::uint64_t& slot = seen.at(rgba);
        if (slot != 0) continue;
        slot = static_cast<std::uint64_t>(rgba) << 1 | 1;
        colours.push_back(rgba);
        few = colours.size() <= 256;
      }
      if (!few) colours.clear();
    }
  };

  // Adds a colour to the palette unless it is there; false past 256 colours.
  bool add(std::uint32_t rgba) {
    std::uint64_t& slot = slots_.at(rgba);
    if (slot != 0) return true;
    slot = static_cast<std::uint64_t>(palette.size()) << 33 | static_cast<std::uint64_t>(rgba) << 1 | 1;
    palette.push_back(rgba);
    return palette.size() <= 256;
  }
  Slots slots_;
};

// PNG colour types (PNG spec 11.2.2).
enum class ColourType : std::uint8_t { Grey = 0, Rgb = 2, Palette = 3, GreyAlpha = 4, Rgba = 6 };

constexpr std::uint8_t kSignature[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};

void put_be32(std::uint8_t* out, std::uint32_t v) {
  out[0] = static_cast<std::uint8_t>(v >> 24), out[1] = static_cast<std::uint8_t>(v >> 16);
  out[2] = static_cast<std::uint8_t>(v >> 8), out[3] = static_cast<std::uint8_t>(v);
}

// A chunk (PNG spec 5.3): length, type, data, and the CRC-32 of type and data. The data may come
// in parts, written as one chunk.
void append_chunk(Bytes& png, const char (&type)[5], std::initializer_list<std::span<const std::uint8_t>> data) {
  std::size_t length = 0;
  for (std::span<const std::uint8_t> part : data) length += part.size();
  if (length > 0x7FFFFFFFu) throw std::runtime_error("PNG encoder: a chunk above 2^31 - 1 bytes");
  std::uint8_t head[8];
  put_be32(head, static_cast<std::uint32_t>(length));
  std::memcpy(head + 4, type, 4);
  png.insert(png.end(), head, head + 8);
  std::uint32_t crc = libdeflate_crc32(0, head + 4, 4);
  for (std::span<const std::uint8_t> part : data) {
    if (part.empty()) continue;
    png.insert(png.end(), part.begin(), part.end());
    crc = libdeflate_crc32(crc, part.data(), part.size());
  }
  std::uint8_t tail[4];
  put_be32(tail, static_cast<std::uint32_t>(crc));
  png.insert(png.end(), tail, tail + 4);
}

// PLTE, and tRNS up to the last colour that is not opaque (PNG spec 11.2.3, 11.3.2.1), of
// `palette` (RGBA packed, little-end first).
void append_palette(Bytes& png, std::span<const std::uint32_t> palette) {
  std::vector<std::uint8_t> plte, trns;
  for (const std::uint32_t rgba : palette) {
    plte.insert(plte.end(), {static_cast<std::uint8_t>(rgba), static_cast<std::uint8_t>(rgba >> 8),
                             static_cast<std::uint8_t>(rgba >> 16)});
    trns.push_back(static_cast<std::uint8_t>(rgba >> 24));
  }
  append_chunk(png, "PLTE", {plte});
  // Entries past tRNS's end are opaque (PNG spec 11.3.2.1): its trailing 255s are left out.
  while (!trns.empty() && trns.back() == 255) trns.pop_back();
  if (!trns.empty()) append_chunk(png, "tRNS", {trns});
}

// The image data's zlib stream in IDAT chunks of 1 MiB (any split reads the same; PNG spec 10.1),
// and IEND: the end of every PNG this module writes.
void append_image_data(Bytes& png, std::span<const std::uint8_t> stream) {
  constexpr std::size_t kChunkBytes = 1u << 20;
  png.reserve(png.size() + stream.size() + (stream.size() / kChunkBytes + 1) * 12 + 12);
  advise_huge_pages(png.data() + png.size(), png.capacity() - png.size());
  for (std::size_t at = 0; at < stream.size(); at += kChunkBytes)
    append_chunk(png, "IDAT", {stream.subspan(at, std::min(kChunkBytes, stream.size() - at))});
  append_chunk(png, "IEND", {});
}

// PNG spec 5.2-5.3 and 11.2: signature, IHDR, and for a palette image PLTE, with tRNS when a
// colour is not opaque (`palette` is RGBA packed, little-end first); IDAT and IEND in deflate_png.
Bytes png_head(int width, int height, ColourType colour_type, std::span<const std::uint32_t> palette) {
  Bytes head(kSignature, kSignature + sizeof kSignature);
  std::uint8_t ihdr[13] = {};
  put_be32(ihdr, static_cast<std::uint32_t>(width));
  put_be32(ihdr + 4, static_cast<std::uint32_t>(height));
  ihdr[8] = 8;  // bit depth; compression, filter and interlace methods 0
  ihdr[9] = static_cast<std::uint8_t>(colour_type);
  append_chunk(head, "IHDR", {ihdr});
  if (colour_type == ColourType::Palette) append_palette(head, palette);
  return head;
}

// The filters the encoder writes (PNG spec 9.2): None for palette images, Average for the rest.
enum class RowFilter : std::uint8_t { None = 0, Average = 3 };

// A row under the Average filter (PNG spec 9.2): each byte less the mean of the byte a pixel
// before (0 at the left) and the one above. The pointers are declared apart so that the loop is
// vectorised: through the caller's buffers the compiler reloaded them for every byte (Avocado's
// 4096² base colour: 50 MB filtered a byte at a time, about 55 ms of CPU; bench/RESULTS.md, session 38).
void average_filtered_row(const std::uint8_t* __restrict row, const std::uint8_t* __restrict above,
                          std::uint8_t* __restrict out, std::size_t row_bytes, std::size_t pixel_bytes) {
  const std::size_t left_edge = std::min(pixel_bytes, row_bytes);
  for (std::size_t i = 0; i < left_edge; ++i) out[i] = static_cast<std::uint8_t>(row[i] - (above[i] >> 1));
  for (std::size_t i = left_edge; i < row_bytes; ++i)
    out[i] = static_cast<std::uint8_t>(row[i] - ((row[i - pixel_bytes] + above[i]) >> 1));
}

// The filtered rows (PNG spec 7.3, 9), converted and filtered in parts on the pool into one
// buffer; it is not zeroed. `row_of(y, scratch)` gives row y as stored: the caller's texels, or
// their conversion written into `scratch` (room for a row). `release`, when given, holds the
// texels and is emptied once they are filtered.
template <class RowOf>
void filter_rows(FilteredPng& png, const RowOf& row_of, std::size_t width, std::size_t height, std::size_t pixel_bytes,
                 RowFilter filter, TexelBytes* release) {
  const std::size_t row_bytes = width * pixel_bytes, filtered_row_bytes = 1 + row_bytes;
  // Plain heap memory, not texel pages: where texel pages are kept for reuse (a preview), these
  // transient buffers would stay mapped after the encode.
  png.size = filtered_row_bytes * height;
  png.rows = std::make_unique_for_overwrite<std::uint8_t[]>(png.size);
  advise_huge_pages(png.rows.get(), png.size);
  constexpr std::size_t kPartBytes = 1u << 20;
  const std::size_t rows_per_part = std::max<std::size_t>(1, kPartBytes / filtered_row_bytes);
  const std::vector<std::uint8_t> zeros(row_bytes, 0);  // the row above the first
  parallel_dynamic(static_cast<std::int64_t>((height + rows_per_part - 1) / rows_per_part), [&](std::int64_t part) {
    // Two rows of scratch: a converted row stays the next one's row above.
    std::vector<std::uint8_t> scratch(2 * row_bytes);
    const std::size_t first = static_cast<std::size_t>(part) * rows_per_part;
    const std::uint8_t* above =
        first == 0 || filter == RowFilter::None ? zeros.data() : row_of(first - 1, scratch.data() + row_bytes);
    for (std::size_t y = first; y < std::min(height, first + rows_per_part); ++y) {
      const std::uint8_t* const row = row_of(y, scratch.data() + (y - first) % 2 * row_bytes);
      std::uint8_t* const out = png.rows.get() + y * filtered_row_bytes;
      out[0] = static_cast<std::uint8_t>(filter);
      if (filter == RowFilter::None)
        std::memcpy(out + 1, row, row_bytes);
      else
        average_filtered_row(row, above, out + 1, row_bytes, pixel_bytes);
      above = row;
    }
  });
  if (release) TexelBytes().swap(*release);  // the texels are read no more
}
}  // namespace

FilteredPng filter_png(std::span<const std::uint8_t> texels, int width, int height, int channels, TexelBytes* release) {
  if (channels < 1 || channels > 4) throw std::runtime_error("PNG encoder: " + std::to_string(channels) + " channels");
  if (width < 1 || height < 1 ||
      texels.size() !=
          static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * static_cast<std::size_t>(channels))
    throw std::runtime_error("PNG encoder: " + std::to_string(texels.size()) + " bytes for " + std::to_string(width) +
                             "x" + std::to_string(height) + "x" + std::to_string(channels));
  // The smallest lossless form, one byte a texel where it can be: grey when R = G = B and no alpha
  // is needed, else a palette (with tRNS for alpha) when at most 256 colours occur, else grey with
  // alpha, else the channels as given. An opaque alpha channel is left out (it reads back as 1).
  // Baked maps of a few colours (BoxTexturedNonPowerOfTwo's) shrink to a fraction.
  const ColourUse use(texels, channels);
  const bool colour = channels >= 3, alpha = channels == 2 || channels == 4;
  const bool keep_alpha = alpha && !use.opaque;
  // How a row is converted to the stored form: channels kept (their offsets in a texel) or the
  // palette index.
  enum class Conversion { None, Channels, PaletteIndex };
  Conversion conversion = Conversion::Channels;
  int kept[3] = {0, channels - 1, 0};
  ColourType colour_type;
  int pixel_bytes = channels;
  if (use.grey && !keep_alpha) {
    colour_type = ColourType::Grey, pixel_bytes = 1;
  } else if (!use.palette.empty() && (colour || keep_alpha)) {
    colour_type = ColourType::Palette, pixel_bytes = 1, conversion = Conversion::PaletteIndex;
  } else if (use.grey) {
    colour_type = ColourType::GreyAlpha, pixel_bytes = 2;  // kept: 0 and the last
  } else if (alpha && !keep_alpha) {
    colour_type = ColourType::Rgb, pixel_bytes = 3, kept[1] = 1, kept[2] = 2;  // colour: the grey cases are above
  } else {
    static constexpr ColourType kColourType[] = {ColourType::Grey, ColourType::GreyAlpha, ColourType::Rgb,
                                                 ColourType::Rgba};
    colour_type = kColourType[channels - 1];
  }
  if (conversion == Conversion::Channels && pixel_bytes == channels) conversion = Conversion::None;
  const std::size_t row_texels = static_cast<std::size_t>(width), in_channels = static_cast<std::size_t>(channels);
  const std::size_t out_bytes = static_cast<std::size_t>(pixel_bytes);
  const auto row_of = [&](std::size_t y, std::uint8_t* scratch) -> const std::uint8_t* {
    const std::uint8_t* const row = texels.data() + y * row_texels * in_channels;
    switch (conversion) {
      case Conversion::None:
        return row;
      case Conversion::Channels:
        for (std::size_t x = 0; x < row_texels; ++x)
          for (std::size_t c = 0; c < out_bytes; ++c) scratch[x * out_bytes + c] = row[x * in_channels + kept[c]];
        return scratch;
      case Conversion::PaletteIndex: {
        // Neighbouring texels mostly repeat a colour: the last one's index is kept.
        std::uint32_t last_rgba = use.palette[0];
        std::uint8_t last_index = 0;
        for (std::size_t x = 0; x < row_texels; ++x) {
          const std::uint32_t rgba = packed_rgba(row + x * in_channels, channels);
          if (rgba != last_rgba) last_rgba = rgba, last_index = use.index_of(rgba);
          scratch[x] = last_index;
        }
        return scratch;
      }
    }
    return row;
  };
  // PNG spec 12.8: palette images compress best unfiltered. Of the five filters, Average left the
  // least for libdeflate to do on baked photographic maps, in bytes and in time (Avocado's base
  // colour at 4096², level 1: 7.81 MB in 168 ms, against Sub's 9.27 MB in 174, Up's 7.90 MB,
  // Paeth's 8.13 MB; at 2048²: 2.88 MB against 3.11 for Sub; bench/RESULTS.md, session 31).
  const RowFilter filter = colour_type == ColourType::Palette ? RowFilter::None : RowFilter::Average;

  FilteredPng png;
  png.head = png_head(width, height, colour_type, use.palette);
  filter_rows(png, row_of, static_cast<std::size_t>(width), static_cast<std::size_t>(height),
              static_cast<std::size_t>(pixel_bytes), filter, release);
  return png;
}

FilteredPng filter_palette_png(std::span<const std::uint8_t> indices, std::span<const std::uint32_t> palette, int width,
                               int height) {
  if (palette.empty() || palette.size() > 256 || width < 1 || height < 1 ||
      indices.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    throw std::runtime_error("PNG encoder: " + std::to_string(indices.size()) + " indices into " +
                             std::to_string(palette.size()) + " colours for " + std::to_string(width) + "x" +
                             std::to_string(height));
  FilteredPng png;
  png.head = png_head(width, height, ColourType::Palette, palette);
  const std::size_t row_bytes = static_cast<std::size_t>(width);
  filter_rows(
      png, [&](std::size_t y, std::uint8_t*) { return indices.data() + y * row_bytes; }, row_bytes,
      static_cast<std::size_t>(height), 1, RowFilter::None, nullptr);
  return png;
}

// The IDAT chunks: the filtered rows as one zlib stream (RFC 1950), compressed whole by
// libdeflate, at level 1 about half the time of zlib's fastest (run-length) deflate for a few
// percent more bytes (Avocado's maps at 4096²: 277 against 517 ms of CPU; bench/RESULTS.md,
// session 29). Its streams cannot be cut into pieces that join, so an image deflates on the
// calling thread; the output is not zeroed (its pages are touched only as far as the stream goes).
// Rows of at most kSmallPngRows bytes (a grey or palette map of up to 255², an RGB one of up to
// 147²) take at least level 9: it costs them about a millisecond and saves 5-15% (bench/RESULTS.md,
// session 33). Above, level 9 costs 20-50 ns a byte more than level 1: VC's 256² palette maps
// took 50 ms more CPU, so they stay at the level asked.
constexpr std::size_t kSmallPngRows = std::size_t{1} << 16;
constexpr int kSmallPngLevel = 9;
Bytes deflate_png(FilteredPng&& filtered, int compression_level) {
  if (filtered.size <= kSmallPngRows) compression_level = std::max(compression_level, kSmallPngLevel);
  const std::unique_ptr<libdeflate_compressor, decltype(&libdeflate_free_compressor)> compressor(
      libdeflate_alloc_compressor(compression_level), &libdeflate_free_compressor);
  if (!compressor)
    throw std::runtime_error("PNG encoder: libdeflate refused compression level " + std::to_string(compression_level));
  const std::size_t bound = libdeflate_zlib_compress_bound(compressor.get(), filtered.size);
  const auto stream = std::make_unique_for_overwrite<std::uint8_t[]>(bound);
  advise_huge_pages(stream.get(), bound);
  const std::size_t length =
      libdeflate_zlib_compress(compressor.get(), filtered.rows.get(), filtered.size, stream.get(), bound);
  if (length == 0) throw std::runtime_error("PNG encoder: the compressed image overran libdeflate's bound");
  filtered.rows.reset();  // read no more: not held while the file is written
  Bytes png = std::move(filtered.head);
  append_image_data(png, std::span<const std::uint8_t>(stream.get(), length));
  return png;
}

std::optional<std::vector<std::uint32_t>> png_palette(std::span<const std::uint8_t> png) {
  // Read as the decoder reads it (libspng: IHDR, and PLTE and tRNS before the image data, each
  // chunk's CRC checked), so the colours are the ones a decode of the file expands its indices to.
  Context ctx(spng_ctx_new(0), &spng_ctx_free);
  if (!ctx) throw std::bad_alloc();
  spng_ihdr header{};
  spng_plte plte{};
  spng_trns transparency{};
  if (spng_set_chunk_limits(ctx.get(), kChunkLimit, kChunkLimit) != 0 ||
      spng_set_png_buffer(ctx.get(), png.data(), png.size()) != 0 || spng_get_ihdr(ctx.get(), &header) != 0 ||
      header.color_type != SPNG_COLOR_TYPE_INDEXED || spng_get_plte(ctx.get(), &plte) != 0)
    return std::nullopt;
  const int trns = spng_get_trns(ctx.get(), &transparency);
  if (trns != 0 && trns != SPNG_ECHUNKAVAIL) return std::nullopt;
  std::vector<std::uint32_t> palette(plte.n_entries);
  for (std::uint32_t i = 0; i < plte.n_entries; ++i) {
    const std::uint8_t colour[4] = {
        plte.entries[i].red, plte.entries[i].green, plte.entries[i].blue,
        trns == 0 && i < transparency.n_type3_entries ? transparency.type3_alpha[i] : std::uint8_t{255}};
    palette[i] = packed_rgba(colour, 4);
  }
  return palette;
}

std::optional<Bytes> png_with_palette(std::span<const std::uint8_t> png, std::span<const std::uint32_t> palette) {
  const std::optional<std::vector<std::uint32_t>> old_palette = png_palette(png);
  if (!old_palette || old_palette->size() != palette.size()) return std::nullopt;
  std::vector<std::uint8_t> joined;
  const std::span<const std::uint8_t> stream = image_data(png, joined);
  if (stream.empty()) return std::nullopt;
  // The signature and IHDR as they are (libspng read IHDR there: first, 13 bytes of data), the new
  // PLTE and tRNS, the image data. Nothing else: the colour-space and other ancillary chunks
  // described the old colours, and a baked map carries none (glTF reads base colour as sRGB).
  constexpr std::size_t kHeadBytes = sizeof kSignature + 12 + 13;
  Bytes out(png.begin(), png.begin() + kHeadBytes);
  append_palette(out, palette);
  append_image_data(out, stream);
  return out;
}

}  // namespace gltf_pbr::codecs
