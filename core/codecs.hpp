// The lean codecs behind core/image.hpp for the two formats core glTF allows: libspng for PNG
// (with libdeflate's inflate and deflate) and libjpeg-turbo (TurboJPEG) for JPEG, called directly
// (DESIGN.md "Images: which library does what"). Only core/image.cpp (and the codecs' tests) call
// these; everyone else goes through decode_image / encode_png (filter_png, deflate_png) /
// encode_jpeg.
#pragma once
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/image.hpp"

namespace gltf_pbr::codecs {

// Each decoder reads the header, refuses an image above `max_pixels` before allocating, and throws
// std::runtime_error with the reason on a corrupt or truncated stream (never returns partial texels).
// PngInflater::Libspng decodes every PNG through libspng alone: the reference that the libdeflate
// path is tested against.
enum class PngInflater { Libdeflate, Libspng };
Pixels decode_png(std::span<const std::uint8_t> encoded, std::uint64_t max_pixels,
                  PngInflater inflater = PngInflater::Libdeflate);
// std::nullopt for a JPEG that TurboJPEG cannot turn into RGB or grey (CMYK, YCCK): OpenImageIO reads those.
std::optional<Pixels> decode_jpeg(std::span<const std::uint8_t> encoded, std::uint64_t max_pixels);

FilteredPng filter_png(std::span<const std::uint8_t> texels, int width, int height, int channels,
                       TexelBytes* release = nullptr);  // freed (and `texels` with it) once filtered
FilteredPng filter_palette_png(std::span<const std::uint8_t> indices, std::span<const std::uint32_t> palette, int width,
                               int height);
Bytes deflate_png(FilteredPng&& filtered, int compression_level);
Bytes encode_jpeg(std::span<const std::uint8_t> texels, int width, int height, int channels, int quality);
std::optional<std::vector<std::uint32_t>> png_palette(std::span<const std::uint8_t> png);
std::optional<Bytes> png_with_palette(std::span<const std::uint8_t> png, std::span<const std::uint32_t> palette);

// The header's size refused against the limit, for every decoder alike.
std::string too_large(std::uint64_t width, std::uint64_t height, std::uint64_t max_pixels);

}  // namespace gltf_pbr::codecs
