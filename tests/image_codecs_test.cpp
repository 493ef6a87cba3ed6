// The lean PNG and JPEG codecs (libspng, TurboJPEG) read every image as OpenImageIO, the library
// they replace on the hot path, reads it: the shared assets' textures, and constructed odd ones
// (16-bit, grey, grey + alpha, palette with transparency, an ICC profile, progressive and grey
// JPEG, an Exif orientation that glTF says to ignore).
#include <gtest/gtest.h>
#include <turbojpeg.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/asset.hpp"
#include "core/codecs.hpp"
#include "core/image.hpp"
#include "test_support.hpp"

namespace gltf_pbr {
namespace {

// Texel i as RGBA in [0, 1], as glTF samples any layout: grey repeats, a missing alpha is 1.
std::array<float, 4> rgba(const Pixels& p, size_t i) {
  const size_t n = static_cast<size_t>(p.channels), at = i * n;
  const float grey = p.value(at);
  const bool colour = n >= 3, alpha = n == 2 || n == 4;
  return {grey, colour ? p.value(at + 1) : grey, colour ? p.value(at + 2) : grey, alpha ? p.value(at + n - 1) : 1.0f};
}

// Ours against OpenImageIO's decode of the same bytes: the same size, and every channel of every
// texel within `tolerance` (in units of the stored precision's steps).
void expect_decoded_as_openimageio_does(std::span<const std::uint8_t> encoded, const std::string& what,
                                        float tolerance_steps) {
  const Pixels ours = decode_image(encoded, what);
  const Pixels reference = decode_image_with_openimageio(encoded);
  ASSERT_EQ(ours.width, reference.width) << what;
  ASSERT_EQ(ours.height, reference.height) << what;
  EXPECT_EQ(ours.bits, reference.bits) << what;
  const float step = 1.0f / (ours.bits == 16 ? 65535.0f : 255.0f);
  float worst = 0.0f;
  const size_t texels = static_cast<size_t>(ours.width) * static_cast<size_t>(ours.height);
  for (size_t i = 0; i < texels; ++i) {
    const auto a = rgba(ours, i), b = rgba(reference, i);
    for (int c = 0; c < 4; ++c)
      worst = std::max(worst, std::abs(a[static_cast<size_t>(c)] - b[static_cast<size_t>(c)]));
  }
  EXPECT_LE(worst, tolerance_steps * step + 1e-7f) << what << ": worst difference " << worst / step << " steps";
}

// --- Constructed PNGs: chunks written by hand (PNG spec 5.3), so any layout can be made. ---
void put32(Bytes& out, std::uint32_t v) {
  for (int k = 3; k >= 0; --k) out.push_back(static_cast<std::uint8_t>(v >> (8 * k)));
}
void add_chunk(Bytes& png, const char* type, const Bytes& data) {
  put32(png, static_cast<std::uint32_t>(data.size()));
  const size_t start = png.size();
  png.insert(png.end(), type, type + 4);
  png.insert(png.end(), data.begin(), data.end());
  put32(png, static_cast<std::uint32_t>(crc32(0, &png[start], static_cast<uInt>(png.size() - start))));
}
Bytes deflated(const Bytes& raw) {
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  Bytes out(size);
  EXPECT_EQ(compress(out.data(), &size, raw.data(), static_cast<uLong>(raw.size())), Z_OK);
  out.resize(size);
  return out;
}
// A PNG of `width` x `height` with IHDR colour type `type` and `depth`, rows given as bytes after
// their filter byte (0), and optional PLTE, tRNS and iCCP chunks.
Bytes make_png(int width, int height, int depth, int type, const std::function<Bytes(int y)>& row,
               const Bytes& palette = {}, const Bytes& transparency = {}, const Bytes& icc = {}) {
  Bytes png = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A};
  Bytes header;
  put32(header, static_cast<std::uint32_t>(width));
  put32(header, static_cast<std::uint32_t>(height));
  header.insert(header.end(), {static_cast<std::uint8_t>(depth), static_cast<std::uint8_t>(type), 0, 0, 0});
  add_chunk(png, "IHDR", header);
  if (!icc.empty()) {  // PNG spec 11.3.3.3: name, 0, compression method 0, zlib stream
    Bytes data = {'t', 'e', 's', 't', 0, 0};
    const Bytes profile = deflated(icc);
    data.insert(data.end(), profile.begin(), profile.end());
    add_chunk(png, "iCCP", data);
  }
  if (!palette.empty()) add_chunk(png, "PLTE", palette);
  if (!transparency.empty()) add_chunk(png, "tRNS", transparency);
  Bytes raw;
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);
    const Bytes r = row(y);
    raw.insert(raw.end(), r.begin(), r.end());
  }
  add_chunk(png, "IDAT", deflated(raw));
  add_chunk(png, "IEND", {});
  return png;
}
// A minimal ICC profile header (ICC.1:2010 7.2): size, device class 'mntr', colour space 'RGB ',
// PCS 'XYZ ', the 'acsp' signature, and no tags.
Bytes icc_profile() {
  Bytes p(132, 0);
  p[3] = 132;
  auto put = [&](size_t at, const char* four) {
    std::copy(four, four + 4, p.begin() + static_cast<std::ptrdiff_t>(at));
  };
  p[8] = 4;  // version 4.0
  put(12, "mntr"), put(16, "RGB "), put(20, "XYZ "), put(36, "acsp");
  return p;
}

constexpr int kW = 23, kH = 17;  // odd sizes: row padding and 4:2:0 edges

TEST(LeanCodecs, EveryPngAndJpegOfTheSharedAssetsDecodesAsOpenImageIoDecodesIt) {
  int images = 0;
  for (const auto& entry : fs::recursive_directory_iterator(test::assets_dir())) {
    const std::string extension = entry.path().extension().string();
    if (extension != ".png" && extension != ".jpg" && extension != ".jpeg") continue;
    const auto bytes = read_file(entry.path());
    ASSERT_TRUE(bytes) << entry.path();
    // PNG is lossless: equal. JPEG: both are libjpeg-turbo's islow IDCT and fancy upsampling.
    expect_decoded_as_openimageio_does(*bytes, entry.path().string(), extension == ".png" ? 0.0f : 1.0f);
    ++images;
  }
  EXPECT_GE(images, 30);
}

TEST(LeanCodecs, OddPngLayoutsDecodeAsOpenImageIoDecodesThem) {
  const auto byte = [](int x, int y, int c) { return static_cast<std::uint8_t>((x * 37 + y * 11 + c * 101) % 256); };
  // 16-bit RGB, big-endian samples.
  expect_decoded_as_openimageio_does(make_png(kW, kH, 16, 2,
                                              [&](int y) {
                                                Bytes r;
                                                for (int x = 0; x < kW; ++x)
                                                  for (int c = 0; c < 3; ++c)
                                                    r.insert(r.end(), {byte(x, y, c), byte(y, x, c)});
                                                return r;
                                              }),
                                     "16-bit RGB", 0.0f);
  // 16-bit grey + alpha.
  expect_decoded_as_openimageio_does(make_png(kW, kH, 16, 4,
                                              [&](int y) {
                                                Bytes r;
                                                for (int x = 0; x < kW; ++x)
                                                  r.insert(r.end(), {byte(x, y, 0), 7, byte(x, y, 3), 250});
                                                return r;
                                              }),
                                     "16-bit grey + alpha", 0.0f);
  // 8-bit grey, and grey + alpha.
  expect_decoded_as_openimageio_does(make_png(kW, kH, 8, 0,
                                              [&](int y) {
                                                Bytes r;
                                                for (int x = 0; x < kW; ++x) r.push_back(byte(x, y, 0));
                                                return r;
                                              }),
                                     "grey", 0.0f);
  expect_decoded_as_openimageio_does(make_png(kW, kH, 8, 4,
                                              [&](int y) {
                                                Bytes r;
                                                for (int x = 0; x < kW; ++x)
                                                  r.insert(r.end(), {byte(x, y, 0), byte(x, y, 1)});
                                                return r;
                                              }),
                                     "grey + alpha", 0.0f);
  // A palette of 5 colours, two of them partly transparent (tRNS), at 8 and 4 bits per index.
  const Bytes palette = {255, 0, 0, 0, 255, 0, 0, 0, 255, 20, 30, 40, 250, 240, 230};
  const Bytes transparency = {0, 128};
  expect_decoded_as_openimageio_does(make_png(
                                         kW, kH, 8, 3,
                                         [&](int y) {
                                           Bytes r;
                                           for (int x = 0; x < kW; ++x)
                                             r.push_back(static_cast<std::uint8_t>((x + y) % 5));
                                           return r;
                                         },
                                         palette, transparency),
                                     "palette + tRNS", 0.0f);
  expect_decoded_as_openimageio_does(make_png(
                                         kW, kH, 4, 3,
                                         [&](int y) {
                                           Bytes r((kW + 1) / 2, 0);
                                           for (int x = 0; x < kW; ++x)
                                             r[static_cast<size_t>(x / 2)] |=
                                                 static_cast<std::uint8_t>(((x * y) % 5) << (x % 2 ? 0 : 4));
                                           return r;
                                         },
                                         palette),
                                     "4-bit palette", 0.0f);
  // An ICC-tagged RGB PNG: the profile is metadata; the texels are read as stored.
  expect_decoded_as_openimageio_does(make_png(
                                         kW, kH, 8, 2,
                                         [&](int y) {
                                           Bytes r;
                                           for (int x = 0; x < kW; ++x)
                                             for (int c = 0; c < 3; ++c) r.push_back(byte(x, y, c));
                                           return r;
                                         },
                                         {}, {}, icc_profile()),
                                     "ICC-tagged RGB", 0.0f);
}

// A changed texel byte under an unchanged chunk CRC is refused, not read as other texels: the stream
// is stored (zlib level 0), so the change leaves it a valid stream that only the checksums (the
// chunk's CRC-32, the stream's Adler-32) can catch.
TEST(LeanCodecs, APngWhoseImageDataChangedUnderItsChunkCrcIsRefused) {
  constexpr int kSize = 16;
  Bytes raw;
  for (int y = 0; y < kSize; ++y) {
    raw.push_back(0);  // filter None
    for (int x = 0; x < kSize * 3; ++x) raw.push_back(static_cast<std::uint8_t>(x * 5 + y));
  }
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  Bytes stored(size);
  ASSERT_EQ(compress2(stored.data(), &size, raw.data(), static_cast<uLong>(raw.size()), 0), Z_OK);
  stored.resize(size);
  Bytes png = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A}, header;
  put32(header, kSize), put32(header, kSize);
  header.insert(header.end(), {8, 2, 0, 0, 0});  // 8-bit RGB
  add_chunk(png, "IHDR", header);
  const size_t idat_data = png.size() + 8;
  add_chunk(png, "IDAT", stored);
  add_chunk(png, "IEND", {});
  ASSERT_EQ(decode_image(png, "as written").bytes[10], raw[1 + 10]);
  // zlib header (2 bytes) and stored block header (5): the texel bytes follow.
  Bytes changed = png;
  changed[idat_data + 7 + 1 + 10] ^= 0x10;  // row 0's filter byte, then its byte 10
  EXPECT_THROW(decode_image(changed, "changed"), std::runtime_error);
}

// A JPEG from TurboJPEG with the given flags and subsampling.
Bytes make_jpeg(int channels, int subsampling, int flags) {
  Bytes texels;
  for (int y = 0; y < kH; ++y)
    for (int x = 0; x < kW; ++x)
      for (int c = 0; c < channels; ++c) texels.push_back(static_cast<std::uint8_t>((x * 29 + y * 13 + c * 80) % 256));
  std::unique_ptr<void, decltype(&tjDestroy)> handle(tjInitCompress(), &tjDestroy);
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  EXPECT_EQ(tjCompress2(handle.get(), texels.data(), kW, 0, kH, channels == 1 ? TJPF_GRAY : TJPF_RGB, &buffer, &size,
                        subsampling, 85, flags),
            0);
  Bytes jpeg(buffer, buffer + size);
  tjFree(buffer);
  return jpeg;
}

TEST(LeanCodecs, ProgressiveGreyAndExifOrientedJpegsDecodeAsOpenImageIoDecodesThem) {
  expect_decoded_as_openimageio_does(make_jpeg(3, TJSAMP_420, TJFLAG_PROGRESSIVE), "progressive 4:2:0", 1.0f);
  expect_decoded_as_openimageio_does(make_jpeg(3, TJSAMP_444, 0), "baseline 4:4:4", 1.0f);
  expect_decoded_as_openimageio_does(make_jpeg(1, TJSAMP_GRAY, 0), "grey", 1.0f);
  // Exif orientation 6 ("rotate 90°") in an APP1 segment after SOI: glTF 2.0 section 3.8.4 says
  // texels are read as stored, so the size stays 23 x 17 and nothing turns.
  Bytes exif = {0xFF, 0xE1, 0, 0, 'E', 'x', 'i', 'f', 0, 0, 'M', 'M', 0, 42, 0, 0, 0, 8,  // TIFF header
                0,    1,                                                                  // one IFD entry
                0x01, 0x12, 0, 3, 0,   0,   0,   1,   0, 6, 0,   0,                       // Orientation = 6
                0,    0,    0, 0};                                                        // no next IFD
  exif[3] = static_cast<std::uint8_t>(exif.size() - 2);
  Bytes oriented = make_jpeg(3, TJSAMP_420, 0);
  oriented.insert(oriented.begin() + 2, exif.begin(), exif.end());
  const Pixels decoded = decode_image(oriented, "Exif");
  EXPECT_EQ(decoded.width, kW);
  EXPECT_EQ(decoded.height, kH);
  expect_decoded_as_openimageio_does(oriented, "Exif orientation 6", 1.0f);
}

// A PNG's chunks (PNG spec 5.3), each CRC checked here with zlib, apart from the decoders.
struct Chunk {
  std::string type;
  Bytes data;
};
std::vector<Chunk> chunks_with_correct_crcs(const Bytes& png) {
  std::vector<Chunk> chunks;
  const auto be32 = [&](size_t i) {
    return std::uint32_t{png[i]} << 24 | std::uint32_t{png[i + 1]} << 16 | std::uint32_t{png[i + 2]} << 8 | png[i + 3];
  };
  size_t at = 8;
  for (; at + 12 <= png.size(); at += 12 + be32(at)) {
    const std::uint32_t length = be32(at);
    EXPECT_LE(at + 12 + length, png.size()) << "chunk at byte " << at << " runs past the end";
    if (at + 12 + length > png.size()) break;
    const auto begin = png.begin() + static_cast<std::ptrdiff_t>(at);
    chunks.push_back({std::string(begin + 4, begin + 8), Bytes(begin + 8, begin + 8 + length)});
    EXPECT_EQ(be32(at + 8 + length), crc32(0, &png[at + 4], 4 + length)) << chunks.back().type << " at byte " << at;
  }
  EXPECT_EQ(at, png.size()) << "bytes after the last whole chunk";
  return chunks;
}

// The encoder converts and filters an image's rows in parts on the thread pool, then deflates them
// whole with libdeflate and writes the stream in IDAT chunks of at most 1 MiB, each with its own
// CRC (core/png.cpp). zlib, another library than the writer's, inflates the joined IDAT data here
// (checking the Adler-32), and both decoders must read every texel back exactly: every colour
// type, in several parts with a short last one, at levels 0 (stored: several chunks), 1 (the
// default), 6 and 9.
TEST(LeanCodecs, APngFilteredInPartsAndDeflatedWholeReadsBackExactlyInBothDecoders) {
  constexpr int kWidth = 1031, kHeight = 1100;  // a part is ~1 MiB: 2 parts a byte a texel, 5 at 4 bytes
  for (int channels = 1; channels <= 4; ++channels)
    for (bool few_colours : {false, true}) {
      std::vector<std::uint8_t> texels(static_cast<size_t>(kWidth) * kHeight * static_cast<size_t>(channels));
      for (size_t i = 0; i < texels.size(); ++i) {  // gradients with noise, or 200 colours (a palette)
        const size_t texel = i / static_cast<size_t>(channels), channel = i % static_cast<size_t>(channels);
        const std::uint32_t noise = static_cast<std::uint32_t>((texel * 3 + channel) * 2654435761u) >> 28;
        texels[i] = few_colours ? static_cast<std::uint8_t>(texel / 97 % 200 + channel * 37)
                                : static_cast<std::uint8_t>(texel % kWidth / 5 * (channel + 1) + noise);
      }
      const Pixels original{kWidth, kHeight, channels, 8, TexelBytes(texels.begin(), texels.end()), {}, {}};
      for (int level : {0, 1, 6, 9}) {
        const Bytes png = encode_png(texels, kWidth, kHeight, channels, level);
        const std::string what = std::to_string(channels) + " channels" + (few_colours ? ", few colours" : "") +
                                 ", level " + std::to_string(level);
        const std::vector<Chunk> chunks = chunks_with_correct_crcs(png);
        ASSERT_GE(chunks.size(), 3u) << what;
        EXPECT_EQ(chunks.back().type, "IEND") << what;
        Bytes stream;
        int idat_chunks = 0;
        for (const Chunk& chunk : chunks)
          if (chunk.type == "IDAT") stream.insert(stream.end(), chunk.data.begin(), chunk.data.end()), ++idat_chunks;
        EXPECT_EQ(idat_chunks, static_cast<int>((stream.size() + (1u << 20) - 1) >> 20)) << what << ": 1 MiB chunks";
        if (level == 0) {
          EXPECT_GE(idat_chunks, 2) << what;  // stored: more than 1 MiB
        }
        const int colour_type = png[25], pixel_bytes = colour_type == 0 || colour_type == 3 ? 1
                                                       : colour_type == 4                   ? 2
                                                       : colour_type == 2                   ? 3
                                                                                            : 4;
        Bytes filtered(static_cast<size_t>(kHeight) * (1 + static_cast<size_t>(kWidth) * pixel_bytes));
        uLongf filtered_size = filtered.size();
        ASSERT_EQ(uncompress(filtered.data(), &filtered_size, stream.data(), stream.size()), Z_OK)
            << what << ": one zlib stream, Adler-32 included";
        EXPECT_EQ(filtered_size, filtered.size()) << what;
        const Pixels decoded = decode_image(png, what);
        ASSERT_EQ(decoded.width, kWidth) << what;
        ASSERT_EQ(decoded.height, kHeight) << what;
        for (size_t i = 0; i < static_cast<size_t>(kWidth) * kHeight; ++i)
          ASSERT_EQ(rgba(decoded, i), rgba(original, i)) << what << ", texel " << i;
        expect_decoded_as_openimageio_does(png, what, 0.0f);
      }
    }
}

// An image whose filtered rows fit in 64 KiB deflates at level 9 whatever level was asked (it costs
// about a millisecond there); a larger one takes the level asked.
TEST(LeanCodecs, ASmallPngTakesTheSmallestLevelAndALargeOneTheLevelAsked) {
  const auto grey_ramp = [](int side) {
    std::vector<std::uint8_t> texels(static_cast<size_t>(side) * static_cast<size_t>(side));
    for (size_t i = 0; i < texels.size(); ++i)
      texels[i] = static_cast<std::uint8_t>(i % static_cast<size_t>(side) / 3 + (i * 2654435761u >> 29));
    return texels;
  };
  const std::vector<std::uint8_t> small = grey_ramp(200), large = grey_ramp(400);  // 40,200 and 160,400 row bytes
  const Bytes small_fast = encode_png(small, 200, 200, 1, 1), small_stored = encode_png(small, 200, 200, 1, 0);
  EXPECT_EQ(small_fast, encode_png(small, 200, 200, 1, 9));
  EXPECT_EQ(small_stored, small_fast);
  EXPECT_LT(small_fast.size(), small.size());
  const Bytes large_fast = encode_png(large, 400, 400, 1, 1), large_smallest = encode_png(large, 400, 400, 1, 9);
  EXPECT_GT(large_fast.size(), large_smallest.size());
  const Pixels decoded = decode_image(small_fast, "small");
  EXPECT_TRUE(std::equal(small.begin(), small.end(), decoded.bytes.begin(), decoded.bytes.end()));
}

// The run's decoded images: a map the conversion made and then did not write is forgotten (the
// preview would hold it to the end), but pixels get() has handed out stay while the object lives.
TEST(DecodedImages, ForgetGivesBackWhatWasKeptButNotWhatGetHandedOut) {
  DecodedImages images;
  const Bytes made = encode_png(std::vector<std::uint8_t>(64 * 64, 7), 64, 64, 1, 1);
  const ImageContentKey made_key = image_content_key(made);
  images.keep(made_key, std::make_shared<Pixels>(decode_image(made, "made")));
  ASSERT_NE(images.find(made_key), nullptr);
  images.forget(made_key);
  EXPECT_EQ(images.find(made_key), nullptr);

  const Asset duck = load_asset(test::model_folder("Duck") / "Duck.gltf");
  const Pixels& read = images.get(duck, 0);
  const ImageContentKey read_key = image_content_key(encoded_image_bytes(duck, 0));
  images.forget(read_key);
  EXPECT_EQ(images.find(read_key).get(), &read);
}

// Rows stored in another form than given (opaque RGBA as RGB, grey RGB as grey) are converted part
// by part on the pool, each part converting its row above for the Average filter as well: every
// texel reads back exactly, across the parts' seams.
TEST(LeanCodecs, RowsConvertedAndFilteredInPartsReadBackExactly) {
  constexpr int kWidth = 1031, kHeight = 1100;  // RGB: 339 rows a part, 4 parts; grey: 2 parts
  for (int channels : {4, 3}) {
    const size_t count = static_cast<size_t>(kWidth) * kHeight, n = static_cast<size_t>(channels);
    std::vector<std::uint8_t> texels(count * n);
    for (size_t t = 0; t < count; ++t)
      for (size_t c = 0; c < n; ++c) {  // opaque colours with noise (far more than 256), or greys
        const size_t channel = channels == 4 ? c : 0;
        const std::uint32_t noise = static_cast<std::uint32_t>((t * 3 + channel) * 2654435761u) >> 28;
        texels[t * n + c] = c == 3 ? 255 : static_cast<std::uint8_t>(t % kWidth / 5 * (channel + 1) + noise);
      }
    const std::string what = channels == 4 ? "opaque RGBA, stored as RGB" : "grey RGB, stored as grey";
    const Bytes png = encode_png(texels, kWidth, kHeight, channels, 1);
    ASSERT_GT(png.size(), 26u) << what;
    EXPECT_EQ(png[25], channels == 4 ? 2 : 0) << what << ": IHDR colour type";
    const Pixels original{kWidth, kHeight, channels, 8, TexelBytes(texels.begin(), texels.end()), {}, {}};
    const Pixels decoded = decode_image(png, what);
    ASSERT_EQ(decoded.width, kWidth) << what;
    ASSERT_EQ(decoded.height, kHeight) << what;
    for (size_t i = 0; i < count; ++i) ASSERT_EQ(rgba(decoded, i), rgba(original, i)) << what << ", texel " << i;
  }
}

// --- PNG image data inflated by libdeflate and reconstructed by our code (core/png.cpp) ---

// Rows filtered by PNG spec 9.2-9.4, written here from the spec apart from the decoder: row y with
// filter type `type_of(y)`, `bpp` bytes a pixel, each row's type byte first.
Bytes filtered_rows(const Bytes& texels, size_t row_bytes, size_t bpp, const std::function<int(size_t)>& type_of) {
  Bytes out;
  const size_t height = texels.size() / row_bytes;
  for (size_t y = 0; y < height; ++y) {
    const int type = type_of(y);
    out.push_back(static_cast<std::uint8_t>(type));
    for (size_t i = 0; i < row_bytes; ++i) {
      const auto at = [&](size_t row, size_t column) { return int{texels[row * row_bytes + column]}; };
      const int a = i >= bpp ? at(y, i - bpp) : 0, b = y > 0 ? at(y - 1, i) : 0,
                c = i >= bpp && y > 0 ? at(y - 1, i - bpp) : 0;
      const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
      const int predictor[] = {0, a, b, (a + b) / 2, pa <= pb && pa <= pc ? a : pb <= pc ? b : c};
      out.push_back(static_cast<std::uint8_t>(at(y, i) - predictor[type]));
    }
  }
  return out;
}

// A PNG of the given filtered rows, their zlib stream cut into IDAT chunks of `chunk_bytes`.
Bytes png_of_filtered_rows(int width, int height, int colour_type, const Bytes& filtered, size_t chunk_bytes) {
  Bytes png = {0x89, 'P', 'N', 'G', 0x0D, 0x0A, 0x1A, 0x0A}, header;
  put32(header, static_cast<std::uint32_t>(width)), put32(header, static_cast<std::uint32_t>(height));
  header.insert(header.end(), {8, static_cast<std::uint8_t>(colour_type), 0, 0, 0});
  add_chunk(png, "IHDR", header);
  const Bytes stream = deflated(filtered);
  for (size_t at = 0; at < stream.size(); at += chunk_bytes)
    add_chunk(png, "IDAT",
              Bytes(stream.begin() + static_cast<std::ptrdiff_t>(at),
                    stream.begin() + static_cast<std::ptrdiff_t>(std::min(stream.size(), at + chunk_bytes))));
  add_chunk(png, "IEND", {});
  return png;
}

// Every filter type, alone and mixed row by row, at every 8-bit layout the libdeflate path reads
// (grey, grey + alpha, RGB, RGBA), in one IDAT chunk and in many, at widths of one pixel and more:
// the texels as filtered, equal to libspng's own decode and to OpenImageIO's.
TEST(LeanCodecs, PngRowsOfEveryFilterTypeReadBackExactlyThroughLibdeflate) {
  constexpr int kColourType[] = {0, 4, 2, 6};
  for (size_t bpp = 1; bpp <= 4; ++bpp)
    for (int width : {1, 2, kW})
      for (int filter = 0; filter <= 5; ++filter) {  // 5: each row another type
        const size_t row_bytes = static_cast<size_t>(width) * bpp;
        Bytes texels(row_bytes * kH);
        for (size_t i = 0; i < texels.size(); ++i)  // noise over a gradient: no filter predicts it exactly
          texels[i] = static_cast<std::uint8_t>(i * 7 + (static_cast<std::uint32_t>(i * 2654435761u) >> 27));
        const Bytes filtered = filtered_rows(
            texels, row_bytes, bpp, [&](size_t y) { return filter < 5 ? filter : static_cast<int>((y * 3 + 1) % 5); });
        for (size_t chunk_bytes : {size_t{1} << 20, size_t{7}}) {
          const Bytes png = png_of_filtered_rows(width, kH, kColourType[bpp - 1], filtered, chunk_bytes);
          const std::string what = std::to_string(bpp) + " bytes a pixel, width " + std::to_string(width) +
                                   ", filter " + std::to_string(filter) + ", IDAT chunks of " +
                                   std::to_string(chunk_bytes) + " bytes";
          const long inflated = work_counters().png_streams_inflated;
          const Pixels ours = codecs::decode_png(png, ~std::uint64_t{0});
          EXPECT_EQ(work_counters().png_streams_inflated, inflated + 1) << what << ": not read by libspng";
          ASSERT_EQ(ours.channels, static_cast<int>(bpp)) << what;
          ASSERT_EQ(ours.bytes.size(), texels.size()) << what;
          EXPECT_TRUE(std::equal(texels.begin(), texels.end(), ours.bytes.begin())) << what;
          const Pixels reference = codecs::decode_png(png, ~std::uint64_t{0}, codecs::PngInflater::Libspng);
          EXPECT_TRUE(std::equal(reference.bytes.begin(), reference.bytes.end(), ours.bytes.begin(), ours.bytes.end()))
              << what;
          expect_decoded_as_openimageio_does(png, what, 0.0f);
        }
      }
}

// The libdeflate path decides nothing that libspng would decide otherwise: a file it refuses goes
// to libspng. Each damaged PNG below (cut short anywhere, any byte changed, a chunk dropped, bytes
// added) is refused by both paths or read by both as the same texels; and the libdeflate path
// does refuse a changed stream whose chunk CRC was made to match (the Adler-32 catches it).
TEST(LeanCodecs, ADamagedPngIsReadOrRefusedAsLibspngAloneReadsOrRefusesIt) {
  Bytes texels(static_cast<size_t>(kW) * 3 * kH);
  for (size_t i = 0; i < texels.size(); ++i) texels[i] = static_cast<std::uint8_t>(i * 13 % 251);
  const Bytes png = png_of_filtered_rows(
      kW, kH, 2, filtered_rows(texels, kW * 3, 3, [](size_t y) { return static_cast<int>(y % 5); }), 64);
  const auto outcome = [](const Bytes& bytes, codecs::PngInflater inflater) -> std::optional<TexelBytes> {
    try {
      return codecs::decode_png(bytes, kDefaultMaxImagePixels, inflater).bytes;
    } catch (const std::runtime_error&) {
      return std::nullopt;
    }
  };
  int read = 0, refused = 0;
  const auto expect_same_outcome = [&](const Bytes& damaged, const std::string& what) {
    const auto ours = outcome(damaged, codecs::PngInflater::Libdeflate);
    EXPECT_EQ(ours, outcome(damaged, codecs::PngInflater::Libspng)) << what;
    ++(ours ? read : refused);
  };
  for (size_t length = 0; length < png.size(); ++length)
    expect_same_outcome(Bytes(png.begin(), png.begin() + static_cast<std::ptrdiff_t>(length)),
                        "cut to " + std::to_string(length) + " bytes");
  for (size_t at = 8; at < png.size(); ++at) {
    Bytes changed = png;
    changed[at] ^= 0x5A;
    expect_same_outcome(changed, "byte " + std::to_string(at) + " changed");
  }
  const std::vector<Chunk> chunks = chunks_with_correct_crcs(png);
  const auto rebuilt = [&](const std::function<void(Bytes&, const Chunk&)>& add) {
    Bytes out(png.begin(), png.begin() + 8);
    for (const Chunk& chunk : chunks) add(out, chunk);
    return out;
  };
  expect_same_outcome(rebuilt([](Bytes& out, const Chunk& c) {
                        if (c.type != "IEND") add_chunk(out, c.type.c_str(), c.data);
                      }),
                      "no IEND");
  Bytes trailing = png;
  trailing.insert(trailing.end(), {1, 2, 3});
  expect_same_outcome(trailing, "bytes after IEND");
  bool first_idat = true;
  expect_same_outcome(rebuilt([&](Bytes& out, const Chunk& c) {  // an ancillary chunk between IDATs
                        add_chunk(out, c.type.c_str(), c.data);
                        if (c.type == "IDAT" && std::exchange(first_idat, false)) add_chunk(out, "tEXt", {'a', 0});
                      }),
                      "a chunk between IDAT chunks");
  // Chunks before the image data that libspng refuses under correct CRCs (PNG spec 5.4, 5.6,
  // 11.2.3): the libdeflate path does not read them, and must refuse the file all the same.
  const auto with_before_image_data = [&](const char* type, const Bytes& data) {
    bool added = false;
    return rebuilt([&](Bytes& out, const Chunk& c) {
      if (c.type == "IDAT" && !std::exchange(added, true)) add_chunk(out, type, data);
      add_chunk(out, c.type.c_str(), c.data);
    });
  };
  for (const auto& [damaged, what] : {std::pair{with_before_image_data("ABCD", {1}), "an unknown critical chunk"},
                                      std::pair{with_before_image_data("IHDR", chunks.front().data), "a second IHDR"},
                                      std::pair{with_before_image_data("PLTE", {1, 2, 3, 4}), "a PLTE of 4 bytes"}}) {
    EXPECT_FALSE(outcome(damaged, codecs::PngInflater::Libdeflate)) << what;
    expect_same_outcome(damaged, what);
  }
  // The stream re-made under correct CRCs: a row short, a row too many, a filter type of 5, data
  // after the stream's end, one texel byte changed (only the Adler-32 sees it).
  const auto with_stream = [&](const Bytes& stream) {
    Bytes out(png.begin(), png.begin() + 33);  // signature and IHDR
    add_chunk(out, "IDAT", stream);
    add_chunk(out, "IEND", {});
    return out;
  };
  const Bytes filtered = filtered_rows(texels, kW * 3, 3, [](size_t) { return 0; });
  const size_t row = 1 + kW * 3;
  expect_same_outcome(with_stream(deflated(Bytes(filtered.begin(), filtered.end() - static_cast<std::ptrdiff_t>(row)))),
                      "a row short");
  Bytes longer = filtered;
  longer.insert(longer.end(), filtered.begin(), filtered.begin() + static_cast<std::ptrdiff_t>(row));
  expect_same_outcome(with_stream(deflated(longer)), "a row too many");
  Bytes bad_type = filtered;
  bad_type[row * 3] = 5;
  expect_same_outcome(with_stream(deflated(bad_type)), "filter type 5");
  Bytes after = deflated(filtered);
  after.insert(after.end(), {9, 9, 9});
  expect_same_outcome(with_stream(after), "data after the stream");
  uLongf size = compressBound(static_cast<uLong>(filtered.size()));
  Bytes stored(size);
  ASSERT_EQ(compress2(stored.data(), &size, filtered.data(), static_cast<uLong>(filtered.size()), 0), Z_OK);
  stored.resize(size);
  stored[2 + 5 + 10] ^= 1;  // zlib header, stored block header, then row 0's bytes
  EXPECT_FALSE(outcome(with_stream(stored), codecs::PngInflater::Libdeflate)) << "a texel changed under the CRC";
  expect_same_outcome(with_stream(stored), "a texel changed under the CRC");
  EXPECT_GT(read, 0);
  EXPECT_GT(refused, 0);
}

}  // namespace
}  // namespace gltf_pbr

namespace gltf_pbr {
namespace {

// png_with_palette gives a palette PNG other colours: every texel reads as its index's new colour
// in both decoders, IHDR and the image data stay byte for byte, tRNS is written exactly when a
// colour is not opaque, and the ancillary chunks that described the old colours (an ICC profile
// here) or anything else (a text chunk) are left out, as a baked map has none.
TEST(PalettePng, ANewPaletteRecoloursEveryIndexKeepingTheHeaderAndImageData) {
  const Bytes plte = {10, 20, 30, 40, 50, 60, 70, 80, 90, 200, 210, 220};
  for (const int depth : {2, 8})
    for (const Bytes& transparency : {Bytes{}, Bytes{128, 0}}) {
      SCOPED_TRACE(testing::Message() << depth << "-bit, tRNS of " << transparency.size());
      Bytes png = make_png(
          kW, kH, depth, 3,
          [&](int y) {  // index (x + y) % 4, packed at `depth` bits
            Bytes row((static_cast<size_t>(kW) * static_cast<size_t>(depth) + 7) / 8, 0);
            for (int x = 0; x < kW; ++x) {
              const auto bit = static_cast<size_t>(x * depth);
              row[bit / 8] |= static_cast<std::uint8_t>(((x + y) % 4) << (8 - depth - bit % 8));
            }
            return row;
          },
          plte, transparency, icc_profile());
      png.resize(png.size() - 12);  // IEND out, a text chunk in, IEND back
      add_chunk(png, "tEXt", {'k', 0, 'v'});
      add_chunk(png, "IEND", {});

      const std::optional<std::vector<std::uint32_t>> palette = png_palette(png);
      ASSERT_TRUE(palette.has_value());
      ASSERT_EQ(palette->size(), 4u);
      EXPECT_EQ((*palette)[0], transparency.empty() ? 0xFF1E140Au : 0x801E140Au);
      EXPECT_EQ((*palette)[3], 0xFFDCD2C8u);  // beyond tRNS: opaque
      for (const bool opaque : {true, false}) {
        const std::vector<std::uint32_t> colours = {0xFF000001u, 0xFF00FF00u, opaque ? 0xFFFF0000u : 0x40FF0000u,
                                                    0xFF808080u};
        const std::optional<Bytes> recoloured = png_with_palette(png, colours);
        ASSERT_TRUE(recoloured.has_value());
        const auto critical = [](const Bytes& file, bool with_transparency) {
          std::vector<std::string> kept;
          for (const Chunk& c : chunks_with_correct_crcs(file))
            if (c.type != "PLTE" && (c.type != "tRNS" || with_transparency) && c.type != "iCCP" && c.type != "tEXt")
              kept.push_back(c.type + std::string(c.data.begin(), c.data.end()));
          return kept;
        };
        EXPECT_EQ(critical(*recoloured, false), critical(png, false));  // IHDR, IDAT, IEND
        std::vector<std::string> types;
        for (const Chunk& c : chunks_with_correct_crcs(*recoloured)) types.push_back(c.type);
        const std::vector<std::string> expected =
            opaque ? std::vector<std::string>{"IHDR", "PLTE", "IDAT", "IEND"}
                   : std::vector<std::string>{"IHDR", "PLTE", "tRNS", "IDAT", "IEND"};
        EXPECT_EQ(types, expected);
        for (const auto inflater : {codecs::PngInflater::Libdeflate, codecs::PngInflater::Libspng}) {
          const Pixels pixels = codecs::decode_png(*recoloured, ~std::uint64_t{0}, inflater);
          ASSERT_EQ(pixels.channels, opaque ? 3 : 4);
          for (int y = 0; y < kH; ++y)
            for (int x = 0; x < kW; ++x) {
              const std::uint32_t want = colours[static_cast<size_t>((x + y) % 4)];
              const size_t at =
                  (static_cast<size_t>(y) * kW + static_cast<size_t>(x)) * static_cast<size_t>(pixels.channels);
              for (int c = 0; c < pixels.channels; ++c)
                ASSERT_EQ(pixels.bytes[at + static_cast<size_t>(c)], static_cast<std::uint8_t>(want >> (8 * c)))
                    << x << "," << y << " channel " << c;
            }
        }
      }
      EXPECT_FALSE(png_with_palette(png, std::vector<std::uint32_t>(3, 0xFF000000u)).has_value());  // another length
    }
}

// The palette is read as the decoder reads it: none from another colour type or from a file cut
// before its image data; an odd tRNS (more alphas than colours, PNG spec 11.3.2.1) gives the
// alphas the decoded texels have.
TEST(PalettePng, ThePaletteIsTheOneTheDecoderExpandsIndicesTo) {
  const Bytes rgb = make_png(kW, kH, 8, 2, [](int) { return Bytes(static_cast<size_t>(kW) * 3, 7); });
  EXPECT_FALSE(png_palette(rgb).has_value());
  EXPECT_FALSE(png_with_palette(rgb, std::vector<std::uint32_t>(1, 0xFFFFFFFFu)).has_value());
  const Bytes indexed = make_png(kW, kH, 8, 3, [](int) { return Bytes(static_cast<size_t>(kW), 0); }, {1, 2, 3});
  ASSERT_TRUE(png_palette(indexed).has_value());
  for (size_t cut : {size_t{0}, size_t{7}, size_t{20}, size_t{40}})  // inside the signature, IHDR, PLTE
    EXPECT_FALSE(png_palette(std::span(indexed).first(cut)).has_value()) << cut;
  EXPECT_FALSE(png_palette(Bytes{1, 2, 3}).has_value());
  const Bytes long_trns =
      make_png(kW, kH, 8, 3, [](int) { return Bytes(static_cast<size_t>(kW), 0); }, {1, 2, 3}, {5, 6});
  const std::optional<std::vector<std::uint32_t>> palette = png_palette(long_trns);
  const Pixels decoded = codecs::decode_png(long_trns, ~std::uint64_t{0});
  ASSERT_TRUE(palette.has_value());
  ASSERT_EQ(palette->size(), 1u);
  const std::uint32_t alpha = decoded.channels == 4 ? decoded.bytes[3] : 255;  // libspng drops a tRNS it refuses
  EXPECT_EQ((*palette)[0], std::uint32_t{decoded.bytes[0]} | std::uint32_t{decoded.bytes[1]} << 8 |
                               std::uint32_t{decoded.bytes[2]} << 16 | alpha << 24);
}

}  // namespace
}  // namespace gltf_pbr
