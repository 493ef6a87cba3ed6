// Environment files: Radiance .hdr read here, other formats through core/image.hpp (see environment.hpp).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <glm/common.hpp>
#include <stdexcept>
#include <string>

#include "core/files.hpp"
#include "core/image.hpp"
#include "preview/environment.hpp"

namespace gltf_pbr::preview {

EquirectMap read_radiance_hdr(const std::vector<std::uint8_t>& bytes, const std::string& name) {
  auto fail = [&](const std::string& why) { return std::runtime_error(name + ": " + why); };
  size_t pos = 0;
  auto read_line = [&]() {
    std::string line;
    while (pos < bytes.size() && bytes[pos] != '\n') line += static_cast<char>(bytes[pos++]);
    if (pos >= bytes.size()) throw fail("truncated header");
    ++pos;
    return line;
  };
  if (read_line().rfind("#?", 0) != 0) throw fail("not a Radiance .hdr file");
  for (std::string line; !(line = read_line()).empty();)
    if (line.rfind("FORMAT=", 0) == 0 && line != "FORMAT=32-bit_rle_rgbe")
      throw fail("unsupported " + line + " (only 32-bit_rle_rgbe)");
  int width = 0, height = 0;
  char y_axis[3] = {}, x_axis[3] = {};
  const std::string resolution = read_line();
  if (std::sscanf(resolution.c_str(), "%2s %d %2s %d", y_axis, &height, x_axis, &width) != 4 ||
      std::strcmp(y_axis, "-Y") != 0 || std::strcmp(x_axis, "+X") != 0 || width <= 0 || height <= 0)
    throw fail("unsupported resolution line '" + resolution + "' (only -Y H +X W)");
  // Nothing is allocated for a size the limit refuses or the bytes cannot hold: each scanline takes
  // at least 4 bytes a pixel flat, or its 4-byte mark and a two-byte run per 127 pixels of each
  // channel run-length encoded.
  const auto pixels = static_cast<std::uint64_t>(width) * static_cast<std::uint64_t>(height);
  if (pixels > max_image_pixels())
    throw fail("the image is " + std::to_string(width) + "x" + std::to_string(height) + " pixels, above the limit of " +
               std::to_string(max_image_pixels()) + " (--max-image-pixels)");
  const std::uint64_t least_per_line = width >= 8 && width < 32768
                                           ? 4 + 4 * 2 * ((static_cast<std::uint64_t>(width) + 126) / 127)
                                           : 4 * static_cast<std::uint64_t>(width);
  if (least_per_line * static_cast<std::uint64_t>(height) > bytes.size() - pos) throw fail("truncated pixel data");
  EquirectMap map{width, height, std::vector<glm::vec3>(static_cast<size_t>(width) * static_cast<size_t>(height))};
  std::vector<std::uint8_t> scanline(static_cast<size_t>(width) * 4);
  for (int y = 0; y < height; ++y) {
    const bool rle = width >= 8 && width < 32768 && pos + 4 <= bytes.size() && bytes[pos] == 2 && bytes[pos + 1] == 2 &&
                     ((bytes[pos + 2] << 8) | bytes[pos + 3]) == width;
    if (rle) {  // adaptive run-length encoding, one channel at a time
      pos += 4;
      for (int c = 0; c < 4; ++c)
        for (int x = 0; x < width;) {
          if (pos >= bytes.size()) throw fail("truncated pixel data");
          int count = bytes[pos++];
          if (count > 128) {
            count -= 128;
            if (count > width - x || pos >= bytes.size()) throw fail("bad run length");
            const std::uint8_t value = bytes[pos++];
            for (int k = 0; k < count; ++k) scanline[static_cast<size_t>((x++) * 4 + c)] = value;
          } else {
            if (count == 0 || count > width - x || pos + static_cast<size_t>(count) > bytes.size())
              throw fail("bad literal length");
            for (int k = 0; k < count; ++k) scanline[static_cast<size_t>((x++) * 4 + c)] = bytes[pos++];
          }
        }
    } else {
      if (pos + scanline.size() > bytes.size()) throw fail("truncated pixel data");
      std::copy_n(bytes.begin() + static_cast<std::ptrdiff_t>(pos), scanline.size(), scanline.begin());
      pos += scanline.size();
    }
    for (int x = 0; x < width; ++x) {
      const std::uint8_t* rgbe = scanline.data() + static_cast<size_t>(x) * 4;
      const float scale = rgbe[3] == 0 ? 0.0f : std::ldexp(1.0f, rgbe[3] - (128 + 8));
      map.at(x, y) = glm::vec3(rgbe[0] + 0.5f, rgbe[1] + 0.5f, rgbe[2] + 0.5f) * scale;
    }
  }
  return map;
}

Environment load_environment(const std::filesystem::path& path) {
  const auto bytes = read_file(path);
  if (!bytes) throw std::runtime_error(path.string() + ": cannot read the environment file");
  EquirectMap map;
  if (bytes->size() >= 2 && (*bytes)[0] == '#' && (*bytes)[1] == '?') {
    map = read_radiance_hdr(*bytes, path.string());
  } else {
    const Pixels pixels = decode_image(*bytes, path.string());
    map.width = pixels.width;
    map.height = pixels.height;
    map.texels.resize(static_cast<size_t>(pixels.width) * static_cast<size_t>(pixels.height));
    for (int y = 0; y < pixels.height; ++y)
      for (int x = 0; x < pixels.width; ++x)
        map.at(x, y) = glm::vec3(pixels.at(x, y, 0), pixels.at(x, y, std::min(1, pixels.channels - 1)),
                                 pixels.at(x, y, std::min(2, pixels.channels - 1)));
  }
  for (glm::vec3& t : map.texels)
    if (!std::isfinite(t.x + t.y + t.z))
      t = glm::vec3(0.0f);  // never let NaN/Inf into the image
    else
      t = glm::max(t, glm::vec3(0.0f));
  return build_environment(map);
}

}  // namespace gltf_pbr::preview
