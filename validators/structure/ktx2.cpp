// KTX2 images (KHR_texture_basisu): the reference validator only recognises the signature; we read
// the container far enough to know it is whole and what KHR_texture_basisu allows. No Debian package
// transcodes Basis Universal, so the texels themselves are not read (the material step says so).
//   KTX File Format Specification, version 2 (Khronos), sections 3 "File Structure" (header, index,
//   level index), 3.4 supercompressionScheme, 3.9 Data Format Descriptor; KHR_texture_basisu README,
//   "KTX v2 Images with Basis Universal Supercompression".
#include "validators/structure/images.hpp"

namespace gltf_pbr::structure {

namespace {

std::uint32_t u32(std::span<const std::uint8_t> b, std::size_t at) {
  return std::uint32_t(b[at]) | (std::uint32_t(b[at + 1]) << 8) | (std::uint32_t(b[at + 2]) << 16) |
         (std::uint32_t(b[at + 3]) << 24);
}
std::uint64_t u64(std::span<const std::uint8_t> b, std::size_t at) {
  return std::uint64_t(u32(b, at)) | (std::uint64_t(u32(b, at + 4)) << 32);
}

// Whether [offset, offset + length) lies inside `size` bytes, without overflow.
bool inside(std::uint64_t offset, std::uint64_t length, std::uint64_t size) {
  return offset <= size && length <= size - offset;
}

constexpr std::size_t kHeaderBytes = 80;  // identifier, header and index (section 3)
constexpr std::uint32_t kModelEtc1s = 163, kModelUastc = 166;  // KHR_DF_MODEL_ETC1S, KHR_DF_MODEL_UASTC

}  // namespace

std::vector<Ktx2Finding> check_ktx2(std::span<const std::uint8_t> b) {
  std::vector<Ktx2Finding> found;
  auto container = [&](std::string reason) { found.push_back({"KTX2_INVALID_CONTAINER", std::move(reason)}); };
  auto basisu = [&](std::string reason) { found.push_back({"KTX2_BASISU_MISMATCH", std::move(reason)}); };
  const std::uint64_t size = b.size();
  if (size < kHeaderBytes) {
    container("the file ends at byte " + std::to_string(size) + ", inside the 80-byte header");
    return found;
  }
  const std::uint32_t vk_format = u32(b, 12), width = u32(b, 20), height = u32(b, 24), depth = u32(b, 28),
                      layers = u32(b, 32), faces = u32(b, 36), levels = u32(b, 40), scheme = u32(b, 44);
  const std::uint32_t dfd_offset = u32(b, 48), dfd_length = u32(b, 52), kvd_offset = u32(b, 56),
                      kvd_length = u32(b, 60);
  const std::uint64_t sgd_offset = u64(b, 64), sgd_length = u64(b, 72);

  // Section 3: the header's own fields.
  if (width == 0) container("pixelWidth is 0");
  if (faces != 1 && faces != 6) container("faceCount " + std::to_string(faces) + " is neither 1 nor 6");
  int max_levels = 0;
  for (std::uint32_t largest = std::max({width, height, depth}); largest > 0; largest >>= 1) ++max_levels;
  if (levels > static_cast<std::uint32_t>(max_levels))
    container("levelCount " + std::to_string(levels) + " is more than the " + std::to_string(max_levels) +
              " levels a " + std::to_string(width) + "x" + std::to_string(height) + "x" + std::to_string(depth) +
              " image has");
  // Section 3.4: 0-3 are defined, 0x10000-0x1FFFF belong to vendors, the rest is reserved.
  if (scheme > 3 && (scheme < 0x10000 || scheme > 0x1FFFF))
    container("supercompressionScheme " + std::to_string(scheme) +
              " is reserved: none of 0 (none), 1 (BasisLZ), 2 (Zstandard), 3 (ZLIB) or a vendor's 0x10000-0x1FFFF");

  // Section 3.1 index: every range inside the file. The DFD is required: its total size (which
  // it starts with), then at least a basic descriptor block of 24 bytes and one 16-byte sample.
  constexpr std::uint32_t kSmallestDfd = 4 + 24 + 16;
  if (dfd_length == 0)
    container("there is no Data Format Descriptor (dfdByteLength 0)");
  else if (!inside(dfd_offset, dfd_length, size))
    container("the Data Format Descriptor (bytes " + std::to_string(dfd_offset) + " + " + std::to_string(dfd_length) +
              ") runs past the end of the file (" + std::to_string(size) + " bytes)");
  else if (dfd_length < kSmallestDfd)
    container("the Data Format Descriptor is " + std::to_string(dfd_length) + " bytes, shorter than the " +
              std::to_string(kSmallestDfd) + " of a basic block with one sample");
  else if (u32(b, dfd_offset) != dfd_length)
    container("the Data Format Descriptor says it is " + std::to_string(u32(b, dfd_offset)) +
              " bytes, the index says " + std::to_string(dfd_length));
  if (kvd_length > 0 && !inside(kvd_offset, kvd_length, size))
    container("the key/value data (bytes " + std::to_string(kvd_offset) + " + " + std::to_string(kvd_length) +
              ") runs past the end of the file (" + std::to_string(size) + " bytes)");
  if (sgd_length > 0 && !inside(sgd_offset, sgd_length, size))
    container("the supercompression global data (bytes " + std::to_string(sgd_offset) + " + " +
              std::to_string(sgd_length) + ") runs past the end of the file (" + std::to_string(size) + " bytes)");
  if (scheme == 1 && sgd_length == 0) container("BasisLZ (supercompressionScheme 1) without its global data");

  // Section 3.2 level index: max(1, levelCount) entries of 24 bytes after the header, each level
  // inside the file. Only a valid levelCount is walked, so a hostile one reads nothing more.
  const std::uint32_t entries = std::max<std::uint32_t>(levels, 1);
  if (levels <= static_cast<std::uint32_t>(max_levels)) {
    if (!inside(kHeaderBytes, std::uint64_t{entries} * 24, size)) {
      container("the level index of " + std::to_string(entries) + " levels runs past the end of the file (" +
                std::to_string(size) + " bytes)");
    } else {
      for (std::uint32_t level = 0; level < entries; ++level) {
        const std::uint64_t offset = u64(b, kHeaderBytes + level * 24), length = u64(b, kHeaderBytes + level * 24 + 8);
        if (length == 0 || !inside(offset, length, size)) {
          container("mip level " + std::to_string(level) + " (bytes " + std::to_string(offset) + " + " +
                    std::to_string(length) + ") " + (length == 0 ? "is empty" : "runs past the end of the file (") +
                    (length == 0 ? "" : std::to_string(size) + " bytes)"));
          break;  // one level says it: the file is cut or the index is wrong
        }
      }
    }
  }

  // KHR_texture_basisu: Basis Universal payloads in a 2D image whose sides are multiples of 4.
  if (vk_format != 0) basisu("vkFormat is " + std::to_string(vk_format) + ", not VK_FORMAT_UNDEFINED (0)");
  if (height == 0 || depth != 0 || layers != 0 || faces != 1)
    basisu("the image is not 2D (pixelHeight " + std::to_string(height) + ", pixelDepth " + std::to_string(depth) +
           ", layerCount " + std::to_string(layers) + ", faceCount " + std::to_string(faces) + ")");
  if (width % 4 != 0 || height % 4 != 0)
    basisu("pixelWidth and pixelHeight " + std::to_string(width) + "x" + std::to_string(height) +
           " are not multiples of 4");
  // Section 3.9: the DFD's total size, then the basic descriptor block, whose colorModel is byte 8.
  if (dfd_length >= kSmallestDfd && inside(dfd_offset, dfd_length, size)) {
    const std::uint32_t model = b[dfd_offset + 4 + 8];
    if (model == kModelEtc1s && scheme != 1)
      basisu("ETC1S data needs supercompressionScheme 1 (BasisLZ), not " + std::to_string(scheme));
    else if (model == kModelUastc && scheme != 0 && scheme != 2)
      basisu("UASTC data needs supercompressionScheme 0 or 2 (Zstandard), not " + std::to_string(scheme));
    else if (model != kModelEtc1s && model != kModelUastc)
      basisu("the DFD's colorModel " + std::to_string(model) + " is neither ETC1S (163) nor UASTC (166)");
  }
  return found;
}

}  // namespace gltf_pbr::structure
