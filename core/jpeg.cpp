// JPEG through libjpeg-turbo's TurboJPEG API: the same islow DCT and fancy upsampling that
// OpenImageIO's libjpeg path uses, at about half its decode time (DESIGN.md). libjpeg "recovers"
// from a truncated or corrupt scan with a warning and grey texels, which would bake silently:
// those warnings are errors here; harmless ones (extraneous bytes, a JFIF revision) are not.
#include <turbojpeg.h>

#include <memory>
#include <stdexcept>

#include "core/codecs.hpp"

namespace gltf_pbr::codecs {
namespace {

using Handle = std::unique_ptr<void, decltype(&tjDestroy)>;

[[noreturn]] void fail(tjhandle handle, const char* what) {
  throw std::runtime_error(std::string(what) + ": " + tjGetErrorStr2(handle));
}

// libjpeg's warnings (jerror.h) that mean texels were not decoded from the stream but made up:
// JWRN_JPEG_EOF, JWRN_HIT_MARKER, JWRN_HUFF_BAD_CODE, JWRN_ARITH_BAD_CODE, JWRN_MUST_RESYNC ("found
// marker 0x.. instead of RSTn": a scan that ends before the frame its header claims).
bool lost_data(const std::string& warning) {
  for (const char* sign : {"remature end", "bad Huffman code", "bad arithmetic code", "instead of RST"})
    if (warning.find(sign) != std::string::npos) return true;
  return false;
}

}  // namespace

std::optional<Pixels> decode_jpeg(std::span<const std::uint8_t> encoded, std::uint64_t max_pixels) {
  Handle handle(tjInitDecompress(), &tjDestroy);
  if (!handle) throw std::bad_alloc();
  int width = 0, height = 0, subsampling = 0, colour_space = 0;
  if (tjDecompressHeader3(handle.get(), encoded.data(), static_cast<unsigned long>(encoded.size()), &width, &height,
                          &subsampling, &colour_space) != 0)
    fail(handle.get(), "JPEG header");
  if (static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height) > max_pixels)
    throw std::runtime_error(
        too_large(static_cast<std::uint64_t>(width), static_cast<std::uint64_t>(height), max_pixels));
  if (colour_space == TJCS_CMYK || colour_space == TJCS_YCCK) return std::nullopt;
  Pixels pixels;
  pixels.width = width;
  pixels.height = height;
  pixels.channels = colour_space == TJCS_GRAY ? 1 : 3;
  pixels.bytes.resize(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) *
                      static_cast<std::size_t>(pixels.channels));
  // LIMITSCANS refuses progressive files with over 500 scans, each a full pass over the image.
  if (tjDecompress2(handle.get(), encoded.data(), static_cast<unsigned long>(encoded.size()), pixels.bytes.data(),
                    width, 0, height, pixels.channels == 1 ? TJPF_GRAY : TJPF_RGB, TJFLAG_LIMITSCANS) != 0) {
    if (tjGetErrorCode(handle.get()) != TJERR_WARNING || lost_data(tjGetErrorStr2(handle.get())))
      fail(handle.get(), "JPEG data");
  }
  return pixels;
}

Bytes encode_jpeg(std::span<const std::uint8_t> texels, int width, int height, int channels, int quality) {
  if (channels != 1 && channels != 3)
    throw std::runtime_error("JPEG encoder: " + std::to_string(channels) + " channels");
  if (texels.size() !=
      static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * static_cast<std::size_t>(channels))
    throw std::runtime_error("JPEG encoder: " + std::to_string(texels.size()) + " bytes for " + std::to_string(width) +
                             "x" + std::to_string(height) + "x" + std::to_string(channels));
  Handle handle(tjInitCompress(), &tjDestroy);
  if (!handle) throw std::bad_alloc();
  unsigned char* buffer = nullptr;
  unsigned long size = 0;
  // 4:2:0 chroma and the islow DCT, libjpeg's defaults and so what OpenImageIO wrote (TurboJPEG
  // alone would compress with the fast DCT).
  const int status = tjCompress2(handle.get(), texels.data(), width, 0, height, channels == 1 ? TJPF_GRAY : TJPF_RGB,
                                 &buffer, &size, channels == 1 ? TJSAMP_GRAY : TJSAMP_420, quality, TJFLAG_ACCURATEDCT);
  std::unique_ptr<unsigned char, decltype(&tjFree)> owned(buffer, &tjFree);
  if (status != 0) fail(handle.get(), "JPEG encoder");
  return Bytes(buffer, buffer + size);
}

}  // namespace gltf_pbr::codecs
