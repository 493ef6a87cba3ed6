// The OpenImageIO side of core/image.hpp, for what the lean PNG/JPEG codecs do not serve (WebP,
// BMP, GIF, EXR and TIFF environments, CMYK JPEG, filtered resizing; Radiance .hdr is read by
// preview/environment_file.cpp), built as a module that
// core/image.cpp loads on first use: Debian's libOpenImageIO pulls in ~260 shared libraries whose
// binding takes 0.2-0.3 s and 128 MiB, a cost that PNG/JPEG and factor-only work must not pay.
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <mutex>
#include <stdexcept>

#include "core/image.hpp"

namespace gltf_pbr {
namespace OIIO = OIIO_NAMESPACE;

namespace {
// OpenImageIO picks its reader by file name; the bytes' signature tells which name to give.
std::string name_for_signature(std::span<const std::uint8_t> bytes) {
  auto starts = [&](std::initializer_list<std::uint8_t> magic) {
    return bytes.size() >= magic.size() && std::equal(magic.begin(), magic.end(), bytes.begin());
  };
  if (starts({0x89, 'P', 'N', 'G'})) return "memory.png";
  if (starts({0xFF, 0xD8, 0xFF})) return "memory.jpg";
  if (starts({'R', 'I', 'F', 'F'})) return "memory.webp";
  if (starts({'B', 'M'})) return "memory.bmp";
  if (starts({'G', 'I', 'F'})) return "memory.gif";
  if (starts({0x76, 0x2F, 0x31, 0x01})) return "memory.exr";
  // TIFF and BigTIFF, either byte order.
  if (starts({'I', 'I', 0x2A, 0}) || starts({'M', 'M', 0, 0x2A}) || starts({'I', 'I', 0x2B, 0}) ||
      starts({'M', 'M', 0, 0x2B}))
    return "memory.tif";
  throw std::runtime_error("not an image format this tool reads (PNG, JPEG, WebP, BMP, GIF, OpenEXR, TIFF)");
}

// A GIF's logical screen (GIF89a section 18): OpenImageIO's reader allocates a canvas of that size
// as it opens the file, before its spec can be checked against the limit.
void refuse_gif_screen_above(std::span<const std::uint8_t> bytes, std::uint64_t max_pixels) {
  if (bytes.size() < 10 || bytes[0] != 'G' || bytes[1] != 'I' || bytes[2] != 'F') return;
  const std::uint64_t width = bytes[6] | bytes[7] << 8, height = bytes[8] | bytes[9] << 8;
  if (width * height > max_pixels)
    throw std::runtime_error("GIF screen is " + std::to_string(width) + "x" + std::to_string(height) +
                             " pixels, above the limit of " + std::to_string(max_pixels) + " (--max-image-pixels)");
}
}  // namespace

namespace {

// OpenImageIO 2.4 is not safe to enter from several threads at once here: ThreadSanitizer reports
// a data race inside ustring::make_unique (its global string table) between two concurrent
// ImageInput::open calls of one PNG held in memory, with or without an ICC profile. The rare
// convert -j 2 segfault inside decode_icc_profile fits it (not proven: it never reproduced under a
// sanitizer): that is where an open first interns some twenty new attribute names
// ("ICCProfile:..."). Only formats without a lean codec and resizes come here, so one call at a
// time costs little.
std::mutex oiio_calls;

Pixels decode_with_oiio(std::span<const std::uint8_t> encoded, std::uint64_t max_pixels) {
  const std::lock_guard lock(oiio_calls);
  refuse_gif_screen_above(encoded, max_pixels);
  OIIO::Filesystem::IOMemReader reader(encoded.data(), encoded.size());
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);  // keep alpha straight, as glTF stores it
  void* proxy = &reader;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy);
  auto input = OIIO::ImageInput::open(name_for_signature(encoded), &config, &reader);
  if (!input) throw std::runtime_error(OIIO::geterror());
  const OIIO::ImageSpec& spec = input->spec();
  const auto width = static_cast<std::uint64_t>(std::max(spec.width, 0));
  const auto height = static_cast<std::uint64_t>(std::max(spec.height, 0));
  // Textures are 2-D with 1-4 channels; a volume (depth > 1) or a 30-channel EXR would not fit the
  // buffer below, which holds width x height x channels.
  if (spec.depth != 1 || spec.nchannels < 1 || spec.nchannels > 4)
    throw std::runtime_error("unsupported image layout: depth " + std::to_string(spec.depth) + ", " +
                             std::to_string(spec.nchannels) + " channels");
  if (width * height > max_pixels)  // before read_image allocates anything
    throw std::runtime_error("image is " + std::to_string(width) + "x" + std::to_string(height) +
                             " pixels, above the limit of " + std::to_string(max_pixels) + " (--max-image-pixels)");
  Pixels pixels;
  pixels.width = spec.width;
  pixels.height = spec.height;
  pixels.channels = spec.nchannels;
  pixels.bits = static_cast<int>(spec.format.size()) * 8;
  const size_t count =
      static_cast<size_t>(spec.width) * static_cast<size_t>(spec.height) * static_cast<size_t>(spec.nchannels);
  // Read at the stored precision (Pixels keeps 8- and 16-bit images as integers).
  bool read = false;
  if (spec.format == OIIO::TypeDesc::UINT8) {
    pixels.bytes.resize(count);
    read = input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, pixels.bytes.data());
  } else if (spec.format == OIIO::TypeDesc::UINT16) {
    pixels.shorts.resize(count);
    read = input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT16, pixels.shorts.data());
  } else {
    pixels.floats.resize(count);
    read = input->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.floats.data());
  }
  if (!read) throw std::runtime_error(input->geterror());
  return pixels;
}

Pixels resample_with_oiio(const Pixels& pixels, int width, int height) {
  const std::lock_guard lock(oiio_calls);
  // The source as it is stored; the result in float, so no precision is lost to the filter.
  const OIIO::TypeDesc stored = !pixels.bytes.empty()    ? OIIO::TypeDesc::UINT8
                                : !pixels.shorts.empty() ? OIIO::TypeDesc::UINT16
                                                         : OIIO::TypeDesc::FLOAT;
  const void* data = !pixels.bytes.empty()    ? static_cast<const void*>(pixels.bytes.data())
                     : !pixels.shorts.empty() ? static_cast<const void*>(pixels.shorts.data())
                                              : static_cast<const void*>(pixels.floats.data());
  OIIO::ImageSpec source_spec(pixels.width, pixels.height, pixels.channels, stored);
  OIIO::ImageBuf source(source_spec, const_cast<void*>(data));
  OIIO::ImageSpec target_spec(width, height, pixels.channels, OIIO::TypeDesc::FLOAT);
  OIIO::ImageBuf target(target_spec);
  // A triangle filter does not ring, so resampled texels stay inside the input's range.
  OIIO::ImageBufAlgo::resize(target, source, "triangle", 0.0f);
  Pixels out;
  out.width = width;
  out.height = height;
  out.channels = pixels.channels;
  out.bits = pixels.bits;
  out.floats.resize(static_cast<size_t>(width) * static_cast<size_t>(height) * static_cast<size_t>(pixels.channels));
  target.get_pixels(OIIO::ROI::All(), OIIO::TypeDesc::FLOAT, out.floats.data());
  return out;
}

}  // namespace
}  // namespace gltf_pbr

extern "C" __attribute__((visibility("default"))) const gltf_pbr::ImageCodec* gltf_pbr_image_codec() {
  // Our callers already run one image per core (core/parallel.hpp). OpenImageIO's own thread pool
  // would oversubscribe the cores and leave idle threads alive at exit, where LeakSanitizer's
  // tracer has crashed suspending them on CI machines.
  static const bool single_threaded = OIIO_NAMESPACE::attribute("threads", 1);
  (void)single_threaded;
  static const gltf_pbr::ImageCodec codec{&gltf_pbr::decode_with_oiio, &gltf_pbr::resample_with_oiio};
  return &codec;
}
