// KTX2 images (KHR_texture_basisu): the reference validator only recognises the signature; we read
// the container far enough to know it is whole and what KHR_texture_basisu allows. No Debian package
// transcodes Basis Universal, so the texels themselves are not read (the material step says so).
//   KTX File Format Specification, version 2 (Khronos): "File Structure", "Header", "Index",
//   "Level Index", "Data Format Descriptor", "Key/Value Data", "Mip Level Array" and the
//   supercompression schemes; Khronos Data Format Specification 1.3, section 5 "Basic descriptor
//   block"; KHR_texture_basisu README, "KTX v2 Images with Basis Universal Supercompression".
#include <algorithm>

#include "core/byte_order.hpp"
#include "validators/structure/images.hpp"

namespace gltf_pbr::structure {

namespace {

// Whether [offset, offset + length) lies inside `size` bytes, without overflow.
bool inside(std::uint64_t offset, std::uint64_t length, std::uint64_t size) {
  return offset <= size && length <= size - offset;
}

std::string str(std::uint64_t value) { return std::to_string(value); }

constexpr std::size_t kHeaderBytes = 80;      // identifier, header and index
constexpr std::size_t kLevelEntryBytes = 24;  // byteOffset, byteLength, uncompressedByteLength
constexpr std::uint32_t kSchemeNone = 0, kSchemeBasisLz = 1, kSchemeZstandard = 2;
// The Data Format Descriptor starts with its total size, then the basic descriptor block: 24 bytes
// (colorModel at byte 8, colorPrimaries 9, transferFunction 10, flags 11, descriptorBlockSize a
// 16-bit value at 6), then one 16-byte sample per channel, whose byte 3 holds the channel id in its
// low four bits.
constexpr std::size_t kBlockBytes = 24, kSampleBytes = 16;
constexpr std::uint32_t kSmallestDfd = 4 + kBlockBytes + kSampleBytes;
constexpr std::uint8_t kModelEtc1s = 163, kModelUastc = 166;  // KHR_DF_MODEL_ETC1S, KHR_DF_MODEL_UASTC
constexpr std::uint8_t kPrimariesUnspecified = 0, kPrimariesBt709 = 1;
constexpr std::uint8_t kTransferLinear = 1, kTransferSrgb = 2;
constexpr std::uint8_t kFlagAlphaPremultiplied = 1;
constexpr std::uint8_t kChannelRgb = 0;  // KHR_DF_CHANNEL_ETC1S_RGB and KHR_DF_CHANNEL_UASTC_RGB
constexpr std::uint8_t kChannelEtc1sAaa = 15, kChannelUastcRgba = 3;
constexpr std::uint64_t kUastcBlockBytes = 16;  // one 4x4 block

// A key from the file, bounded for a message (the report escapes what it shows).
std::string quoted(std::span<const std::uint8_t> text) {
  constexpr std::size_t kShown = 64;
  std::string out(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(std::min(text.size(), kShown)));
  return "'" + out + (text.size() > kShown ? "...'" : "'");
}

struct Level {
  std::uint64_t offset, length, uncompressed;
};

class Ktx2Checker {
 public:
  Ktx2Checker(std::span<const std::uint8_t> bytes, const ImageUse& use) : b_(bytes), use_(use) {}

  std::vector<Ktx2Finding> run() {
    if (b_.size() < kHeaderBytes) {
      container("the file ends at byte " + str(b_.size()) + ", inside the 80-byte header");
      return std::move(found_);
    }
    vk_format_ = little_endian32(b_, 12);
    width_ = little_endian32(b_, 20);
    height_ = little_endian32(b_, 24);
    depth_ = little_endian32(b_, 28);
    layers_ = little_endian32(b_, 32);
    faces_ = little_endian32(b_, 36);
    level_count_ = little_endian32(b_, 40);
    scheme_ = little_endian32(b_, 44);
    for (std::uint32_t largest = std::max({width_, height_, depth_}); largest > 0; largest >>= 1) ++full_levels_;
    header();
    index();
    const bool levels_whole = level_index();
    const bool dfd_whole = data_format_descriptor();
    key_value_data();
    basisu();
    if (levels_whole && dfd_whole) uastc_level_sizes();
    mipmaps();
    return std::move(found_);
  }

 private:
  void container(std::string reason) { found_.push_back({"KTX2_INVALID_CONTAINER", std::move(reason)}); }
  void mismatch(std::string reason) { found_.push_back({"KTX2_BASISU_MISMATCH", std::move(reason)}); }
  bool two_d() const { return height_ != 0 && depth_ == 0 && layers_ == 0 && faces_ == 1; }
  bool level_count_valid() const { return level_count_ <= static_cast<std::uint32_t>(full_levels_); }

  // "Header": the fields' own ranges, and the supercompression schemes: 0-3 are defined,
  // 0x10000-0x1FFFF belong to vendors, the rest is reserved.
  void header() {
    if (width_ == 0) container("pixelWidth is 0");
    if (faces_ != 1 && faces_ != 6) container("faceCount " + str(faces_) + " is neither 1 nor 6");
    if (!level_count_valid())
      container("levelCount " + str(level_count_) + " is more than the " + str(full_levels_) + " levels a " +
                str(width_) + "x" + str(height_) + "x" + str(depth_) + " image has");
    if (scheme_ > 3 && (scheme_ < 0x10000 || scheme_ > 0x1FFFF))
      container("supercompressionScheme " + str(scheme_) +
                " is reserved: none of 0 (none), 1 (BasisLZ), 2 (Zstandard), 3 (ZLIB) or a vendor's 0x10000-0x1FFFF");
  }

  // "Index": every range inside the file. The DFD is required: its total size (which it starts
  // with), then at least a basic descriptor block with one sample.
  void index() {
    const std::uint64_t size = b_.size();
    const std::uint32_t dfd_offset = little_endian32(b_, 48), dfd_length = little_endian32(b_, 52);
    const std::uint32_t kvd_offset = little_endian32(b_, 56), kvd_length = little_endian32(b_, 60);
    const std::uint64_t sgd_offset = little_endian64(b_, 64), sgd_length = little_endian64(b_, 72);
    if (dfd_length == 0)
      container("there is no Data Format Descriptor (dfdByteLength 0)");
    else if (!inside(dfd_offset, dfd_length, size))
      container("the Data Format Descriptor (bytes " + str(dfd_offset) + " + " + str(dfd_length) +
                ") runs past the end of the file (" + str(size) + " bytes)");
    else if (dfd_length < kSmallestDfd)
      container("the Data Format Descriptor is " + str(dfd_length) + " bytes, shorter than the " + str(kSmallestDfd) +
                " of a basic block with one sample");
    else if (little_endian32(b_, dfd_offset) != dfd_length)
      container("the Data Format Descriptor says it is " + str(little_endian32(b_, dfd_offset)) + " bytes, the index says " +
                str(dfd_length));
    else
      dfd_ = b_.subspan(dfd_offset, dfd_length);
    if (kvd_length > 0 && !inside(kvd_offset, kvd_length, size))
      container("the key/value data (bytes " + str(kvd_offset) + " + " + str(kvd_length) +
                ") runs past the end of the file (" + str(size) + " bytes)");
    else if (kvd_length > 0)
      kvd_ = b_.subspan(kvd_offset, kvd_length);
    if (sgd_length > 0 && !inside(sgd_offset, sgd_length, size))
      container("the supercompression global data (bytes " + str(sgd_offset) + " + " + str(sgd_length) +
                ") runs past the end of the file (" + str(size) + " bytes)");
    if (scheme_ == kSchemeBasisLz && sgd_length == 0)
      container("BasisLZ (supercompressionScheme 1) without its global data");
  }

  // "Level Index": max(1, levelCount) entries after the header, each level inside the file, with
  // uncompressedByteLength equal to byteLength without supercompression and 0 with BasisLZ.
  // "Mip Level Array": the levels are stored from the smallest to the largest. Only a valid
  // levelCount is walked, so a hostile one reads nothing more. True when every level is whole.
  bool level_index() {
    if (!level_count_valid()) return false;
    const std::uint64_t size = b_.size(), entries = std::max<std::uint32_t>(level_count_, 1);
    if (!inside(kHeaderBytes, entries * kLevelEntryBytes, size)) {
      container("the level index of " + str(entries) + " levels runs past the end of the file (" + str(size) +
                " bytes)");
      return false;
    }
    bool said_uncompressed = false, said_order = false;
    for (std::size_t level = 0; level < entries; ++level) {
      const std::size_t at = kHeaderBytes + level * kLevelEntryBytes;
      const Level entry{little_endian64(b_, at), little_endian64(b_, at + 8), little_endian64(b_, at + 16)};
      const std::string name = "mip level " + str(level);
      if (entry.length == 0 || !inside(entry.offset, entry.length, size)) {
        container(name + " (bytes " + str(entry.offset) + " + " + str(entry.length) + ") " +
                  (entry.length == 0 ? "is empty" : "runs past the end of the file (" + str(size) + " bytes)"));
        return false;  // one level says it: the file is cut or the index is wrong
      }
      // Said once for the first level it fits, as one writer's habit repeats on every level.
      if (!said_uncompressed && scheme_ == kSchemeNone && entry.uncompressed != entry.length) {
        container(name + "'s uncompressedByteLength " + str(entry.uncompressed) + " is not its byteLength " +
                  str(entry.length) + ", as it must be without supercompression");
        said_uncompressed = true;
      }
      if (!said_uncompressed && scheme_ == kSchemeBasisLz && entry.uncompressed != 0) {
        container(name + "'s uncompressedByteLength is " + str(entry.uncompressed) + ", not 0 as BasisLZ needs");
        said_uncompressed = true;
      }
      if (!said_order && !levels_.empty() && entry.offset + entry.length > levels_.back().offset) {
        container(name + " (bytes " + str(entry.offset) + " + " + str(entry.length) +
                  ") is not stored before mip level " + str(level - 1) + " (byte " + str(levels_.back().offset) +
                  "): the mip level array runs from the smallest level to the largest");
        said_order = true;
      }
      levels_.push_back(entry);
    }
    return true;
  }

  // The basic descriptor block's own size against the DFD's, then its samples' channel ids.
  // True when the block and its samples can be read.
  bool data_format_descriptor() {
    if (dfd_.empty()) return false;
    const std::uint32_t block_size = dfd_[4 + 6] | (dfd_[4 + 7] << 8);
    if (block_size < kBlockBytes + kSampleBytes || block_size > dfd_.size() - 4 ||
        (block_size - kBlockBytes) % kSampleBytes != 0) {
      container("the basic descriptor block says it is " + str(block_size) + " bytes; it holds 24 and one 16-byte " +
                "sample per channel within the " + str(dfd_.size() - 4) + " bytes after the DFD's size");
      return false;
    }
    for (std::size_t at = 4 + kBlockBytes; at < 4 + block_size; at += kSampleBytes)
      channels_.push_back(dfd_[at + 3] & 0x0F);
    return true;
  }

  // "Key/Value Data": entries of a 32-bit length, a NUL-terminated key and its value, each padded
  // to 4 bytes, sorted by key (byte order) without repeats. KHR_texture_basisu allows only the
  // default orientation and swizzle: KTXorientation "rd", KTXswizzle "rgba".
  void key_value_data() {
    std::size_t at = 0;
    std::span<const std::uint8_t> previous;
    while (at < kvd_.size()) {
      if (kvd_.size() - at < 4) {
        container("the key/value data ends inside an entry's length, " + str(at) + " bytes in");
        return;
      }
      const std::uint32_t length = little_endian32(kvd_, at);
      if (length > kvd_.size() - at - 4) {
        container("the key/value entry " + str(at) + " bytes in (" + str(length) +
                  " bytes) runs past the end of the key/value data (" + str(kvd_.size()) + " bytes)");
        return;
      }
      const std::span<const std::uint8_t> entry = kvd_.subspan(at + 4, length);
      const auto nul = std::find(entry.begin(), entry.end(), std::uint8_t{0});
      if (nul == entry.end()) {
        container("the key/value entry " + str(at) + " bytes in has no NUL to end its key");
        return;
      }
      const std::span<const std::uint8_t> key = entry.first(static_cast<std::size_t>(nul - entry.begin()));
      std::span<const std::uint8_t> value = entry.subspan(key.size() + 1);
      if (!previous.empty() && !std::lexicographical_compare(previous.begin(), previous.end(), key.begin(), key.end()))
        container("the key/value data is not sorted by key without repeats: " + quoted(key) + " follows " +
                  quoted(previous));
      if (!value.empty() && value.back() == 0) value = value.first(value.size() - 1);  // a string value's NUL
      auto is = [](std::span<const std::uint8_t> text, std::string_view expected) {
        return std::equal(text.begin(), text.end(), expected.begin(), expected.end());
      };
      if (is(key, "KTXorientation") && !is(value, "rd"))
        mismatch("KTXorientation is " + quoted(value) + "; KHR_texture_basisu allows only 'rd' or none");
      if (is(key, "KTXswizzle") && !is(value, "rgba"))
        mismatch("KTXswizzle is " + quoted(value) + "; KHR_texture_basisu allows only 'rgba' or none");
      previous = key;
      at += 4 + ((std::size_t{length} + 3) & ~std::size_t{3});
    }
  }

  // KHR_texture_basisu: Basis Universal payloads (ETC1S with BasisLZ, or UASTC with no or Zstandard
  // supercompression, with the channels each allows) in a 2D image whose sides are multiples of 4,
  // without premultiplied alpha (no core material's alpha is), in the colour space of its use.
  void basisu() {
    if (vk_format_ != 0) mismatch("vkFormat is " + str(vk_format_) + ", not VK_FORMAT_UNDEFINED (0)");
    if (!two_d())
      mismatch("the image is not 2D (pixelHeight " + str(height_) + ", pixelDepth " + str(depth_) + ", layerCount " +
               str(layers_) + ", faceCount " + str(faces_) + ")");
    if (width_ % 4 != 0 || height_ % 4 != 0)
      mismatch("pixelWidth and pixelHeight " + str(width_) + "x" + str(height_) + " are not multiples of 4");
    if (dfd_.empty()) return;
    const std::uint8_t model = dfd_[4 + 8], primaries = dfd_[4 + 9], transfer = dfd_[4 + 10], flags = dfd_[4 + 11];
    std::string listed;
    for (std::uint8_t channel : channels_) listed += (listed.empty() ? "" : ", ") + str(channel);
    if (model == kModelEtc1s) {
      if (scheme_ != kSchemeBasisLz)
        mismatch("ETC1S data needs supercompressionScheme 1 (BasisLZ), not " + str(scheme_));
      const bool rgb = channels_ == std::vector<std::uint8_t>{kChannelRgb};
      const bool rgba = channels_ == std::vector<std::uint8_t>{kChannelRgb, kChannelEtc1sAaa};
      if (!channels_.empty() && !rgb && !rgba)
        mismatch("ETC1S data has the channels [" + listed +
                 "]; KHR_texture_basisu allows RGB (0) or RGB and AAA (0, 15)");
    } else if (model == kModelUastc) {
      if (scheme_ != kSchemeNone && scheme_ != kSchemeZstandard)
        mismatch("UASTC data needs supercompressionScheme 0 or 2 (Zstandard), not " + str(scheme_));
      const bool one = channels_.size() == 1 && (channels_[0] == kChannelRgb || channels_[0] == kChannelUastcRgba);
      if (!channels_.empty() && !one)
        mismatch("UASTC data has the channels [" + listed + "]; KHR_texture_basisu allows one, RGB (0) or RGBA (3)");
    } else {
      mismatch("the DFD's colorModel " + str(model) + " is neither ETC1S (163) nor UASTC (166)");
    }
    if (flags & kFlagAlphaPremultiplied)
      mismatch("the DFD sets KHR_DF_FLAG_ALPHA_PREMULTIPLIED; no core material's alpha is premultiplied");
    const std::string space = "colorPrimaries " + str(primaries) + " and transferFunction " + str(transfer);
    if (!use_.colour.empty() && (primaries != kPrimariesBt709 || transfer != kTransferSrgb))
      mismatch(use_.colour + " reads it as colour data, which needs colorPrimaries BT709 (1) and transferFunction " +
               "sRGB (2); the DFD says " + space);
    if (!use_.non_colour.empty() && (primaries != kPrimariesUnspecified || transfer != kTransferLinear))
      mismatch(use_.non_colour + " reads it as non-colour data, which needs colorPrimaries UNSPECIFIED (0) and " +
               "transferFunction LINEAR (1); the DFD says " + space);
  }

  // UASTC stores every 4x4 block of a level in 16 bytes: a 2D level of w x h texels holds
  // ceil(w/4) * ceil(h/4) blocks (after Zstandard, its uncompressedByteLength). Without
  // supercompression each level also starts at a multiple of 16 ("Mip Level Array": mipPadding
  // aligns to lcm(texel block size, 4)).
  void uastc_level_sizes() {
    if (dfd_[4 + 8] != kModelUastc || !two_d() || (scheme_ != kSchemeNone && scheme_ != kSchemeZstandard)) return;
    for (std::size_t level = 0; level < levels_.size(); ++level) {
      const std::uint64_t w = std::max<std::uint64_t>(width_ >> level, 1),
                          h = std::max<std::uint64_t>(height_ >> level, 1);
      const std::uint64_t blocks = ((w + 3) / 4) * ((h + 3) / 4);  // at most 2^60: no overflow
      const std::uint64_t held = scheme_ == kSchemeNone ? levels_[level].length : levels_[level].uncompressed;
      if (blocks > held / kUastcBlockBytes || held != blocks * kUastcBlockBytes) {
        container("mip level " + str(level) + " holds " + str(held) + " bytes of UASTC blocks; a " + str(w) + "x" +
                  str(h) + " level has " + str(blocks) + " blocks of 16 bytes");
        return;
      }
      if (scheme_ == kSchemeNone && levels_[level].offset % kUastcBlockBytes != 0) {
        container("mip level " + str(level) + " starts at byte " + str(levels_[level].offset) +
                  ", not a multiple of 16 as uncompressed UASTC blocks need");
        return;
      }
    }
  }

  // KHR_texture_basisu: "When a texture refers to a sampler with mipmap minification or when the
  // sampler is undefined, the KTX image SHOULD contain a full mip pyramid." levelCount 0 asks the
  // loader to generate the levels, which a Basis texture cannot do without decompressing it.
  void mipmaps() {
    const std::uint32_t stored = std::max<std::uint32_t>(level_count_, 1);
    if (use_.mipmapped.empty() || !level_count_valid() || stored == static_cast<std::uint32_t>(full_levels_)) return;
    found_.push_back({"KTX2_MIPMAPS_INCOMPLETE", "it has " + str(stored) + " of the " + str(full_levels_) +
                                                     " mip levels of a " + str(width_) + "x" + str(height_) +
                                                     " image (levelCount " + str(level_count_) + "), and " +
                                                     use_.mipmapped + " minifies it with mipmaps"});
  }

  std::span<const std::uint8_t> b_;
  const ImageUse& use_;
  std::uint32_t vk_format_ = 0, width_ = 0, height_ = 0, depth_ = 0, layers_ = 0, faces_ = 0, level_count_ = 0,
                scheme_ = 0;
  int full_levels_ = 0;
  std::span<const std::uint8_t> dfd_, kvd_;  // empty unless whole inside the file
  std::vector<Level> levels_;
  std::vector<std::uint8_t> channels_;
  std::vector<Ktx2Finding> found_;
};

}  // namespace

std::vector<Ktx2Finding> check_ktx2(std::span<const std::uint8_t> bytes, const ImageUse& use) {
  return Ktx2Checker(bytes, use).run();
}

}  // namespace gltf_pbr::structure
