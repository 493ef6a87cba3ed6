// PNG: decode through libspng with the tRNS chunk as alpha (as OpenImageIO did); encode in the
// smallest lossless colour type with the sub filter and zlib's run-length strategy, which DESIGN.md
// measured at a third of OpenImageIO's encode time for smaller files on baked maps. The encoder
// writes the chunks itself because its zlib stream is compressed in pieces on the thread pool:
// libspng deflates on one thread, and a large map's deflate then held a core alone.
#include <spng.h>
#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>
#include <vector>

#include "core/codecs.hpp"
#include "core/parallel.hpp"

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
// whether the alpha channel is all 255, and the distinct colours when there are at most 256, with
// the palette index of each.
class ColourUse {
 public:
  ColourUse(std::span<const std::uint8_t> texels, int channels) {
    const bool alpha = channels == 2 || channels == 4;
    bool few = true;
    const std::size_t count = texels.size() / static_cast<std::size_t>(channels);
    // Until nothing is left to learn: without an alpha channel, every texel is opaque.
    for (std::size_t i = 0; i < count && (few || grey || (alpha && opaque)); ++i) {
      const std::uint32_t rgba = packed_rgba(&texels[i * static_cast<std::size_t>(channels)], channels);
      const std::uint32_t r = rgba & 0xFF, g = rgba >> 8 & 0xFF, b = rgba >> 16 & 0xFF;
      grey = grey && r == g && g == b;
      opaque = opaque && rgba >> 24 == 0xFF;
      if (!few) continue;
      std::uint64_t& slot = slots_[slot_of(rgba)];
      if (slot != 0) continue;
      slot = static_cast<std::uint64_t>(palette.size()) << 33 | static_cast<std::uint64_t>(rgba) << 1 | 1;
      palette.push_back(rgba);
      few = palette.size() <= 256;
    }
    if (!few) palette.clear();
  }

  bool grey = true, opaque = true;
  std::vector<std::uint32_t> palette;  // RGBA packed, by first appearance; empty above 256 colours

  // The palette index of a colour that occurs.
  std::uint8_t index_of(std::uint32_t rgba) const { return static_cast<std::uint8_t>(slots_[slot_of(rgba)] >> 33); }

 private:
  // Open addressing over 1024 slots holds 256 colours with few collisions. A slot holds its
  // colour shifted up by one with the low bit set, so that 0 can mark it empty, and its index above.
  std::size_t slot_of(std::uint32_t rgba) const {
    const std::uint64_t key = static_cast<std::uint64_t>(rgba) << 1 | 1;
    std::size_t slot = (rgba * 2654435761u) >> 22;
    while (slots_[slot] != 0 && (slots_[slot] & 0x1FFFFFFFFull) != key) slot = (slot + 1) & 1023;
    return slot;
  }
  std::vector<std::uint64_t> slots_ = std::vector<std::uint64_t>(1024, 0);
};

// PNG colour types (PNG spec 11.2.2).
enum class ColourType : std::uint8_t { Grey = 0, Rgb = 2, Palette = 3, GreyAlpha = 4, Rgba = 6 };

constexpr std::uint8_t kSignature[] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};

void put_be32(std::uint8_t* out, std::uint32_t v) {
  out[0] = static_cast<std::uint8_t>(v >> 24), out[1] = static_cast<std::uint8_t>(v >> 16);
  out[2] = static_cast<std::uint8_t>(v >> 8), out[3] = static_cast<std::uint8_t>(v);
}

// A chunk (PNG spec 5.3): length, type, data, and the CRC-32 of type and data. The data may come
// in parts (zlib header, a piece, zlib trailer), written as one chunk.
void append_chunk(Bytes& png, const char (&type)[5], std::initializer_list<std::span<const std::uint8_t>> data) {
  std::size_t length = 0;
  for (std::span<const std::uint8_t> part : data) length += part.size();
  if (length > 0x7FFFFFFFu) throw std::runtime_error("PNG encoder: a chunk above 2^31 - 1 bytes");
  std::uint8_t head[8];
  put_be32(head, static_cast<std::uint32_t>(length));
  std::memcpy(head + 4, type, 4);
  png.insert(png.end(), head, head + 8);
  uLong crc = crc32(0, head + 4, 4);
  for (std::span<const std::uint8_t> part : data) {
    if (part.empty()) continue;  // crc32_z of a null pointer would restart the CRC
    png.insert(png.end(), part.begin(), part.end());
    crc = crc32_z(crc, part.data(), part.size());
  }
  std::uint8_t tail[4];
  put_be32(tail, static_cast<std::uint32_t>(crc));
  png.insert(png.end(), tail, tail + 4);
}

// The IDAT chunks: the filtered rows (PNG spec 7.3, 9) as one zlib stream (RFC 1950), compressed
// in pieces of rows on the thread pool, as pigz does: each piece is raw deflate that ends on a
// byte boundary (Z_SYNC_FLUSH) but the last (Z_FINISH), so the pieces concatenate into one
// stream, and the stream's Adler-32 is combined from the pieces'. A piece starts without the
// previous one's window; the run-length strategy only matches at distance 1, so that costs at
// most its first byte. Pieces are a fixed number of bytes, whatever the thread count, so an image
// encodes to the same bytes on every machine. One IDAT chunk a piece.
void append_image_data(Bytes& png, std::span<const std::uint8_t> image, std::size_t width, std::size_t height,
                       std::size_t pixel_bytes, bool sub_filter, int level) {
  constexpr std::size_t kPieceBytes = 1u << 20;
  const std::size_t row_bytes = width * pixel_bytes, filtered_row_bytes = 1 + row_bytes;
  if (filtered_row_bytes > std::numeric_limits<uInt>::max())  // zlib takes a row in one call
    throw std::runtime_error("PNG encoder: a row of " + std::to_string(row_bytes) + " bytes");
  const std::size_t rows_per_piece = std::max<std::size_t>(1, kPieceBytes / filtered_row_bytes);
  const std::size_t pieces = (height + rows_per_piece - 1) / rows_per_piece;
  struct Piece {
    Bytes deflated;
    uLong adler = 0;
    std::size_t length = 0;  // filtered bytes in
  };
  std::vector<Piece> out(pieces);
  parallel_dynamic(static_cast<std::int64_t>(pieces), [&](std::int64_t index) {
    const std::size_t p = static_cast<std::size_t>(index);
    const std::size_t first = p * rows_per_piece, end = std::min(height, first + rows_per_piece);
    z_stream z{};
    if (deflateInit2(&z, level, Z_DEFLATED, -15, 8, Z_RLE) != Z_OK)
      throw std::runtime_error("PNG encoder: zlib refused compression level " + std::to_string(level));
    const std::unique_ptr<z_stream, int (*)(z_stream*)> stream(&z, &deflateEnd);
    Piece& piece = out[p];
    piece.length = (end - first) * filtered_row_bytes;
    piece.adler = adler32(0, nullptr, 0);
    // Deflates the input given through a small buffer: the output grows as it comes, never zeroed.
    std::uint8_t buffer[1 << 16];
    const auto pump = [&](int flush) {
      for (;;) {
        z.next_out = buffer;
        z.avail_out = sizeof buffer;
        const int status = deflate(&z, flush);
        piece.deflated.insert(piece.deflated.end(), buffer, buffer + (sizeof buffer - z.avail_out));
        if (status == Z_STREAM_ERROR) throw std::runtime_error("PNG encoder: deflate failed");
        if (flush == Z_FINISH ? status == Z_STREAM_END : z.avail_in == 0 && z.avail_out != 0) return;
      }
    };
    std::vector<std::uint8_t> filtered(filtered_row_bytes);
    for (std::size_t y = first; y < end; ++y) {
      const std::uint8_t* row = image.data() + y * row_bytes;
      filtered[0] = sub_filter ? 1 : 0;  // filter type: Sub (each byte less the one a pixel before) or None
      std::uint8_t* const out_row = filtered.data() + 1;
      const std::size_t copied = sub_filter ? std::min(pixel_bytes, row_bytes) : row_bytes;
      std::memcpy(out_row, row, copied);
      for (std::size_t i = copied; i < row_bytes; ++i)
        out_row[i] = static_cast<std::uint8_t>(row[i] - row[i - pixel_bytes]);
      piece.adler = adler32_z(piece.adler, filtered.data(), filtered.size());
      z.next_in = filtered.data();
      z.avail_in = static_cast<uInt>(filtered.size());
      pump(y + 1 < end ? Z_NO_FLUSH : p + 1 < pieces ? Z_SYNC_FLUSH : Z_FINISH);
    }
  });
  // CMF 0x78: deflate with a 32 KiB window; FLG 0x01 makes CMF·256 + FLG a multiple of 31 (RFC 1950 2.2).
  static constexpr std::uint8_t kZlibHeader[] = {0x78, 0x01};
  uLong adler = adler32(0, nullptr, 0);
  for (std::size_t p = 0; p < pieces; ++p) {
    adler = adler32_combine(adler, out[p].adler, static_cast<z_off_t>(out[p].length));
    std::uint8_t trailer[4];
    put_be32(trailer, static_cast<std::uint32_t>(adler));
    const bool first = p == 0, last = p + 1 == pieces;
    append_chunk(png, "IDAT",
                 {first ? std::span<const std::uint8_t>(kZlibHeader) : std::span<const std::uint8_t>(), out[p].deflated,
                  last ? std::span<const std::uint8_t>(trailer) : std::span<const std::uint8_t>()});
    Bytes().swap(out[p].deflated);
  }
}
}  // namespace

Bytes encode_png(std::span<const std::uint8_t> texels, int width, int height, int channels, int compression_level) {
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
  const std::size_t count = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const bool colour = channels >= 3, alpha = channels == 2 || channels == 4;
  const bool keep_alpha = alpha && !use.opaque;
  std::vector<std::uint8_t> converted;
  auto gather = [&](int out_channels, auto&& write) {
    converted.resize(count * static_cast<std::size_t>(out_channels));
    for (std::size_t i = 0; i < count; ++i)
      write(&texels[i * static_cast<std::size_t>(channels)], &converted[i * static_cast<std::size_t>(out_channels)]);
  };
  std::span<const std::uint8_t> image = texels;
  ColourType colour_type;
  int pixel_bytes = channels;
  std::vector<std::uint8_t> plte, trns;  // PLTE and tRNS data of a palette image
  if (use.grey && !keep_alpha) {
    colour_type = ColourType::Grey, pixel_bytes = 1;
    if (channels != 1) gather(1, [](const std::uint8_t* in, std::uint8_t* out) { out[0] = in[0]; });
  } else if (!use.palette.empty() && (colour || keep_alpha)) {
    colour_type = ColourType::Palette, pixel_bytes = 1;
    for (const std::uint32_t rgba : use.palette) {
      plte.insert(plte.end(), {static_cast<std::uint8_t>(rgba), static_cast<std::uint8_t>(rgba >> 8),
                               static_cast<std::uint8_t>(rgba >> 16)});
      if (keep_alpha) trns.push_back(static_cast<std::uint8_t>(rgba >> 24));
    }
    // Neighbouring texels mostly repeat a colour: the last one's index is kept.
    std::uint32_t last_rgba = use.palette[0];
    std::uint8_t last_index = 0;
    gather(1, [&](const std::uint8_t* in, std::uint8_t* out) {
      const std::uint32_t rgba = packed_rgba(in, channels);
      if (rgba != last_rgba) last_rgba = rgba, last_index = use.index_of(rgba);
      out[0] = last_index;
    });
  } else if (use.grey) {
    colour_type = ColourType::GreyAlpha, pixel_bytes = 2;
    if (channels != 2)
      gather(2, [&](const std::uint8_t* in, std::uint8_t* out) { out[0] = in[0], out[1] = in[channels - 1]; });
  } else if (alpha && !keep_alpha) {
    colour_type = ColourType::Rgb, pixel_bytes = 3;  // colour: the grey cases are above
    gather(3, [](const std::uint8_t* in, std::uint8_t* out) { out[0] = in[0], out[1] = in[1], out[2] = in[2]; });
  } else {
    static constexpr ColourType kColourType[] = {ColourType::Grey, ColourType::GreyAlpha, ColourType::Rgb,
                                                 ColourType::Rgba};
    colour_type = kColourType[channels - 1];
  }
  if (!converted.empty()) image = converted;
  // PNG spec 12.8: palette images compress best unfiltered; the others with the sub filter.
  const bool sub_filter = colour_type != ColourType::Palette;

  // PNG spec 5.2-5.3 and 11.2: signature, IHDR, PLTE and tRNS, IDAT, IEND.
  Bytes png(kSignature, kSignature + sizeof kSignature);
  std::uint8_t ihdr[13] = {};
  put_be32(ihdr, static_cast<std::uint32_t>(width));
  put_be32(ihdr + 4, static_cast<std::uint32_t>(height));
  ihdr[8] = 8;  // bit depth; compression, filter and interlace methods 0
  ihdr[9] = static_cast<std::uint8_t>(colour_type);
  append_chunk(png, "IHDR", {ihdr});
  if (colour_type == ColourType::Palette) {
    append_chunk(png, "PLTE", {plte});
    if (!trns.empty()) append_chunk(png, "tRNS", {trns});
  }
  append_image_data(png, image, static_cast<std::size_t>(width), static_cast<std::size_t>(height),
                    static_cast<std::size_t>(pixel_bytes), sub_filter, compression_level);
  append_chunk(png, "IEND", {});
  return png;
}

}  // namespace gltf_pbr::codecs
