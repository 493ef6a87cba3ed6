// Picks the codec by signature: PNG and JPEG through core/codecs.hpp, the rest through the
// OpenImageIO module, loaded on first use (see core/image_oiio.cpp for why).
#include "core/image.hpp"

#include <dlfcn.h>
#include <link.h>
#include <unistd.h>
#include <xxhash.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <new>
#include <optional>
#include <stdexcept>

#include "core/asset.hpp"
#include "core/codecs.hpp"
#include "core/image_header.hpp"
#include "core/json_pointer.hpp"

namespace gltf_pbr {
namespace {

constexpr const char* kModuleName = "libgltf_pbr_images.so";

// The folder of the file this code was loaded from: the executable (the tool, a test), or the
// shared library libgltf_pbr.so when a program or Python links that instead.
fs::path own_folder() {
  Dl_info info;
  link_map* object = nullptr;
  std::error_code ec;
  if (::dladdr1(reinterpret_cast<void*>(&own_folder), &info, reinterpret_cast<void**>(&object), RTLD_DL_LINKMAP) &&
      object && object->l_name && object->l_name[0]) {  // the main program's entry has no name
    // A library never looks beside the program that loaded it: that may hold another version.
    const fs::path library = fs::canonical(object->l_name, ec);
    return (ec ? fs::absolute(object->l_name, ec) : library).parent_path();
  }
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : self.parent_path();
}

// Looks beside its own file, then in ../lib/gltf-pbr (the installed layout: from bin/ for the
// tool, from lib/ itself for the library), and, only for a program or library inside the build tree (the
// tool, tests, benchmarks), in the build tree: an installed copy never reads a build folder that
// may be gone or hold another version.
const ImageCodec& codec() {
  static const ImageCodec* loaded = [] {
    std::vector<fs::path> candidates;
    if (const char* override_path = std::getenv("GLTF_PBR_IMAGE_MODULE")) candidates.emplace_back(override_path);
    const fs::path here = own_folder();
    candidates.push_back(here / kModuleName);
    candidates.push_back((here / ".." / "lib" / "gltf-pbr" / kModuleName).lexically_normal());
    // /proc/self/exe has its symlinks resolved; the build folder's path as CMake wrote it may not.
    const fs::path build = fs::weakly_canonical(fs::path(GLTF_PBR_BUILD_DIR));
    const auto [build_end, here_end] = std::mismatch(build.begin(), build.end(), here.begin(), here.end());
    if (build_end == build.end()) candidates.push_back(build / kModuleName);
    std::string tried;
    for (const fs::path& candidate : candidates) {
      if (!fs::exists(candidate)) continue;
      void* module = ::dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (!module) {
        tried += std::string(" ") + ::dlerror();
        continue;
      }
      using Entry = const ImageCodec* (*)();
      if (auto entry = reinterpret_cast<Entry>(::dlsym(module, "gltf_pbr_image_codec"))) return entry();
    }
    throw std::runtime_error("cannot load the image module " + std::string(kModuleName) + tried);
  }();
  return *loaded;
}

std::atomic<std::uint64_t> max_pixels{kDefaultMaxImagePixels};

}  // namespace

void set_max_image_pixels(std::uint64_t pixels) { max_pixels = pixels; }
std::uint64_t max_image_pixels() { return max_pixels; }

Pixels decode_image(std::span<const std::uint8_t> encoded, const std::string& name_for_errors) {
  Pixels pixels;
  try {
    const ImageFormat format = image_format_of(encoded);
    if (format == ImageFormat::Png) {
      pixels = codecs::decode_png(encoded, max_pixels);
    } else if (std::optional<Pixels> jpeg;
               format == ImageFormat::Jpeg && (jpeg = codecs::decode_jpeg(encoded, max_pixels))) {
      pixels = std::move(*jpeg);
    } else {
      pixels = codec().decode(encoded, max_pixels);
    }
  } catch (const std::runtime_error& error) {
    throw std::runtime_error("cannot decode image " + name_for_errors + ": " + error.what());
  } catch (const std::exception& error) {  // bad_alloc, length_error: a library's own buffers past our checks
    throw std::runtime_error("cannot decode image " + name_for_errors + ": it needs more memory than there is (" +
                             error.what() + ")");
  }
  ++work_counters().images_decoded;
  return pixels;
}

Pixels decode_image_with_openimageio(std::span<const std::uint8_t> encoded) {
  return codec().decode(encoded, ~std::uint64_t{0});
}

Pixels resize(const Pixels& pixels, int width, int height) {
  if (pixels.width == width && pixels.height == height) return pixels;
  return codec().resample(pixels, width, height);
}

TexelGrid bake_grid(std::span<const Pixels* const> textures) {
  TexelGrid grid;
  for (const Pixels* pixels : textures)
    if (pixels) grid.width = std::max(grid.width, pixels->width), grid.height = std::max(grid.height, pixels->height);
  return grid;
}

Bytes encode_png(std::span<const std::uint8_t> texels, int width, int height, int channels, int compression_level) {
  return deflate_png(filter_png(texels, width, height, channels), compression_level);
}

Bytes encode_png(TexelBytes&& texels, int width, int height, int channels, int compression_level) {
  return deflate_png(filter_png(std::move(texels), width, height, channels), compression_level);
}

FilteredPng filter_png(std::span<const std::uint8_t> texels, int width, int height, int channels) {
  return codecs::filter_png(texels, width, height, channels);
}

FilteredPng filter_palette_png(std::span<const std::uint8_t> indices, std::span<const std::uint32_t> palette, int width,
                               int height) {
  return codecs::filter_palette_png(indices, palette, width, height);
}

FilteredPng filter_png(TexelBytes&& texels, int width, int height, int channels) {
  TexelBytes owned = std::move(texels);
  return codecs::filter_png(owned, width, height, channels, &owned);
}

Bytes deflate_png(FilteredPng&& filtered, int compression_level) {
  return codecs::deflate_png(std::move(filtered), compression_level);
}

std::optional<std::vector<std::uint32_t>> png_palette(std::span<const std::uint8_t> png) {
  return codecs::png_palette(png);
}

std::optional<Bytes> png_with_palette(std::span<const std::uint8_t> png, std::span<const std::uint32_t> palette) {
  return codecs::png_with_palette(png, palette);
}

Bytes encode_jpeg(std::span<const std::uint8_t> texels, int width, int height, int channels, int quality) {
  return codecs::encode_jpeg(texels, width, height, channels, quality);
}

ImageContentKey image_content_key(std::span<const std::uint8_t> encoded) {
  const XXH128_hash_t hash = XXH3_128bits(encoded.data(), encoded.size());
  return {hash.low64, hash.high64, encoded.size()};
}

const Pixels& DecodedImages::get(const Asset& asset, int image) {
  const std::lock_guard lock(mutex_);  // its readers are sequential: held through a decode, it decodes once
  if (const auto it = by_image_.find({&asset, image}); it != by_image_.end()) return *it->second;
  const std::span<const std::uint8_t> encoded = encoded_image_bytes(asset, image);
  const ImageContentKey key = image_content_key(encoded);
  auto held = by_content_.find(key);
  if (held == by_content_.end())
    held =
        by_content_.emplace(key, std::make_shared<const Pixels>(decode_image(encoded, pointer("images", image)))).first;
  release_encoded_image_pages(asset, image);  // also after a hash alone: the pixels are held either way
  by_image_.emplace(std::make_pair(&asset, image), held->second.get());
  return *held->second;
}

void DecodedImages::forget(const ImageContentKey& key) {
  const std::lock_guard lock(mutex_);
  const auto held = by_content_.find(key);
  if (held == by_content_.end()) return;
  for (const auto& [image, pixels] : by_image_)
    if (pixels == held->second.get()) return;  // a reference get() gave out lives as long as this object
  by_content_.erase(held);
}

void DecodedImages::keep(const ImageContentKey& key, std::shared_ptr<const Pixels> pixels) {
  const std::lock_guard lock(mutex_);
  by_content_.try_emplace(key, std::move(pixels));
}

std::shared_ptr<const Pixels> DecodedImages::find(const ImageContentKey& key) const {
  const std::lock_guard lock(mutex_);
  const auto it = by_content_.find(key);
  return it == by_content_.end() ? nullptr : it->second;
}

void DecodedImages::clear() {
  const std::lock_guard lock(mutex_);
  by_content_.clear();
  by_image_.clear();
}

}  // namespace gltf_pbr
