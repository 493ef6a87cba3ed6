// What a hostile file or an unlucky user meets: no file outside the asset is opened, no header can
// make us allocate what it claims, no terminal escape reaches a terminal, no output is lost or
// written twice, and every failure says what and why.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <csignal>
#include <functional>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <span>
#include <sstream>
#include <thread>

#include "converter/convert.hpp"
#include "core/asset.hpp"
#include "core/error.hpp"
#include "core/files.hpp"
#include "core/image.hpp"
#include "core/text.hpp"
#include "test_support.hpp"
#include "validators/validate.hpp"

namespace gltf_pbr {
namespace {

using test::copy_model;
using test::quoted;
using test::run_cli;
using test::ScratchDir;
using test::write_bytes;

Bytes bytes_of(const std::string& text) { return Bytes(text.begin(), text.end()); }

// A PNG whose IHDR claims width x height, with a valid CRC and a few bytes of (wrong) data.
Bytes png_claiming(std::uint32_t width, std::uint32_t height) {
  Bytes png = encode_png(std::vector<std::uint8_t>(4 * 4 * 3, 7), 4, 4, 3, 1);
  auto put32 = [&](std::size_t at, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) png[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (24 - 8 * i));
  };
  put32(16, width);  // IHDR data starts after the 8-byte signature, length and type
  put32(20, height);
  put32(29, static_cast<std::uint32_t>(crc32(0, png.data() + 12, 17)));  // over type + 13 data bytes
  return png;
}

TEST(ImageLimits, AHeaderClaimingMorePixelsThanTheLimitIsRefusedBeforeDecoding) {
  const Bytes bomb = png_claiming(60000, 60000);
  ASSERT_LT(bomb.size(), 200u);
  try {
    (void)decode_image(bomb, "/images/0");
    FAIL() << "a 60000x60000 header was decoded";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/images/0"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("60000x60000"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--max-image-pixels"), std::string::npos) << e.what();
  }
  // A limit of 15 pixels refuses the honest 4x4 image too; the default accepts it.
  const Bytes honest = encode_png(std::vector<std::uint8_t>(16 * 3, 7), 4, 4, 3, 1);
  set_max_image_pixels(15);
  EXPECT_THROW((void)decode_image(honest, "small"), std::runtime_error);
  set_max_image_pixels(kDefaultMaxImagePixels);
  EXPECT_EQ(decode_image(honest, "small").width, 4);
}

TEST(ImageLimits, ConvertAndValidateRefuseAnImageBombNamingItsPointer) {
  ScratchDir scratch;
  const fs::path gltf = copy_model("BoxTextured", scratch / "box");
  write_bytes(scratch / "box" / "CesiumLogoFlat.png", png_claiming(60000, 60000));
  const auto converted = run_cli("convert -q " + quoted(gltf) + " -o " + quoted(scratch / "out"), scratch);
  EXPECT_EQ(converted.exit_code, 1) << converted.err;
  EXPECT_NE(converted.err.find("/images/0"), std::string::npos) << converted.err;
  EXPECT_NE(converted.err.find("above the limit"), std::string::npos) << converted.err;
  const auto validated = run_cli("validate -f json " + quoted(gltf), scratch);
  EXPECT_NE(validated.out.find("IMAGE_UNDECODABLE"), std::string::npos) << validated.out;
  EXPECT_NE(validated.out.find("above the limit"), std::string::npos) << validated.out;
}

TEST(ImageLimits, AGifWhoseScreenIsAboveTheLimitIsRefusedBeforeItsReaderAllocatesIt) {
  // 42 bytes: a GIF89a logical screen of 40000 x 40000 (OpenImageIO's reader would allocate it on
  // open: 2.1 GB) around a 256 x 256 image.
  const Bytes gif = {0x47, 0x49, 0x46, 0x38, 0x39, 0x61, 0x40, 0x9c, 0x40, 0x9c, 0x80, 0x00, 0x00, 0x00,
                     0x00, 0xff, 0xff, 0xff, 0x21, 0xf9, 0x04, 0x01, 0x00, 0x00, 0x00, 0x00, 0x2c, 0x00,
                     0x00, 0x00, 0x00, 0x01, 0x00, 0x01, 0x00, 0x00, 0x02, 0x02, 0x44, 0x01, 0x00, 0x3b};
  try {
    (void)decode_image(gif, "screen.gif");
    FAIL() << "a 40000 x 40000 screen was decoded";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("above the limit"), std::string::npos) << e.what();
  }
}

TEST(CorruptImages, ATruncatedJpegOrPngIsAnErrorNotGreyTexels) {
  const Bytes jpeg = *read_file(test::model_folder("CesiumMan") / "CesiumMan.jpg");
  EXPECT_NO_THROW((void)decode_image(jpeg, "whole"));
  const Bytes cut_jpeg(jpeg.begin(), jpeg.begin() + static_cast<std::ptrdiff_t>(jpeg.size() / 2));
  EXPECT_THROW((void)decode_image(cut_jpeg, "cut jpeg"), std::runtime_error);
  const Bytes png = *read_file(test::model_folder("BoxTextured") / "CesiumLogoFlat.png");
  const Bytes cut_png(png.begin(), png.begin() + static_cast<std::ptrdiff_t>(png.size() / 2));
  EXPECT_THROW((void)decode_image(cut_png, "cut png"), std::runtime_error);
}

TEST(CorruptImages, AJpegWhoseFrameClaimsMoreThanItsScanHoldsIsAnError) {
  // The frame header's size doubled: the scan runs out of restart intervals, libjpeg warns "found
  // marker 0xd9 instead of RST" and would fill three quarters of the image with grey.
  Bytes jpeg = *read_file(test::model_folder("CesiumMan") / "CesiumMan.jpg");
  std::size_t frame = 2;
  while (frame + 9 < jpeg.size() && !(jpeg[frame] == 0xFF && (jpeg[frame + 1] == 0xC0 || jpeg[frame + 1] == 0xC2)))
    frame += 2 + static_cast<std::size_t>(jpeg[frame + 2] << 8 | jpeg[frame + 3]);  // marker segments up to the frame
  ASSERT_LT(frame + 9, jpeg.size());
  const int height = jpeg[frame + 5] << 8 | jpeg[frame + 6], width = jpeg[frame + 7] << 8 | jpeg[frame + 8];
  jpeg[frame + 5] = static_cast<std::uint8_t>((2 * height) >> 8);
  jpeg[frame + 6] = static_cast<std::uint8_t>(2 * height);
  jpeg[frame + 7] = static_cast<std::uint8_t>((2 * width) >> 8);
  jpeg[frame + 8] = static_cast<std::uint8_t>(2 * width);
  EXPECT_THROW((void)decode_image(jpeg, "lying frame"), std::runtime_error);
}

TEST(CorruptImages, AHarmlessJpegWarningStillDecodes) {
  // Bytes between the entropy-coded data and EOI: libjpeg warns "extraneous bytes before marker"
  // and decodes every texel; only warnings that mean lost data are errors.
  Bytes jpeg = *read_file(test::model_folder("CesiumMan") / "CesiumMan.jpg");
  ASSERT_EQ(jpeg[jpeg.size() - 2], 0xFF);
  ASSERT_EQ(jpeg[jpeg.size() - 1], 0xD9);
  jpeg.insert(jpeg.end() - 2, {0x00, 0x11, 0x22});
  EXPECT_NO_THROW((void)decode_image(jpeg, "extraneous bytes"));
}

TEST(ImageLimits, TwoTexturesThatBakeAboveTheLimitTogetherAreRefused) {
  // 512x1 and 1x512 images bake at 512x512: above a limit of 100000 pixels, though each is under it.
  auto png = [](int width, int height) {
    return encode_png(std::vector<std::uint8_t>(std::size_t(width * height * 4), 200), width, height, 4, 1);
  };
  ScratchDir scratch;
  const fs::path gltf = copy_model("BoxTextured", scratch / "box");
  write_bytes(scratch / "box" / "wide.png", png(512, 1));
  write_bytes(scratch / "box" / "tall.png", png(1, 512));
  auto document = nlohmann::json::parse(test::read_text(gltf));
  document["images"] = {{{"uri", "wide.png"}}, {{"uri", "tall.png"}}};
  document["textures"] = {{{"source", 0}}, {{"source", 1}}};
  auto& extension = document["materials"][0]["extensions"]["KHR_materials_pbrSpecularGlossiness"];
  extension["diffuseTexture"] = {{"index", 0}};
  extension["specularGlossinessTexture"] = {{"index", 1}};
  test::write_text(gltf, document.dump());
  const auto r =
      run_cli("convert --max-image-pixels 100000 " + quoted(gltf) + " -o " + quoted(scratch / "out"), scratch);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("/materials/0: its two textures bake at 512x512"), std::string::npos) << r.err;
}

TEST(CorruptImages, ConvertRefusesToBakeATruncatedJpegAndValidateReportsIt) {
  ScratchDir scratch;
  const fs::path gltf = copy_model("CesiumMan", scratch / "man");
  const Bytes jpeg = *read_file(scratch / "man" / "CesiumMan.jpg");
  write_bytes(scratch / "man" / "CesiumMan.jpg",
              Bytes(jpeg.begin(), jpeg.begin() + static_cast<std::ptrdiff_t>(jpeg.size() * 2 / 3)));
  const auto converted = run_cli("convert -q " + quoted(gltf) + " -o " + quoted(scratch / "out"), scratch);
  EXPECT_EQ(converted.exit_code, 1);
  EXPECT_NE(converted.err.find("/images/0"), std::string::npos) << converted.err;
  EXPECT_FALSE(fs::exists(scratch / "out"));
  const auto validated = run_cli("validate -f json " + quoted(gltf), scratch);
  EXPECT_NE(validated.out.find("IMAGE_UNDECODABLE"), std::string::npos) << validated.out;
}

// Texel i as RGBA, as every reader expands it (grey repeats, a missing alpha is opaque).
std::array<std::uint8_t, 4> rgba_at(std::span<const std::uint8_t> texels, int channels, std::size_t i) {
  const std::uint8_t* t = &texels[i * static_cast<std::size_t>(channels)];
  const bool colour = channels >= 3, alpha = channels == 2 || channels == 4;
  return {t[0], colour ? t[1] : t[0], colour ? t[2] : t[0], alpha ? t[channels - 1] : std::uint8_t{255}};
}

TEST(LeanCodecs, EveryChannelCountRoundTripsThroughPngExactly) {
  // The encoder may store fewer channels (a palette, grey); every texel reads back the same.
  for (int channels = 1; channels <= 4; ++channels) {
    std::vector<std::uint8_t> texels(static_cast<std::size_t>(37 * 11 * channels));
    for (std::size_t i = 0; i < texels.size(); ++i) texels[i] = static_cast<std::uint8_t>((i * 97 + 13) % 256);
    const Pixels decoded = decode_image(encode_png(texels, 37, 11, channels, 3), "round trip");
    EXPECT_EQ(decoded.width, 37);
    EXPECT_EQ(decoded.height, 11);
    for (std::size_t i = 0; i < 37 * 11; ++i)
      ASSERT_EQ(rgba_at(decoded.bytes, decoded.channels, i), rgba_at(texels, channels, i)) << channels << " channels";
  }
}

TEST(LeanCodecs, PngTakesTheSmallestLosslessFormAndReadsBackTheSameColours) {
  std::mt19937 random(5);
  constexpr int kWidth = 23, kHeight = 19;
  constexpr std::size_t kCount = kWidth * kHeight;
  enum : std::uint8_t { kGrey = 0, kRgb = 2, kIndexed = 3, kGreyAlpha = 4, kRgba = 6 };
  for (int channels = 1; channels <= 4; ++channels)
    for (int colours : {1, 2, 17, 256, 400})
      for (bool grey : {false, true})
        for (bool opaque : {false, true}) {
          const bool has_alpha = channels == 2 || channels == 4;
          if ((channels < 3 && !grey) || (!has_alpha && !opaque)) continue;
          std::vector<std::array<std::uint8_t, 4>> palette;
          for (int k = 0; k < colours; ++k) {
            const auto v = [&] { return static_cast<std::uint8_t>(random()); };
            const std::uint8_t r = v();
            palette.push_back({r, grey ? r : v(), grey ? r : v(), opaque ? std::uint8_t{255} : v()});
          }
          std::vector<std::uint8_t> texels;
          for (std::size_t i = 0; i < kCount; ++i) {
            const auto& c = palette[i < palette.size() ? i : random() % palette.size()];
            if (channels >= 3)
              texels.insert(texels.end(), {c[0], c[1], c[2]});
            else
              texels.push_back(c[0]);
            if (has_alpha) texels.push_back(c[3]);
          }
          const Bytes png = encode_png(texels, kWidth, kHeight, channels, 3);
          const Pixels decoded = decode_image(png, "round trip");
          const std::string what = std::to_string(channels) + " channels, " + std::to_string(colours) + " colours" +
                                   (grey ? ", grey" : "") + (opaque ? ", opaque" : "");
          ASSERT_EQ(decoded.width * decoded.height, static_cast<int>(kCount)) << what;
          for (std::size_t i = 0; i < kCount; ++i)
            ASSERT_EQ(rgba_at(decoded.bytes, decoded.channels, i), rgba_at(texels, channels, i))
                << what << ", texel " << i;
          // IHDR's colour type (PNG spec 11.2.2) sits at byte 25.
          const std::uint8_t type = png[25];
          const int distinct = std::min<int>(colours, static_cast<int>(kCount));
          const bool alpha_needed = has_alpha && !opaque;
          if (grey && !alpha_needed)
            EXPECT_EQ(type, kGrey) << what;
          else if (distinct <= 256)
            EXPECT_EQ(type, kIndexed) << what;
          else if (grey)
            EXPECT_EQ(type, kGreyAlpha) << what;
          else
            EXPECT_EQ(type, alpha_needed ? kRgba : kRgb) << what;
        }
}

TEST(LeanCodecs, APaletteHoldsAtMost256Colours) {
  for (int colours : {256, 257}) {
    std::vector<std::uint8_t> texels;
    for (int k = 0; k < 20 * 20; ++k) {
      const int c = k % colours;  // distinct for c < 512: (c mod 256, c / 256, 7)
      texels.insert(texels.end(), {static_cast<std::uint8_t>(c & 255), static_cast<std::uint8_t>(c >> 8), 7});
    }
    const Bytes png = encode_png(texels, 20, 20, 3, 3);
    EXPECT_EQ(png[25], colours == 256 ? 3 : 2) << colours << " colours";  // IHDR colour type
    const Pixels decoded = decode_image(png, "palette");
    EXPECT_TRUE(std::ranges::equal(decoded.bytes, texels)) << colours << " colours";
  }
}

TEST(LeanCodecs, JpegRoundTripStaysCloseAtHighQuality) {
  std::vector<std::uint8_t> texels(64 * 64 * 3);
  for (std::size_t i = 0; i < texels.size(); ++i) texels[i] = static_cast<std::uint8_t>(64 + (i / 3 % 64) * 2);
  const Pixels decoded = decode_image(encode_jpeg(texels, 64, 64, 3, 95), "jpeg");
  ASSERT_EQ(decoded.bytes.size(), texels.size());
  double worst = 0;
  for (std::size_t i = 0; i < texels.size(); ++i)
    worst = std::max(worst, std::abs(double(decoded.bytes[i]) - texels[i]));
  EXPECT_LT(worst, 8);
}

// A folder holding the asset, beside a secret it must never read.
struct OutsideUriCase {
  fs::path gltf;
  std::string secret = "SECRET-0123456789-SECRET-0123456789";
};

OutsideUriCase asset_pointing_outside(const ScratchDir& scratch, const std::string& uri) {
  OutsideUriCase c;
  fs::create_directories(scratch / "asset");
  test::write_text(scratch / "secret.bin", c.secret);
  fs::create_symlink(scratch / "secret.bin", scratch / "asset" / "link.bin");
  c.gltf = scratch / "asset" / "a.gltf";
  test::write_text(c.gltf, R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":35,"uri":")" + uri +
                               R"("}],"bufferViews":[{"buffer":0,"byteLength":35}],)"
                               R"("accessors":[{"bufferView":0,"componentType":5121,"count":35,"type":"SCALAR",)"
                               R"("min":[0],"max":[1]}],"images":[{"uri":")" +
                               uri + R"(","mimeType":"image/png"}]})");
  return c;
}

TEST(ValidateOutsideUris, ValidateNeverReadsAFileOutsideTheAssetsFolderInAnyFormat) {
  for (const char* uri : {"../secret.bin", "%2e%2e/secret.bin", "link.bin", "/etc/passwd"}) {
    ScratchDir scratch;
    const OutsideUriCase c = asset_pointing_outside(
        scratch, std::string(uri) == "/etc/passwd" ? fs::absolute(scratch / "secret.bin").string() : std::string(uri));
    for (const char* format : {"text", "json", "sarif"}) {
      const auto r = run_cli(std::string("validate -f ") + format + " " + quoted(c.gltf), scratch);
      const std::string all = r.out + r.err;
      // Had the secret been read, the accessor's min/max checks would print its byte values.
      EXPECT_EQ(all.find("ACCESSOR_MAX_MISMATCH"), std::string::npos) << uri << " " << format << ":\n" << all;
      EXPECT_EQ(all.find("ACCESSOR_MIN_MISMATCH"), std::string::npos) << uri << " " << format << ":\n" << all;
      EXPECT_EQ(all.find("Resource not found"), std::string::npos) << uri << ": the policy refuses, not a lookup";
      EXPECT_TRUE(all.find("outside the asset's folder") != std::string::npos ||
                  all.find("absolute path") != std::string::npos)
          << uri << " " << format << ":\n"
          << all;
    }
    const Report report = validate_file(c.gltf, "a.gltf", builtin_rules(), {}, ValidateOptions{});
    bool buffer_refused = false, image_refused = false;
    for (const Issue& issue : report.messages) {
      buffer_refused |= issue.code == "IO_ERROR" && issue.pointer == "/buffers/0/uri";
      image_refused |= issue.code == "IO_ERROR" && issue.pointer == "/images/0/uri";
    }
    EXPECT_TRUE(buffer_refused && image_refused) << uri;
  }
}

TEST(ValidateOutsideUris, ABareFileNameOnTheCommandLineKeepsThePolicy) {
  ScratchDir scratch;
  const OutsideUriCase c = asset_pointing_outside(scratch, "../secret.bin");
  const std::string command = "cd " + quoted(scratch / "asset") + " && '" GLTF_PBR_CLI "' validate -f json a.gltf > " +
                              quoted(scratch / "out.json");
  std::system(command.c_str());
  const std::string out = test::read_text(scratch / "out.json");
  EXPECT_NE(out.find("outside the asset's folder"), std::string::npos) << out;
  EXPECT_EQ(out.find("ACCESSOR_MAX_MISMATCH"), std::string::npos) << out;
}

TEST(ValidateOutsideUris, AUriThatCannotBeResolvedIsAnIssueNotACrash) {
  ScratchDir scratch;
  fs::create_directories(scratch / "asset");
  fs::create_symlink("loop", scratch / "asset" / "loop");  // a symlink to itself: ELOOP
  for (const std::string& uri : {std::string("loop/x.bin"), std::string(300, 'n') + "/x.bin"}) {
    test::write_text(scratch / "asset" / "a.gltf",
                     R"({"asset":{"version":"2.0"},"buffers":[{"byteLength":4,"uri":")" + uri + R"("}]})");
    const Report report = validate_file(scratch / "asset" / "a.gltf", "a.gltf", builtin_rules(), {}, ValidateOptions{});
    bool io_error = false;
    for (const Issue& issue : report.messages)
      io_error |= issue.code == "IO_ERROR" && issue.pointer == "/buffers/0/uri";
    EXPECT_TRUE(io_error) << uri.substr(0, 20);
  }
}

TEST(ValidateOutsideUris, AllowingThemReadsTheFileAsEveryCommandWould) {
  ScratchDir scratch;
  const OutsideUriCase c = asset_pointing_outside(scratch, "../secret.bin");
  ValidateOptions allowed;
  allowed.allow_outside_uris = true;
  const Report report = validate_file(c.gltf, "a.gltf", builtin_rules(), {}, allowed);
  for (const Issue& issue : report.messages)
    EXPECT_FALSE(issue.code == "IO_ERROR" && issue.pointer == "/buffers/0/uri") << issue.message;
}

TEST(ValidateOutsideUris, APercentEncodedImageNameInsideTheFolderIsFound) {
  ScratchDir scratch;
  const fs::path gltf = copy_model("BoxTextured", scratch / "box");
  fs::rename(scratch / "box" / "CesiumLogoFlat.png", scratch / "box" / "Cesium Logo.png");
  auto document = nlohmann::json::parse(test::read_text(gltf));
  document["images"][0]["uri"] = "Cesium%20Logo.png";
  test::write_text(gltf, document.dump());
  const Report report = validate_file(gltf, "BoxTextured.gltf", builtin_rules(), {}, ValidateOptions{});
  for (const Issue& issue : report.messages) EXPECT_NE(issue.code, "IO_ERROR") << issue.message;
}

// RFC 3986 keeps '+' in a path as itself (only forms read it as a space): a buffer file named
// "Box+0.bin" is read by every step and keeps its name in the saved asset.
TEST(ValidateOutsideUris, APlusInABufferNameIsThePlusWhicheverStepReadsIt) {
  ScratchDir scratch;
  const fs::path gltf = copy_model("Box", scratch / "box");
  fs::rename(scratch / "box" / "Box0.bin", scratch / "box" / "Box+0.bin");
  auto document = nlohmann::json::parse(test::read_text(gltf));
  ASSERT_EQ(document["buffers"][0]["uri"], "Box0.bin");
  document["buffers"][0]["uri"] = "Box+0.bin";
  test::write_text(gltf, document.dump());
  const Report report = validate_file(gltf, "Box.gltf", builtin_rules(), {}, ValidateOptions{});
  for (const Issue& issue : report.messages) EXPECT_NE(issue.severity, Severity::Error) << issue.message;
  Asset asset = load_asset(gltf, {});
  EXPECT_EQ(asset.model.buffers.at(0).uri, "Box+0.bin");
  EXPECT_EQ(asset.model.buffers.at(0).data, *read_file(scratch / "box" / "Box+0.bin"));
  save_asset(asset, scratch / "out" / "Box.gltf");
  EXPECT_EQ(nlohmann::json::parse(test::read_text(scratch / "out" / "Box.gltf"))["buffers"][0]["uri"], "Box+0.bin");
  EXPECT_EQ(read_file(scratch / "out" / "Box+0.bin"), read_file(scratch / "box" / "Box+0.bin"));
}

// An image read from outside the folder (allowed) is saved beside the output under its file
// name, and one whose name is taken gets another: the saved asset (which convert --preview draws)
// still reads each image's own bytes under its new URI.
TEST(SaveOutsideUris, RenamedImagesKeepTheirBytesInTheSavedAsset) {
  ScratchDir scratch;
  const fs::path gltf = copy_model("BoxTextured", scratch / "box");
  fs::create_directories(scratch / "tex");
  fs::rename(scratch / "box" / "CesiumLogoFlat.png", scratch / "tex" / "CesiumLogoFlat.png");
  test::write_text(scratch / "box" / "CesiumLogoFlat.png", "not the logo");  // takes the name beside the output
  auto document = nlohmann::json::parse(test::read_text(gltf));
  document["images"][0]["uri"] = "../tex/CesiumLogoFlat.png";
  document["images"][1] = {{"uri", "CesiumLogoFlat.png"}};
  test::write_text(gltf, document.dump());
  Asset asset = load_asset(gltf, {/*allow_outside_uris=*/true, nullptr, std::nullopt});
  save_asset(asset, scratch / "out" / "saved.gltf");
  const auto& images = asset.model.images;
  ASSERT_EQ(images.size(), 2u);
  EXPECT_NE(images[0].uri, images[1].uri);  // both wanted CesiumLogoFlat.png
  const Bytes logo_file = *read_file(scratch / "tex" / "CesiumLogoFlat.png");
  const auto logo = encoded_image_bytes(asset, 0), other = encoded_image_bytes(asset, 1);
  EXPECT_EQ(Bytes(logo.begin(), logo.end()), logo_file);
  EXPECT_EQ(Bytes(other.begin(), other.end()), bytes_of("not the logo"));
  EXPECT_EQ(read_file(scratch / "out" / images[0].uri), logo_file) << images[0].uri;  // beside the output
  EXPECT_EQ(read_file(scratch / "out" / images[1].uri), bytes_of("not the logo")) << images[1].uri;
}

// A GLB may name external files too: converted with nothing to change into another folder, it is
// copied as it was and takes them along.
TEST(CopyVerbatim, AGlbWithExternalFilesTakesThemAlong) {
  ScratchDir scratch;
  fs::create_directories(scratch / "in" / "tex");
  const fs::path logo = test::model_folder("BoxTextured") / "CesiumLogoFlat.png";
  fs::copy_file(logo, scratch / "in" / "tex" / "logo.png");
  const std::string json = R"({"asset":{"version":"2.0"},"images":[{"uri":"tex/logo.png"}],"textures":[{"source":0}],)"
                           R"("materials":[{"pbrMetallicRoughness":{"baseColorTexture":{"index":0}}}]})";
  write_bytes(scratch / "in" / "a.glb", glb_bytes(json, {}));
  const auto r =
      run_cli("convert -q " + quoted(scratch / "in" / "a.glb") + " -o " + quoted(scratch / "out" / "a.glb"), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(read_file(scratch / "out" / "a.glb"), read_file(scratch / "in" / "a.glb"));
  EXPECT_EQ(read_file(scratch / "out" / "tex" / "logo.png"), read_file(logo));
}

TEST(BadImages, AnEmptyImageFileIsRefusedAtLoadNamingItsUri) {
  ScratchDir scratch;
  const fs::path gltf = copy_model("BoxTextured", scratch / "box");
  test::write_text(scratch / "box" / "CesiumLogoFlat.png", "");
  try {
    (void)load_asset(gltf);
    FAIL() << "an empty image file loaded";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("/images/0/uri"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("empty"), std::string::npos) << error.what();
  }
}

TEST(Reports, MessagesStayValidUtf8WhateverBytesALibraryQuotes) {
  // A library's error may quote the bytes it read (nlohmann's parse errors, which tinygltf passes
  // on, say "last read: '\xFF'"); the report keeps them as
  // U+FFFD, so every format serialises (the fuzzer found report_to_json throwing type_error 316).
  ScratchDir scratch;
  test::write_text(scratch / "bytes.gltf", std::string("\xFF\xFE\xFD\x02\x03\x04"));
  const Report report = validate_file(scratch / "bytes.gltf", "bytes.gltf", builtin_rules(), {}, ValidateOptions{});
  ASSERT_FALSE(report.messages.empty());
  EXPECT_NO_THROW((void)report_to_json(report).dump());
  EXPECT_EQ(valid_utf8("caf\xC3\xA9 \xFF!"), "caf\xC3\xA9 \xEF\xBF\xBD!");
  EXPECT_EQ(valid_utf8("plain"), "plain");
}

TEST(TerminalEscapes, NamesFromTheFileAreEscapedInTextAndKeptExactInJson) {
  ScratchDir scratch;
  const fs::path gltf = copy_model("Box", scratch / "box");
  auto document = nlohmann::json::parse(test::read_text(gltf));
  const std::string hostile =
      "Red\x1b]0;pwned\x07\x1b[2J\r\nFAKE \xc2\x9b"
      "31m";
  document["materials"][0]["name"] = hostile;
  document["materials"][0]["extensions"]["KHR_materials_pbrSpecularGlossiness"]["specularFactor"] = {0.3, 0.9, 0.1};
  test::write_text(gltf, document.dump());
  for (const std::string& command : {std::string("validate "), "convert -v -o " + quoted(scratch / "out") + " "}) {
    const auto r = run_cli(command + quoted(gltf), scratch);
    const std::string shown = r.out + r.err;
    EXPECT_EQ(shown.find('\x1b'), std::string::npos) << command << shown;
    EXPECT_EQ(shown.find('\x07'), std::string::npos) << command << shown;
    EXPECT_EQ(shown.find("\xc2\x9b"), std::string::npos) << command << shown;
    EXPECT_EQ(shown.find("\nFAKE"), std::string::npos) << command << "a name forged a line:\n" << shown;
    EXPECT_NE(shown.find("Red\\x1b]0;pwned\\x07"), std::string::npos) << command << shown;
  }
  const auto converted = nlohmann::json::parse(test::read_text(scratch / "out" / "Box.gltf"));
  EXPECT_EQ(converted["materials"][0]["name"], hostile);
}

TEST(InPlace, KeepsTheInputsModeAndRefusesAReadOnlyFile) {
  ScratchDir scratch;
  const fs::path gltf = copy_model("Box", scratch / "box");
  fs::permissions(gltf, fs::perms::owner_read | fs::perms::owner_write);  // 0600
  auto r = run_cli("convert -q --in-place " + quoted(gltf), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(fs::status(gltf).permissions() & fs::perms::all, fs::perms::owner_read | fs::perms::owner_write);

  const fs::path read_only = copy_model("Box", scratch / "read-only");
  const Bytes before = *read_file(read_only);
  fs::permissions(read_only, fs::perms::owner_read | fs::perms::group_read | fs::perms::others_read);  // 0444
  r = run_cli("convert -q --in-place " + quoted(read_only), scratch);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("read-only"), std::string::npos) << r.err;
  EXPECT_EQ(*read_file(read_only), before);
}

TEST(LostOutputs, AReportThatCannotBeWrittenIsAnErrorWithItsReason) {
  ScratchDir scratch;
  test::write_text(scratch / "a-file", "x");
  const fs::path box = test::model_folder("Box") / "Box.gltf";
  for (const std::string& command :
       {"validate -f sarif -o " + quoted(scratch / "a-file" / "scan.sarif") + " " + quoted(box),
        "validate -f json -o " + quoted(scratch / "a-file" / "reports") + " " + quoted(box),
        "convert -q " + quoted(box) + " -o " + quoted(scratch / "out") + " --report " +
            quoted(scratch / "a-file" / "report.json")}) {
    const auto r = run_cli(command, scratch);
    EXPECT_EQ(r.exit_code, 3) << command << "\n" << r.err;
    EXPECT_NE(r.err.find("Not a directory"), std::string::npos) << command << "\n" << r.err;
    EXPECT_EQ(r.err.find("terminate"), std::string::npos) << r.err;
  }
  const int status =
      std::system(("'" GLTF_PBR_CLI "' validate -f json " + quoted(box) + " > /dev/full 2>/dev/null").c_str());
  EXPECT_EQ(WEXITSTATUS(status), 3);
}

TEST(LostOutputs, AnOutputThatCannotBeWrittenNamesItAndTheReason) {
  ScratchDir scratch;
  test::write_text(scratch / "a-file", "x");
  const auto r = run_cli(
      "convert " + quoted(test::model_folder("Box") / "Box.gltf") + " -o " + quoted(scratch / "a-file" / "Box.gltf"),
      scratch);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("output " + (scratch / "a-file" / "Box.gltf").string()), std::string::npos) << r.err;
  // The step that failed: making the folder, not writing the file into it.
  EXPECT_NE(r.err.find("cannot create the folder " + (scratch / "a-file").string() + ": Not a directory"),
            std::string::npos)
      << r.err;
}

TEST(LostOutputs, InputsThatShareAFileNameAreRefusedNotWrittenOverEachOther) {
  ScratchDir scratch;
  const fs::path a = copy_model("Box", scratch / "a"), b = copy_model("Box", scratch / "b");
  const auto r = run_cli("convert " + quoted(a) + " " + quoted(b) + " -o " + quoted(scratch / "out"), scratch);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("would both be written"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(scratch / "out"));
  const auto v =
      run_cli("validate -f json -o " + quoted(scratch / "reports") + " " + quoted(a) + " " + quoted(b), scratch);
  EXPECT_EQ(v.exit_code, 2) << v.err;
  // Their folders keep the paths apart, and both are written.
  const auto folders = run_cli(
      "convert -q " + quoted(scratch / "a") + " " + quoted(scratch / "b") + " -o " + quoted(scratch / "out"), scratch);
  EXPECT_EQ(folders.exit_code, 0) << folders.err;
  EXPECT_TRUE(fs::exists(scratch / "out" / "a" / "Box.gltf"));
  EXPECT_TRUE(fs::exists(scratch / "out" / "b" / "Box.gltf"));
}

TEST(LostOutputs, PreviewsOfAGltfAndAGlbOfOneNameAreRefusedNotDrawnIntoOneFolder) {
  ScratchDir scratch;
  copy_model("Box", scratch / "lib");
  ASSERT_EQ(run_cli("convert -q " + quoted(scratch / "lib" / "Box.gltf") + " -o " + quoted(scratch / "lib" / "Box.glb"),
                    scratch)
                .exit_code,
            0);
  const auto r = run_cli("convert " + quoted(scratch / "lib") + " -o " + quoted(scratch / "out") + " --preview " +
                             quoted(scratch / "previews"),
                         scratch);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("would both be written to " + (scratch / "previews" / "lib" / "Box").string()),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(scratch / "previews"));
  // Without previews the two outputs differ (Box.gltf, Box.glb) and both are written.
  EXPECT_EQ(run_cli("convert -q " + quoted(scratch / "lib") + " -o " + quoted(scratch / "out"), scratch).exit_code, 0);
  EXPECT_TRUE(fs::exists(scratch / "out" / "lib" / "Box.gltf"));
  EXPECT_TRUE(fs::exists(scratch / "out" / "lib" / "Box.glb"));
}

TEST(LostOutputs, AClosedPipeIsAWriteErrorNotASilentDeath) {
  ScratchDir scratch;
  // The reader is gone before we write: SIGPIPE (status 141) unless it is ignored and EPIPE reported.
  // The reader opens the FIFO and leaves at once; the writer's open waits for it.
  test::write_text(scratch / "run.sh",
                   "mkfifo \"$1/pipe\"\n(exec 3<\"$1/pipe\") &\n"
                   "'" GLTF_PBR_CLI
                   "' validate -f json \"$2\" > \"$1/pipe\" 2>/dev/null\n"
                   "echo $? > \"$1/status\"\n");
  std::system(("bash " + quoted(scratch / "run.sh") + " " + quoted(scratch.path()) + " " +
               quoted(test::model_folder("Box") / "Box.gltf"))
                  .c_str());
  const std::string status = test::read_text(scratch / "status");
  EXPECT_TRUE(status == "3\n" || status == "0\n") << "exit status " << status;
}

TEST(LostOutputs, HeatMapsOfInputsThatShareAFileNameAreKeptApart) {
  ScratchDir scratch;
  for (const char* copy : {"a", "b"}) {
    copy_model("BoxTextured", scratch / "lib" / copy);
    // A black diffuse map fails the albedo rule on every texel, so each file writes a heat map.
    write_bytes(scratch / "lib" / copy / "CesiumLogoFlat.png",
                encode_png(std::vector<std::uint8_t>(16 * 16 * 3, 0), 16, 16, 3, 1));
  }
  const auto r = run_cli("validate -q --heatmaps " + quoted(scratch / "maps") + " " + quoted(scratch / "lib"), scratch);
  ASSERT_TRUE(fs::exists(scratch / "maps")) << r.out << r.err;
  std::size_t in_a = 0, in_b = 0;
  for (const fs::path& map : test::files_under(scratch / "maps")) {
    in_a += map.parent_path() == scratch / "maps" / "lib" / "a";
    in_b += map.parent_path() == scratch / "maps" / "lib" / "b";
  }
  EXPECT_GE(in_a, 1u) << r.out;
  EXPECT_EQ(in_a, in_b);
}

TEST(LostOutputs, AFolderConvertedIntoItsParentOrBesideItselfIsStillConverted) {
  // `convert src/ -o .` puts src's files straight into "."; nothing there is an earlier output.
  ScratchDir scratch;
  copy_model("Box", scratch / "project" / "src");
  const std::string cli = "cd " + quoted(scratch / "project") + " && '" GLTF_PBR_CLI "' convert -q ";
  EXPECT_EQ(std::system((cli + "src/ -o . --format glb").c_str()), 0);
  EXPECT_TRUE(fs::exists(scratch / "project" / "Box.glb"));
  EXPECT_EQ(std::system((cli + "src -o out").c_str()), 0);
  EXPECT_TRUE(fs::exists(scratch / "project" / "out" / "src" / "Box.gltf"));
  EXPECT_EQ(std::system((cli + ". -o out").c_str()), 0) << "the earlier out/ is skipped, the rest converts";
  EXPECT_TRUE(fs::exists(scratch / "project" / "out" / "src" / "Box.gltf"));
}

TEST(LostOutputs, AnOutputFolderThatIsTheInputFolderIsNotConvertedAgain) {
  ScratchDir scratch;
  copy_model("Box", scratch / "lib" / "box");
  const std::string command = "convert " + quoted(scratch / "lib") + " -o " + quoted(scratch / "lib");
  for (int run = 0; run < 3; ++run) ASSERT_EQ(run_cli(command, scratch).exit_code, 0);
  std::size_t gltf_files = 0;
  for (const fs::path& file : test::files_under(scratch / "lib")) gltf_files += file.extension() == ".gltf";
  EXPECT_EQ(gltf_files, 2u);
}

TEST(LostOutputs, AnOutputFolderInsideTheInputTreeIsNotConvertedAgain) {
  ScratchDir scratch;
  copy_model("Box", scratch / "lib" / "box");
  const std::string command = "convert " + quoted(scratch / "lib") + " -o " + quoted(scratch / "lib" / "out");
  for (int run = 0; run < 3; ++run) {
    const auto r = run_cli(command, scratch);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    if (run > 0) {
      EXPECT_NE(r.err.find("skipped 1 "), std::string::npos) << r.err;
    }
  }
  std::size_t gltf_files = 0;
  for (const fs::path& file : test::files_under(scratch / "lib")) gltf_files += file.extension() == ".gltf";
  EXPECT_EQ(gltf_files, 2u) << "the input and its one conversion";
}

// Box with one edit applied to its JSON.
fs::path edited_box(const ScratchDir& scratch, const std::function<void(nlohmann::json&)>& edit) {
  const fs::path gltf = copy_model("Box", scratch / "box");
  auto document = nlohmann::json::parse(test::read_text(gltf));
  edit(document);
  test::write_text(gltf, document.dump());
  return gltf;
}

TEST(SilentLoss, ConvertRefusesAValueLoadingWouldDropNamingItsPointer) {
  const std::vector<std::pair<std::function<void(nlohmann::json&)>, std::string>> cases{
      {[](nlohmann::json& d) { d["nodes"][0]["children"] = {1.5}; }, "/nodes/0/children/0"},
      {[](nlohmann::json& d) {
         d["materials"][0]["extensions"]["KHR_materials_pbrSpecularGlossiness"] = nlohmann::json::array();
       },
       "/materials/0/extensions/KHR_materials_pbrSpecularGlossiness"},
      {[](nlohmann::json& d) { d["bufferViews"][0]["byteOffset"] = -4; }, "/bufferViews/0/byteOffset"},
  };
  for (const auto& [edit, pointer] : cases) {
    ScratchDir scratch;
    const fs::path gltf = edited_box(scratch, edit);
    const auto r = run_cli("convert " + quoted(gltf) + " -o " + quoted(scratch / "out"), scratch);
    EXPECT_EQ(r.exit_code, 1) << pointer << "\n" << r.err;
    EXPECT_NE(r.err.find(pointer + ": "), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(scratch / "out" / "Box.gltf")) << pointer;
  }
}

TEST(SilentLoss, AnErrorLoadingKeepsAsItWasIsNotRefused) {
  // The near miss: `children: []` is EMPTY_ENTITY to the validator, but loading loses nothing.
  ScratchDir scratch;
  const fs::path gltf =
      edited_box(scratch, [](nlohmann::json& d) { d["nodes"][1]["children"] = nlohmann::json::array(); });
  const auto r = run_cli("convert -q " + quoted(gltf) + " -o " + quoted(scratch / "out"), scratch);
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(SilentLoss, TheDemosGeneratedSamplesAllConvert) {
  // The README's demo command converts these; gold's F0 above 1 is among them.
  const fs::path samples = fs::path(GLTF_PBR_CLI).parent_path() / "samples";
  ASSERT_TRUE(fs::exists(samples / "metal-gold.gltf")) << samples;
  ScratchDir scratch;
  const auto r = run_cli("convert -q " + quoted(samples) + " -o " + quoted(scratch / "out"), scratch);
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

TEST(SilentLoss, TrailingBytesAfterTheJsonAreRefusedByConvertAsValidateReportsThem) {
  for (const std::string& trailing : {std::string("\n}garbage"), std::string("\0\0\0", 3), std::string("{}")}) {
    ScratchDir scratch;
    const fs::path gltf = copy_model("Box", scratch / "box");
    test::write_text(gltf, test::read_text(gltf) + trailing);
    const auto converted = run_cli("convert " + quoted(gltf) + " -o " + quoted(scratch / "out"), scratch);
    EXPECT_EQ(converted.exit_code, 1) << converted.err;
    EXPECT_TRUE(converted.err.find("INVALID_JSON") != std::string::npos ||
                converted.err.find("malformed JSON") != std::string::npos)
        << converted.err;
    EXPECT_FALSE(fs::exists(scratch / "out" / "Box.gltf"));
    const auto validated = run_cli("validate " + quoted(gltf), scratch);
    EXPECT_NE(validated.out.find("INVALID_JSON"), std::string::npos) << validated.out;
  }
}

TEST(SilentLoss, AnEmptyGlbIsNamedAsAnEmptyContainerNotAsJson) {
  ScratchDir scratch;
  test::write_text(scratch / "empty.glb", "");
  for (const std::string isolate : {"", " --isolate"}) {  // a child's failure keeps its byte offset too
    const auto r =
        run_cli("convert " + quoted(scratch / "empty.glb") + " -o " + quoted(scratch / "out") + isolate, scratch);
    EXPECT_EQ(r.exit_code, 1) << isolate;
    EXPECT_EQ(r.err.find("JSON"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("byte 0: not a GLB: 0 bytes"), std::string::npos) << isolate << "\n" << r.err;
    EXPECT_NE(r.err.find("1 file: "), std::string::npos) << r.err;
  }
}

TEST(SilentLoss, AnImageDataUriOfAnyTypeIsReadAsDataAndKeptAsItWas) {
  // A 1x1 lossless WebP; the '+' and '/' of base64 must survive untouched.
  const std::string webp = "data:image/webp;base64,UklGRhoAAABXRUJQVlA4TA0AAAAvAAAAEAcQERGIiP4HAPv/";
  ScratchDir scratch;
  const fs::path gltf = edited_box(scratch, [&](nlohmann::json& d) {
    d["images"] = {{{"uri", webp}}};
    d["textures"] = {{{"source", 0}}};
    d["materials"][0]["occlusionTexture"] = {{"index", 0}};
  });
  const auto r = run_cli("convert -q " + quoted(gltf) + " -o " + quoted(scratch / "out"), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto converted = nlohmann::json::parse(test::read_text(scratch / "out" / "Box.gltf"));
  EXPECT_EQ(converted["images"][0]["uri"], webp);
}

TEST(SilentLoss, PreviewOfASceneWithNothingToDrawIsNotAPass) {
  ScratchDir scratch;
  const fs::path gltf = edited_box(scratch, [](nlohmann::json& d) {
    d["scenes"] = {{{"nodes", nlohmann::json::array()}}};
  });
  const auto r = run_cli("preview " + quoted(gltf) + " -o " + quoted(scratch / "preview"), scratch);
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("nothing to draw"), std::string::npos) << r.err;
}

TEST(SilentLoss, ConvertsPreviewOfASceneWithNothingToDrawReportsNullFiguresNotZeros) {
  ScratchDir scratch;
  const fs::path gltf = edited_box(scratch, [](nlohmann::json& d) {
    d["scenes"] = {{{"nodes", nlohmann::json::array()}}};
  });
  const auto r = run_cli("convert -q " + quoted(gltf) + " -o " + quoted(scratch / "out") + " --preview " +
                             quoted(scratch / "preview") + " --preview-size 32",
                         scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;  // the conversion itself succeeded
  const auto report = nlohmann::json::parse(test::read_text(scratch / "preview" / "Box" / "report.json"));
  const nlohmann::json& difference = report["difference"];
  EXPECT_EQ(difference["pixels_compared"], 0);
  for (const char* figure :
       {"/delta_e_2000/mean", "/delta_e_2000/p95", "/delta_e_2000/max", "/flip/mean", "/rms_db", "/rms_pass"})
    EXPECT_TRUE(difference[nlohmann::json::json_pointer(figure)].is_null()) << figure << ": " << difference;
  EXPECT_NE(report["scene"]["warnings"].dump().find("nothing to draw"), std::string::npos) << report["scene"];
}

TEST(Messages, LibraryTextComesOutAsOneLineWithoutAbsolutePaths) {
  ScratchDir scratch;
  const fs::path gltf = edited_box(scratch, [](nlohmann::json& d) { d["buffers"][0]["byteLength"] = 100000; });
  const auto r = run_cli("convert " + quoted(gltf) + " -o " + quoted(scratch / "out"), scratch);
  EXPECT_EQ(r.exit_code, 1);
  const std::string first_line = r.err.substr(0, r.err.find('\n'));
  EXPECT_NE(first_line.find(gltf.string()), std::string::npos) << r.err;
  EXPECT_EQ(first_line.find((scratch / "box").string() + "/Box0.bin"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("\n\n"), std::string::npos) << r.err;
  // Ours, with the pointer, not tinygltf's "File size mismatch".
  EXPECT_NE(first_line.find("/buffers/0/byteLength"), std::string::npos) << r.err;
  EXPECT_NE(first_line.find("byteLength is 100000 but the file Box0.bin holds 648 bytes"), std::string::npos) << r.err;
}

TEST(Messages, ABufferFileLongerThanItsByteLengthIsNamedByItsPointer) {
  ScratchDir scratch;
  const fs::path gltf = edited_box(scratch, [](nlohmann::json& d) { d["buffers"][0]["byteLength"] = 600; });
  try {
    (void)load_asset(gltf);
    FAIL() << "tinygltf would have refused it without a pointer";
  } catch (const InputError& error) {
    EXPECT_EQ(error.pointer, "/buffers/0/byteLength");
    EXPECT_NE(error.reason.find("byteLength is 600 but the file Box0.bin holds 648 bytes (valid glTF"),
              std::string::npos)
        << error.what();
  }
}

TEST(Messages, AShortDataUriBufferIsNamedByItsPointer) {
  ScratchDir scratch;
  const fs::path gltf = edited_box(
      scratch, [](nlohmann::json& d) { d["buffers"][0]["uri"] = "data:application/octet-stream;base64,AAAA"; });
  try {
    (void)load_asset(gltf);
    FAIL() << "a 3-byte data URI standing for 648 bytes loaded";
  } catch (const InputError& error) {
    EXPECT_EQ(error.pointer, "/buffers/0/byteLength");
    EXPECT_NE(std::string(error.what()).find("the data URI holds 3 bytes"), std::string::npos) << error.what();
  }
}

TEST(MeasuredFigures, TheExtensionRouteReportsTheErrorItMeasuredUnderBothReadings) {
  Asset asset = load_asset(test::model_folder("BoxTextured") / "BoxTextured.gltf");
  ConvertOptions options;
  options.target = Target::Specular;
  options.specular_tolerance = 0;  // every material takes the extension route
  const ConversionReport report = convert(asset, options);
  ASSERT_FALSE(report.materials.empty());
  for (const MaterialReport& m : report.materials) {
    ASSERT_EQ(m.outcome, MaterialOutcome::Specular);
    EXPECT_GT(m.error_samples, 0u) << "texels were sampled";
    ASSERT_TRUE(m.error_a && m.error_b);
    EXPECT_LT(m.error_a->diffuse.max, 0.5) << "the route reproduces reading A";
    EXPECT_GT(m.error_b->diffuse.mean, 0.01) << "reading B's extra (1 - F) is measured, not assumed 0";
  }
}

TEST(MeasuredFigures, AMaterialLeftAsSpecGlossHasNullErrorsNotZeros) {
  ScratchDir scratch;
  const fs::path gltf = copy_model("BoxTextured", scratch / "box");
  auto document = nlohmann::json::parse(test::read_text(gltf));
  auto& extension = document["materials"][0]["extensions"]["KHR_materials_pbrSpecularGlossiness"];
  extension["specularGlossinessTexture"] = {{"index", 0}, {"texCoord", 1}};
  test::write_text(gltf, document.dump());
  const auto r = run_cli(
      "convert -v " + quoted(gltf) + " -o " + quoted(scratch / "out") + " --report " + quoted(scratch / "report.json"),
      scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = nlohmann::json::parse(test::read_text(scratch / "report.json"));
  const auto& material = report["files"][0]["materials"][0];
  EXPECT_EQ(material["outcome"], "legacy");
  EXPECT_TRUE(material["deltaE2000"]["readingA"].is_null()) << material.dump();
  EXPECT_TRUE(material["deltaE2000"]["readingB"].is_null()) << material.dump();
  EXPECT_NE(r.err.find("not measured"), std::string::npos) << r.err;
  // compare measures what a core viewer shows of it: BoxTextured's core fallback (the diffuse
  // texture, metallic 0: F0 0.04 against the legacy's 0.2), not a spec-gloss material compared with
  // itself, which gave 0.
  const auto c = run_cli("compare " + quoted(gltf) + " " + quoted(scratch / "out" / "BoxTextured.gltf"), scratch);
  ASSERT_EQ(c.exit_code, 0) << c.err;
  const auto compared = nlohmann::json::parse(c.out)["materials"][0]["deltaE2000"];
  EXPECT_GT(compared["f0"]["mean"].get<double>(), 10.0) << compared;
  EXPECT_GT(compared["diffuse"]["mean"].get<double>(), 0.5) << compared;
}

TEST(MeasuredFigures, ImagesDecodedCountsEachFilesOwnDecodesWhateverRunsBesideIt) {
  ScratchDir scratch;
  for (int i = 0; i < 4; ++i) copy_model("BoxTextured", scratch / "lib" / ("box" + std::to_string(i)));
  const auto r = run_cli("convert -q -j 2 " + quoted(scratch / "lib") + " -o " + quoted(scratch / "out") +
                             " --report " + quoted(scratch / "report.json"),
                         scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto report = nlohmann::json::parse(test::read_text(scratch / "report.json"));
  ASSERT_EQ(report["files"].size(), 4u);
  for (const auto& file : report["files"]) EXPECT_EQ(file["imagesDecoded"], 1) << file["input"];
}

// A 24-bit BMP (BITMAPINFOHEADER, rows bottom-up, padded to 4 bytes): a format only OpenImageIO reads.
Bytes bmp(int width, int height) {
  const int row = (width * 3 + 3) / 4 * 4;
  const std::uint32_t size = 54 + static_cast<std::uint32_t>(row * height);
  Bytes out(size, 0);
  auto put = [&](std::size_t at, std::uint32_t value, int bytes) {
    for (int k = 0; k < bytes; ++k) out[at + static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(value >> (8 * k));
  };
  out[0] = 'B';
  out[1] = 'M';
  put(2, size, 4);
  put(10, 54, 4);
  put(14, 40, 4);
  put(18, static_cast<std::uint32_t>(width), 4);
  put(22, static_cast<std::uint32_t>(height), 4);
  put(26, 1, 2);
  put(28, 24, 2);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width * 3; ++x)
      out[54 + static_cast<std::size_t>(y * row + x)] = static_cast<std::uint8_t>(x * 7 + y * 13);
  return out;
}

// The OpenImageIO module takes one call at a time (core/image_oiio.cpp says why); many threads
// decoding and resizing through it at once get the same texels every time.
TEST(ConcurrentDecodes, ManyThreadsThroughOpenImageIoGetIdenticalTexels) {
  const Bytes image = bmp(37, 29);
  const Pixels reference = decode_image(image, "bmp");
  ASSERT_EQ(reference.width, 37);
  const Pixels resized_reference = resize(reference, 16, 16);
  std::atomic<int> mismatches{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t)
    threads.emplace_back([&] {
      for (int i = 0; i < 6; ++i) {
        const Pixels decoded = decode_image(image, "bmp");
        mismatches += decoded.bytes != reference.bytes;
        mismatches += resize(decoded, 16, 16).floats != resized_reference.floats;
      }
    });
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(mismatches, 0);
}

// OpenImageIO's PNG reader crashed now and then in decode_icc_profile under `convert -j 2`; PNG and
// JPEG no longer go through it, and concurrent decodes must give the same texels every time.
TEST(ConcurrentDecodes, ManyThreadsDecodingPngAndJpegGetIdenticalTexels) {
  const Bytes png = *read_file(test::model_folder("BoxTextured") / "CesiumLogoFlat.png");
  const Bytes jpeg = *read_file(test::model_folder("CesiumMan") / "CesiumMan.jpg");
  const Pixels png_reference = decode_image(png, "png"), jpeg_reference = decode_image(jpeg, "jpeg");
  std::atomic<int> mismatches{0};
  std::vector<std::thread> threads;
  for (int t = 0; t < 8; ++t)
    threads.emplace_back([&] {
      for (int i = 0; i < 6; ++i) {
        mismatches += decode_image(png, "png").bytes != png_reference.bytes;
        mismatches += decode_image(jpeg, "jpeg").bytes != jpeg_reference.bytes;
      }
    });
  for (auto& thread : threads) thread.join();
  EXPECT_EQ(mismatches, 0);
}

TEST(ConcurrentDecodes, ConvertingManyTexturedCopiesInParallelNeverCrashes) {
  ScratchDir scratch;
  for (int i = 0; i < 12; ++i) copy_model("BoxTextured", scratch / "lib" / ("box" + std::to_string(i)));
  for (int run = 0; run < 3; ++run) {
    const auto r =
        run_cli("convert -q -j 2 " + quoted(scratch / "lib") + " -o " + quoted(scratch / ("out" + std::to_string(run))),
                scratch);
    ASSERT_EQ(r.exit_code, 0) << "run " << run << ":\n" << r.err;
  }
}

// Files, bakes, decodes and encodes share one pool (core/parallel.hpp): `-j 8` on a machine of N
// cores holds at most N threads of work, plus the thread that waits for signals.
TEST(Threads, ConvertWithMoreJobsThanCoresNeverHoldsMoreThreadsThanThePool) {
  ScratchDir scratch;
  for (int i = 0; i < 6; ++i) copy_model("CesiumMilkTruck", scratch / "lib" / ("truck" + std::to_string(i)));
  // Samples the process's thread count (/proc/PID/status) until it exits; prints the most seen.
  test::write_text(scratch / "count.sh", "'" GLTF_PBR_CLI
                                         "' convert -q -j 8 \"$1/lib\" -o \"$1/out\" & pid=$!\n"
                                         "most=0\n"
                                         "while [ -r /proc/$pid/status ]; do\n"
                                         "  n=$(sed -n 's/^Threads:[[:space:]]*//p' /proc/$pid/status 2>/dev/null)\n"
                                         "  [ -n \"$n\" ] && [ \"$n\" -gt \"$most\" ] && most=$n\n"
                                         "done\n"
                                         "wait $pid; echo \"$? $most\" > \"$1/result\"\n");
  std::system(("bash " + quoted(scratch / "count.sh") + " " + quoted(scratch.path())).c_str());
  std::istringstream result(test::read_text(scratch / "result"));
  int status = -1, most = 0;
  result >> status >> most;
  EXPECT_EQ(status, 0);
  EXPECT_GT(most, 0);
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  EXPECT_LE(most, cores + 1) << "threads seen at once, on " << cores << " cores";
}

TEST(DecodeOnce, AnImageReadUnderDifferentFactorsOrInBothSlotsIsDecodedOnce) {
  ScratchDir scratch;
  const fs::path gltf = copy_model("BoxTextured", scratch / "box");
  auto document = nlohmann::json::parse(test::read_text(gltf));
  auto second = document["materials"][0];
  second["extensions"]["KHR_materials_pbrSpecularGlossiness"]["diffuseFactor"] = {0.5, 0.5, 0.5, 1.0};
  auto third = document["materials"][0];
  third["extensions"]["KHR_materials_pbrSpecularGlossiness"]["specularGlossinessTexture"] = {{"index", 0}};
  document["materials"].push_back(second);
  document["materials"].push_back(third);
  test::write_text(gltf, document.dump());
  Asset asset = load_asset(gltf);
  const ConversionReport report = convert(asset, ConvertOptions{});
  ASSERT_EQ(report.materials.size(), 3u);
  EXPECT_EQ(report.images_decoded, 1);
}

TEST(DecodeOnce, AnImageSeveralMaterialsReadIsDecodedOnce) {
  // VC: 20 images, read by many materials under different factors (so by different bakes).
  Asset asset = load_asset(test::model_folder("VC") / "VC.gltf");
  std::set<int> read;
  for (const auto& material : asset.model.materials) {
    const auto extension = material.extensions.find("KHR_materials_pbrSpecularGlossiness");
    if (extension == material.extensions.end()) continue;
    for (const char* slot : {"diffuseTexture", "specularGlossinessTexture"})
      if (extension->second.Has(slot))
        read.insert(asset.model.textures[static_cast<size_t>(extension->second.Get(slot).Get("index").GetNumberAsInt())]
                        .source);
  }
  const ConversionReport report = convert(asset, ConvertOptions{});
  // Each input once, and each JPEG base colour a bake made once more: its error is measured on
  // what the file would hold, written or then left for the diffuse kept as it is. A material that
  // made its bake has the bake's times; one that shares it has none.
  long jpeg_made = 0;
  for (const MaterialReport& m : report.materials) {
    const auto& pbr = asset.model.materials[static_cast<size_t>(m.index)].pbrMetallicRoughness;
    const bool kept_diffuse = m.note.rfind("the diffuse image kept as it is", 0) == 0;
    const bool baked_jpeg = m.outputs.base_color == TextureOutcome::Baked &&
                            asset.model
                                    .images[static_cast<size_t>(
                                        asset.model.textures[static_cast<size_t>(pbr.baseColorTexture.index)].source)]
                                    .mimeType == "image/jpeg";
    jpeg_made += baked_jpeg || (kept_diffuse && m.times.solve_ms > 0);
  }
  EXPECT_GT(jpeg_made, 0);
  EXPECT_EQ(report.images_decoded, static_cast<long>(read.size()) + jpeg_made);
}

TEST(Signals, SigtermRemovesStagedTemporariesAndExitsWithTheSignal) {
  ScratchDir scratch;
  const fs::path destination = scratch / "out.bin";
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    install_signal_cleanup();
    AtomicWriteSet files;
    files.stage(destination, bytes_of("partial"));
    ::kill(::getpid(), SIGTERM);
    ::pause();
    std::_Exit(0);  // not reached: the cleanup thread exits first
  }
  int status = 0;
  ::waitpid(child, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);
  EXPECT_TRUE(test::files_under(scratch.path()).empty()) << test::files_under(scratch.path()).front();
}

TEST(Messages, BothBatchCommandsShowProgressOnATerminalAndNotInAPipe) {
  ScratchDir scratch;
  copy_model("Box", scratch / "lib" / "a");
  copy_model("Box", scratch / "lib" / "b");
  for (const std::string& command : {"validate -q " + quoted(scratch / "lib"),
                                     "convert -q " + quoted(scratch / "lib") + " -o " + quoted(scratch / "out")}) {
    // script(1) (bsdutils, in every Debian) gives the command a terminal.
    const fs::path log = scratch / "terminal.txt";
    std::system(("script -qec \"'" GLTF_PBR_CLI "' " + command + "\" /dev/null > " + quoted(log)).c_str());
    EXPECT_NE(test::read_text(log).find("[1/2] "), std::string::npos) << command << ":\n" << test::read_text(log);
    const auto piped = run_cli(command, scratch);
    EXPECT_EQ(piped.err.find("[1/2] "), std::string::npos) << command;
  }
}

TEST(Messages, BadJobCountsAndUnknownCommandsGiveShortClearMessages) {
  ScratchDir scratch;
  const fs::path box = test::model_folder("Box") / "Box.gltf";
  for (const char* command : {"convert -j 0 -o x ", "validate -j 0 "}) {
    const auto r = run_cli(std::string(command) + quoted(box), scratch);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_LT(r.err.size(), 300u) << r.err;
    EXPECT_NE(r.err.find("--jobs"), std::string::npos) << r.err;
  }
  const auto unknown = run_cli("convrt " + quoted(box), scratch);
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("unknown command 'convrt'"), std::string::npos) << unknown.err;
}

// Duck with its diffuse image moved to a file named `name`: an image file, or a buffer read through
// a bufferView. As buffer 1, the buffer holds a second, unused view too, so the conversion keeps it
// compacted and names it anew; as buffer 0, before Duck0.bin, the conversion empties it.
enum class ImagePlace { File, BufferKeptAfterTheMesh, BufferOnlyBeforeTheMesh };
fs::path duck_with_image_in(const fs::path& folder, const std::string& name, ImagePlace place) {
  const fs::path gltf = copy_model("Duck", folder);
  auto document = nlohmann::json::parse(test::read_text(gltf));
  fs::rename(folder / "DuckCM.png", folder / name);
  if (place == ImagePlace::File) {
    document["images"][0]["uri"] = name;
  } else {
    auto bytes = *read_file(folder / name);
    const size_t image_size = bytes.size();
    const bool first = place == ImagePlace::BufferOnlyBeforeTheMesh;
    if (!first) {  // the unused view's 4 bytes, 4-aligned after the image
      bytes.resize((image_size + 3) / 4 * 4 + 4, 7);
      test::write_bytes(folder / name, bytes);
    }
    const nlohmann::json buffer = {{"uri", name}, {"byteLength", bytes.size()}};
    if (first) {
      for (auto& view : document["bufferViews"]) view["buffer"] = 1;
      document["buffers"].insert(document["buffers"].begin(), buffer);
    } else {
      document["buffers"].push_back(buffer);
    }
    const int image_buffer = first ? 0 : 1;
    document["bufferViews"].push_back({{"buffer", image_buffer}, {"byteLength", image_size}});
    document["images"][0] = {{"bufferView", document["bufferViews"].size() - 1}, {"mimeType", "image/png"}};
    if (!first) document["bufferViews"].push_back({{"buffer", 1}, {"byteOffset", bytes.size() - 4}, {"byteLength", 4}});
  }
  test::write_text(gltf, document.dump());
  return gltf;
}

// The validator's error count for a converted file: what the conversion wrote must be valid glTF.
std::size_t errors_in(const fs::path& gltf) {
  const Report report = validate_file(gltf, gltf.filename().string(), builtin_rules(), {}, ValidateOptions{});
  for (const Issue& issue : report.messages)
    if (issue.severity == Severity::Error) ADD_FAILURE() << gltf << ": " << issue.code << " " << issue.message;
  return report.count(Severity::Error);
}

TEST(LostOutputs, AFileTheInputReadsIsNeverTakenForAnOutputsName) {
  // Named as the output's new files would be: its baked base colour, and its compacted buffer 1.
  ScratchDir scratch;
  for (const ImagePlace place : {ImagePlace::File, ImagePlace::BufferKeptAfterTheMesh}) {
    const fs::path folder = scratch / (place == ImagePlace::File ? "image" : "buffer");
    const std::string name = place == ImagePlace::File ? "o_baseColor_1.png" : "o_1.bin";
    const fs::path gltf = duck_with_image_in(folder, name, place);
    const auto before = read_file(folder / name);
    const auto r = run_cli("convert -q " + quoted(gltf) + " -o " + quoted(folder / "o.gltf"), scratch);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(read_file(folder / name), before) << name << " was written over";
    EXPECT_NO_THROW(load_asset(gltf)) << "the input still loads";
    EXPECT_EQ(errors_in(folder / "o.gltf"), 0u);
  }
}

TEST(LostOutputs, AnImageInItsOwnBufferLeavesNoEmptyBufferWhenItIsBakedAway) {
  // The image's buffer is buffer 0: removing it moves every other view's buffer index.
  ScratchDir scratch;
  const fs::path gltf = duck_with_image_in(scratch / "in", "image.bin", ImagePlace::BufferOnlyBeforeTheMesh);
  const auto r = run_cli("convert -q " + quoted(gltf) + " -o " + quoted(scratch / "out" / "Duck.gltf"), scratch);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Asset converted = load_asset(scratch / "out" / "Duck.gltf");
  ASSERT_EQ(converted.model.buffers.size(), 1u) << "the image's buffer held nothing else";
  EXPECT_EQ(converted.model.buffers[0].data, read_file(test::model_folder("Duck") / "Duck0.bin"));
  for (const auto& view : converted.model.bufferViews) EXPECT_EQ(view.buffer, 0);
  const Asset original = load_asset(test::model_folder("Duck") / "Duck.gltf");
  ASSERT_EQ(converted.model.accessors.size(), original.model.accessors.size());
  const auto accessor_bytes = [](const tinygltf::Model& model, size_t accessor) {
    const auto& view = model.bufferViews.at(static_cast<size_t>(model.accessors.at(accessor).bufferView));
    const auto& data = model.buffers.at(static_cast<size_t>(view.buffer)).data;
    const auto first = data.begin() + static_cast<std::ptrdiff_t>(view.byteOffset);
    return std::vector<std::uint8_t>(first, first + static_cast<std::ptrdiff_t>(view.byteLength));
  };
  for (size_t a = 0; a < original.model.accessors.size(); ++a)
    EXPECT_EQ(accessor_bytes(converted.model, a), accessor_bytes(original.model, a)) << "accessor " << a;
  EXPECT_EQ(errors_in(scratch / "out" / "Duck.gltf"), 0u);
}

TEST(LostOutputs, AReportWhereAFolderStandsIsRefusedBeforeTheRunsWork) {
  ScratchDir scratch;
  const fs::path gltf = copy_model("Box", scratch / "in");
  fs::create_directories(scratch / "report.json");
  const auto r = run_cli(
      "convert -q " + quoted(gltf) + " -o " + quoted(scratch / "out") + " --report " + quoted(scratch / "report.json"),
      scratch);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("it is a folder"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(scratch / "out")) << "found before any file was converted";
}

TEST(LostOutputs, AReportToAPipeReachesItsReader) {
  // `--report /dev/stdout | jq` as root used to rename a file over what /dev/stdout leads to.
  ScratchDir scratch;
  const fs::path gltf = copy_model("Box", scratch / "in");
  const std::string command = "(" + quoted(GLTF_PBR_CLI) + " convert -q " + quoted(gltf) + " -o " +
                              quoted(scratch / "out") + " --report /dev/stdout; echo $? > " +
                              quoted(scratch / "code.txt") + ") | cat > " + quoted(scratch / "piped.json");
  ASSERT_EQ(std::system(command.c_str()), 0);
  EXPECT_EQ(test::read_text(scratch / "code.txt"), "0\n");
  const nlohmann::json report = nlohmann::json::parse(test::read_text(scratch / "piped.json"));
  EXPECT_EQ(report.at("files").size(), 1u);
  // Appended to a log, with the run's messages beside it: written at the descriptor's end, not
  // over what the log held.
  test::write_text(scratch / "run.log", "EARLIER\n");
  const std::string appended = quoted(GLTF_PBR_CLI) + " convert " + quoted(gltf) + " -o " + quoted(scratch / "out2") +
                               " --report /dev/stdout >> " + quoted(scratch / "run.log") + " 2>&1";
  ASSERT_EQ(std::system(appended.c_str()), 0);
  const std::string log = test::read_text(scratch / "run.log");
  EXPECT_EQ(log.rfind("EARLIER\n", 0), 0u) << log;
  const std::size_t json_start = log.find("\n{") + 1;
  ASSERT_NE(json_start, 0u) << log;
  const std::size_t json_end = log.find("\n}\n", json_start);
  ASSERT_NE(json_end, std::string::npos) << log;
  EXPECT_EQ(nlohmann::json::parse(log.substr(json_start, json_end + 2 - json_start)).at("files").size(), 1u) << log;
}

TEST(LostOutputs, AReportOrResultsFileNamingAnInputIsRefusedBeforeAnythingIsWritten) {
  ScratchDir scratch;
  const fs::path gltf = copy_model("BoxTextured", scratch / "in");
  const auto document = read_file(gltf), image = read_file(scratch / "in" / "CesiumLogoFlat.png");
  for (const std::string& option :
       {"--report " + quoted(gltf), "--results " + quoted(scratch / "in" / "CesiumLogoFlat.png"),
        "--report " + quoted(scratch / "in" / "BoxTextured0.bin")}) {
    const auto r = run_cli("convert -q " + quoted(gltf) + " -o " + quoted(scratch / "out") + " " + option, scratch);
    EXPECT_EQ(r.exit_code, 2) << option << "\n" << r.err;
    EXPECT_NE(r.err.find("refusing to write"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(scratch / "out")) << option;
  }
  const auto v = run_cli("validate " + quoted(gltf) + " --results " + quoted(gltf), scratch);
  EXPECT_EQ(v.exit_code, 2) << v.err;
  test::write_text(scratch / "list.txt", gltf.string() + "\n");  // the input list is read too
  const auto listed = run_cli("convert -q --inputs-from " + quoted(scratch / "list.txt") + " -o " +
                                  quoted(scratch / "out") + " --report " + quoted(scratch / "list.txt"),
                              scratch);
  EXPECT_EQ(listed.exit_code, 2) << listed.err;
  EXPECT_EQ(test::read_text(scratch / "list.txt"), gltf.string() + "\n");
  // A report beside the input that is no file of it is written, new or over an old one.
  test::write_text(scratch / "in" / "old.json", "an earlier report");
  for (const char* name : {"new.json", "old.json"}) {
    const auto beside = run_cli(
        "convert -q " + quoted(gltf) + " -o " + quoted(scratch / "out") + " --report " + quoted(scratch / "in" / name),
        scratch);
    EXPECT_EQ(beside.exit_code, 0) << name << "\n" << beside.err;
    EXPECT_TRUE(nlohmann::json::parse(test::read_text(scratch / "in" / name)).contains("files")) << name;
  }
  EXPECT_EQ(read_file(gltf), document);
  EXPECT_EQ(read_file(scratch / "in" / "CesiumLogoFlat.png"), image);
}

TEST(LostOutputs, AResultsFileThatIsAHardLinkToAFileTheRunReadsIsRefused) {
  // --results is appended to in place: under another name, the same file would be written into.
  ScratchDir scratch;
  const fs::path gltf = copy_model("BoxTextured", scratch / "in");
  const auto document = read_file(gltf), image = read_file(scratch / "in" / "CesiumLogoFlat.png");
  fs::create_hard_link(gltf, scratch / "results.jsonl");
  fs::create_hard_link(scratch / "in" / "CesiumLogoFlat.png", scratch / "texture.jsonl");
  const auto validate =
      run_cli("validate " + quoted(gltf) + " --results " + quoted(scratch / "results.jsonl"), scratch);
  EXPECT_EQ(validate.exit_code, 2) << validate.err;
  EXPECT_NE(validate.err.find("refusing to write"), std::string::npos) << validate.err;
  const auto convert = run_cli("convert -q " + quoted(gltf) + " -o " + quoted(scratch / "out") + " --results " +
                                   quoted(scratch / "texture.jsonl"),
                               scratch);
  EXPECT_EQ(convert.exit_code, 2) << convert.err;
  EXPECT_FALSE(fs::exists(scratch / "out"));
  EXPECT_EQ(read_file(gltf), document);
  EXPECT_EQ(read_file(scratch / "in" / "CesiumLogoFlat.png"), image);
}

TEST(LostOutputs, APreviewOrAReportFolderNamingAFileTheInputReadsIsRefusedBeforeAnythingIsWritten) {
  // The texture is named as a preview's image and lies where the previews go: the input's folder
  // (preview -o), its own name's folder (convert --preview), and the input is named as a report
  // folder's summary.
  ScratchDir scratch;
  const fs::path gltf = copy_model("BoxTextured", scratch / "in");
  fs::create_directories(scratch / "in" / "BoxTextured");
  fs::rename(scratch / "in" / "CesiumLogoFlat.png", scratch / "in" / "BoxTextured" / "before.png");
  std::string text = test::read_text(gltf);
  const std::string old_uri = "\"CesiumLogoFlat.png\"";
  ASSERT_NE(text.find(old_uri), std::string::npos);
  text.replace(text.find(old_uri), old_uri.size(), "\"BoxTextured/before.png\"");
  test::write_text(gltf, text);
  const fs::path summary = scratch / "in" / "summary.json";
  fs::copy(gltf, summary);
  const auto image = read_file(scratch / "in" / "BoxTextured" / "before.png");

  const auto preview =
      run_cli("preview -q --size 32 " + quoted(gltf) + " -o " + quoted(scratch / "in" / "BoxTextured"), scratch);
  EXPECT_EQ(preview.exit_code, 2) << preview.err;
  EXPECT_NE(preview.err.find("refusing to write"), std::string::npos) << preview.err;
  const auto convert = run_cli("convert -q " + quoted(gltf) + " -o " + quoted(scratch / "out") + " --preview " +
                                   quoted(scratch / "in") + " --preview-size 32",
                               scratch);
  EXPECT_EQ(convert.exit_code, 2) << convert.err;
  EXPECT_FALSE(fs::exists(scratch / "out"));
  const auto validate = run_cli("validate --format json " + quoted(summary) + " -o " + quoted(scratch / "in"), scratch);
  EXPECT_EQ(validate.exit_code, 2) << validate.err;
  EXPECT_EQ(read_file(scratch / "in" / "BoxTextured" / "before.png"), image);
  EXPECT_EQ(test::read_text(summary), text);
  EXPECT_FALSE(fs::exists(scratch / "in" / "summary.json.report.json"));
  // validate's config file is read too.
  test::write_text(scratch / "rules.json", "{}");
  const auto config = run_cli("validate --config " + quoted(scratch / "rules.json") + " " + quoted(gltf) + " -o " +
                                  quoted(scratch / "rules.json"),
                              scratch);
  EXPECT_EQ(config.exit_code, 2) << config.err;
  EXPECT_EQ(test::read_text(scratch / "rules.json"), "{}");
  // The same runs elsewhere write their files.
  EXPECT_EQ(run_cli("preview -q --size 32 " + quoted(gltf) + " -o " + quoted(scratch / "p"), scratch).exit_code, 0);
  EXPECT_TRUE(fs::exists(scratch / "p" / "before.png"));
  // (BoxTextured's diffuse + F0 exceeds 1: an error, exit 1.)
  EXPECT_EQ(run_cli("validate --format json " + quoted(summary) + " -o " + quoted(scratch / "v"), scratch).exit_code,
            1);
  EXPECT_TRUE(fs::exists(scratch / "v" / "summary.json"));
}

TEST(LostOutputs, TwoInputsWhoseHeatMapsWouldShareNamesAreRefused) {
  // a/BoxTextured.gltf and b/BoxTextured.gltf given as files: both heat maps would be
  // BoxTextured-material0-texture0.png in one folder.
  ScratchDir scratch;
  const fs::path a = copy_model("BoxTextured", scratch / "lib" / "a"),
                 b = copy_model("BoxTextured", scratch / "lib" / "b");
  const auto r =
      run_cli("validate -q " + quoted(a) + " " + quoted(b) + " --heatmaps " + quoted(scratch / "maps"), scratch);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("would both be written"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(scratch / "maps"));
  // Given as their folder, each keeps its own subfolder (HeatMapsOfInputsThatShareAFileNameAreKeptApart).
}

TEST(LostOutputs, AHeatMapFolderHoldingAFileTheInputReadsUnderAHeatMapsNameIsRefused) {
  // Heat maps are named as they are written (<stem>-material<M>-texture<T>.png); the texture is
  // given the name BoxTextured's first heat map takes, in the folder the heat maps go to.
  ScratchDir scratch;
  const fs::path gltf = copy_model("BoxTextured", scratch / "in");
  const std::string heat_map_name = "BoxTextured-material0-texture0.png";
  fs::rename(scratch / "in" / "CesiumLogoFlat.png", scratch / "in" / heat_map_name);
  std::string text = test::read_text(gltf);
  const std::string old_uri = "\"CesiumLogoFlat.png\"";
  ASSERT_NE(text.find(old_uri), std::string::npos);
  text.replace(text.find(old_uri), old_uri.size(), "\"" + heat_map_name + "\"");
  test::write_text(gltf, text);
  const auto image = read_file(scratch / "in" / heat_map_name);

  const auto refused = run_cli("validate -q " + quoted(gltf) + " --heatmaps " + quoted(scratch / "in"), scratch);
  EXPECT_EQ(refused.exit_code, 2) << refused.err;
  EXPECT_NE(refused.err.find("refusing to write"), std::string::npos) << refused.err;
  EXPECT_NE(refused.err.find(heat_map_name), std::string::npos) << refused.err;
  EXPECT_EQ(read_file(scratch / "in" / heat_map_name), image);
  // Elsewhere the heat map is written under that name (BoxTextured's diffuse + F0 exceeds 1: exit 1).
  EXPECT_EQ(run_cli("validate -q " + quoted(gltf) + " --heatmaps " + quoted(scratch / "maps"), scratch).exit_code, 1);
  EXPECT_TRUE(fs::exists(scratch / "maps" / heat_map_name));
  // A symbolic link named as the heat map, to a texture outside the heat maps' folder: writing the
  // heat map would rename it over the link the input reads.
  fs::create_directories(scratch / "in" / "maps");
  fs::create_symlink("../" + heat_map_name, scratch / "in" / "maps" / heat_map_name);
  std::string linked = text;
  linked.replace(linked.find(heat_map_name), heat_map_name.size(), "maps/" + heat_map_name);
  test::write_text(gltf, linked);
  const auto through_link =
      run_cli("validate -q " + quoted(gltf) + " --heatmaps " + quoted(scratch / "in" / "maps"), scratch);
  EXPECT_EQ(through_link.exit_code, 2) << through_link.err;
  EXPECT_TRUE(fs::is_symlink(scratch / "in" / "maps" / heat_map_name));
  test::write_text(gltf, text);
  // A file of the folder that no heat map is named as stays no reason to refuse.
  fs::copy(scratch / "in" / heat_map_name, scratch / "in" / "BoxTextured-material0-texture0.jpg");
  text.replace(text.find(heat_map_name), heat_map_name.size(), "BoxTextured-material0-texture0.jpg");
  test::write_text(gltf, text);
  EXPECT_EQ(run_cli("validate -q " + quoted(gltf) + " --heatmaps " + quoted(scratch / "in"), scratch).exit_code, 1);
}

TEST(SilentLoss, FactorsOutsideTheSchemaStillConvertIntoAValidFile) {
  // Above 1 and below 0 in every route that copies a factor: a JPEG diffuse kept as it is, a PNG
  // diffuse reused, factors only, and the KHR_materials_specular route.
  ScratchDir scratch;
  const fs::path gltf = copy_model("Duck", scratch / "in");
  const Pixels duck = decode_image(*read_file(scratch / "in" / "DuckCM.png"), "DuckCM.png");
  test::write_bytes(scratch / "in" / "duck.jpg", encode_jpeg(duck.bytes, duck.width, duck.height, duck.channels, 95));
  auto document = nlohmann::json::parse(test::read_text(gltf));
  document["images"].push_back({{"uri", "duck.jpg"}});
  document["textures"].push_back({{"source", 1}});
  const auto material = [](nlohmann::json factors, int texture) {
    if (texture >= 0) factors["diffuseTexture"] = {{"index", texture}};
    return nlohmann::json{{"extensions", {{test::kSpecGloss, factors}}}, {"alphaMode", "BLEND"}};
  };
  document["materials"] = {
      material({{"diffuseFactor", {1.5, 1.2, 1.0, 1.0}}, {"specularFactor", {0, 0, 0}}, {"glossinessFactor", 0.6}}, 1),
      material({{"diffuseFactor", {1, 1, 1, 1.7}}, {"specularFactor", {0.04, 0.04, 0.04}}}, 0),
      material({{"diffuseFactor", {1, 1, 1, -0.5}}, {"specularFactor", {0.04, 0.04, 0.04}}}, 0),
      material({{"diffuseFactor", {2, -0.5, 0.3, 2}}, {"specularFactor", {-0.5, 2, 0}}, {"glossinessFactor", -1}}, -1)};
  document["meshes"][0]["primitives"][0]["material"] = 0;
  for (int m = 1; m < 4; ++m) {
    document["meshes"][0]["primitives"].push_back(document["meshes"][0]["primitives"][0]);
    document["meshes"][0]["primitives"][static_cast<size_t>(m)]["material"] = m;
  }
  test::write_text(gltf, document.dump());
  for (const std::string target : {"metalness", "specular"}) {
    const fs::path out = scratch / target / "Duck.gltf";
    const auto r = run_cli("convert -q " + quoted(gltf) + " -o " + quoted(out) + " --target " + target, scratch);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(errors_in(out), 0u) << target;
  }
}

TEST(SilentLoss, ADiffuseImageGltfDoesNotAllowIsBakedNotKeptAsTheBaseColour) {
  // A CMYK JPEG (IMAGE_DATA_INVALID), and a JPEG declared as image/png: kept as they are, the
  // converted file would carry the error. The specular route copies the diffuse too.
  ScratchDir scratch;
  const auto converts_into_valid_files = [&](const fs::path& input, const std::string& folder) {
    for (const std::string target : {"metalness", "specular"}) {
      const fs::path out = scratch / folder / target / input.filename();
      const auto r = run_cli(
          "convert -q " + quoted(input) + " -o " + quoted(out) + " --target " + target + " --specular-tolerance 0",
          scratch);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      EXPECT_EQ(errors_in(out), 0u) << folder << ", " << target;
    }
  };
  converts_into_valid_files(fs::path(GLTF_PBR_SOURCE_DIR) / "tests" / "hostile_inputs" / "cmyk_jpeg_diffuse.gltf",
                            "cmyk");

  const fs::path gltf = copy_model("Duck", scratch / "in");
  const Pixels duck = decode_image(*read_file(scratch / "in" / "DuckCM.png"), "DuckCM.png");
  test::write_bytes(scratch / "in" / "DuckCM.png", encode_jpeg(duck.bytes, duck.width, duck.height, duck.channels, 95));
  auto document = nlohmann::json::parse(test::read_text(gltf));
  document["images"][0]["mimeType"] = "image/png";
  test::write_text(gltf, document.dump());
  converts_into_valid_files(gltf, "mime");
}

}  // namespace
}  // namespace gltf_pbr
