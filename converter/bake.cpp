#include "converter/bake.hpp"

#include <atomic>
#include <bit>
#include <cmath>
#include <cstring>
#include <thread>

#include "core/color.hpp"
#include "core/parallel.hpp"

namespace gltf_pbr {
namespace {

std::uint8_t quantize(float value) {
  return static_cast<std::uint8_t>(std::lround(std::clamp(value, 0.0f, 1.0f) * 255.0f));
}

// The value of channel c (RGBA) of a texel: grey images repeat their one channel and a missing
// alpha reads as 1 (PNG and JPEG channel expansion). 8-bit sRGB goes through a table.
float channel(const Pixels& pixels, size_t texel, int c, bool srgb) {
  if (c == 3 && pixels.channels != 2 && pixels.channels != 4) return 1.0f;
  const int source = c == 3 ? pixels.channels - 1 : (pixels.channels >= 3 ? c : 0);
  const size_t i = texel * static_cast<size_t>(pixels.channels) + static_cast<size_t>(source);
  if (srgb && !pixels.bytes.empty()) return srgb8_to_linear(pixels.bytes[i]);  // the common case, straight
  const float value = pixels.value(i);
  if (!srgb) return value;
  return pixels.bits == 8 ? srgb8_to_linear(quantize(value)) : srgb_to_linear(value);
}

// The solve depends only on diffuse and specular (roughness is 1 - glossiness), and textures
// repeat those pairs a lot: a direct-mapped cache of solves, keyed by the exact input bits, skips
// most of the work without changing any result. Misses are gathered per band and solved together
// in SIMD lanes (solve_batch), whose answer for an input never depends on its neighbours, so a
// texel's result is the same whichever batch solved it. The ΔE2000 of the stored (quantized)
// result against both legacy readings depends on the same inputs, so it is cached too.
class SolveCache {
 public:
  struct Entry {
    std::uint32_t key[6];
    std::uint8_t base_srgb[3];
    std::uint8_t metalness;
    float delta_e[4];  // diffuse A, F0 A, diffuse B, F0 B; valid when has_error
    bool filled = false, queued = false, has_error = false;
  };
  enum class Found { Solved, Queued };
  struct Lookup {
    Found found;
    Entry* entry;  // Solved: the entry; Queued: null until solve_queued(), then entry(ticket)
    size_t ticket;
  };

  // Sized to the texels it will see (a power of two up to 65536 entries, about 3 MB).
  SolveCache(const SolverSettings& settings, size_t texels)
      : settings_(settings), entries_(std::bit_ceil(std::clamp<size_t>(texels, 256, 65536))) {}

  // The solved entry of `legacy` (valid until the next call), or a ticket for it in the next
  // solve_queued(). An input already queued shares its ticket. A queued slot is never taken by another input before the
  // solve: one that maps there is queued apart, so every ticket stays valid.
  Lookup find_or_queue(const SpecGloss& legacy) {
    std::uint32_t key[6];
    Entry& entry = slot(legacy, key);
    const bool same = std::memcmp(entry.key, key, sizeof key) == 0;
    if (entry.filled && same) return {Found::Solved, &entry, 0};
    const size_t slot_index = static_cast<size_t>(&entry - entries_.data());
    if (entry.queued && same) return {Found::Queued, nullptr, ticket_of_slot_[slot_index]};
    if (solves_to_its_diffuse(legacy)) {               // no search needed (solver.hpp); cached all the same
      Entry& into = entry.queued ? unqueued_ : entry;  // a queued slot keeps its claim
      std::memcpy(into.key, key, sizeof key);
      fill(into, {legacy.diffuse, 0.0f, 0.0f});
      return {Found::Solved, &into, 0};
    }
    const size_t ticket = queue_.size();
    queue_.push_back(legacy);
    if (entry.queued) {
      spill_.push_back(ticket);
    } else {  // claim the slot (an older solve there is dropped)
      std::memcpy(entry.key, key, sizeof key);
      entry.filled = false, entry.queued = true;
      ticket_of_slot_[slot_index] = ticket;
      claimed_.push_back(slot_index);
    }
    return {Found::Queued, nullptr, ticket};
  }

  // Solves every queued input in one batch; tickets then name their entries until the next call.
  void solve_queued() {
    std::vector<MetalRough> solved(queue_.size());
    solve_batch(queue_, solved, settings_);
    ticket_entries_.assign(queue_.size(), nullptr);
    for (size_t slot_index : claimed_) {
      Entry& entry = entries_[slot_index];
      const size_t ticket = ticket_of_slot_[slot_index];
      fill(entry, solved[ticket]);
      ticket_entries_[ticket] = &entry;
    }
    spilled_.resize(spill_.size());
    for (size_t i = 0; i < spill_.size(); ++i) {
      fill(spilled_[i], solved[spill_[i]]);
      ticket_entries_[spill_[i]] = &spilled_[i];
    }
    queue_.clear(), claimed_.clear(), spill_.clear();
  }
  Entry& entry(size_t ticket) { return *ticket_entries_[ticket]; }

  // The error of what is stored: the quantized texels, read back as a viewer reads them.
  static const float* error(Entry& entry, const SpecGloss& legacy) {
    if (!entry.has_error) {
      MetalRough stored;
      for (int c = 0; c < 3; ++c) stored.base[c] = srgb8_to_linear(entry.base_srgb[c]);
      stored.metalness = static_cast<float>(entry.metalness) / 255.0f;
      const Reflectance converted = core_reflectance(stored);
      const Reflectance a = legacy_reflectance(legacy, LegacyReading::A),
                        b = legacy_reflectance(legacy, LegacyReading::B);
      // Each colour's Lab once: the converted pair serves both readings, and so does F0, which is
      // the specular colour under either.
      auto lab = [](glm::vec3 linear) { return linear_srgb_to_lab(glm::dvec3(linear)); };
      const glm::dvec3 diffuse = lab(converted.diffuse), f0 = lab(converted.f0);
      entry.delta_e[0] = static_cast<float>(delta_e_2000(lab(a.diffuse), diffuse));
      entry.delta_e[1] = static_cast<float>(delta_e_2000(lab(a.f0), f0));
      entry.delta_e[2] = static_cast<float>(delta_e_2000(lab(b.diffuse), diffuse));
      entry.delta_e[3] = b.f0 == a.f0 ? entry.delta_e[1] : static_cast<float>(delta_e_2000(lab(b.f0), f0));
      entry.has_error = true;
    }
    return entry.delta_e;
  }

 private:
  Entry& slot(const SpecGloss& legacy, std::uint32_t (&key)[6]) {
    std::memcpy(key, &legacy.diffuse, sizeof(float) * 3);
    std::memcpy(key + 3, &legacy.specular, sizeof(float) * 3);
    std::uint64_t hash = 1469598103934665603ull;  // FNV-1a over the six words
    for (std::uint32_t word : key) hash = (hash ^ word) * 1099511628211ull;
    return entries_[(hash ^ (hash >> 29)) & (entries_.size() - 1)];
  }

  static void fill(Entry& entry, const MetalRough& r) {
    for (int c = 0; c < 3; ++c) entry.base_srgb[c] = quantize(linear_to_srgb(r.base[c]));
    entry.metalness = quantize(r.metalness);
    entry.filled = true, entry.queued = false, entry.has_error = false;
  }

  const SolverSettings& settings_;
  std::vector<Entry> entries_;
  std::vector<size_t> ticket_of_slot_ = std::vector<size_t>(entries_.size());
  std::vector<SpecGloss> queue_;         // inputs to solve, by ticket
  std::vector<size_t> claimed_, spill_;  // slots claimed by tickets; tickets whose slot was taken
  std::vector<Entry> spilled_;           // the spilled tickets' solves, until the next batch
  std::vector<Entry*> ticket_entries_;
  Entry unqueued_;  // an answer known without a solve whose slot is claimed: good until the next ask
};

}  // namespace

BakedTexels bake(const BakeInputs& in, const SolverSettings& settings, size_t max_error_samples) {
  BakedTexels out;
  out.width = in.width;
  out.height = in.height;
  const size_t texels = static_cast<size_t>(in.width) * static_cast<size_t>(in.height);
  // Without an alpha channel in the diffuse, alpha is the factor's: the texels need RGB only.
  const bool alpha_texels = in.diffuse && (in.diffuse->channels == 2 || in.diffuse->channels == 4);
  out.base_channels = alpha_texels ? 4 : 3;
  const size_t base_channels = static_cast<size_t>(out.base_channels);
  out.base_color.resize(texels * base_channels);
  out.metalness.resize(texels);
  if (in.spec_gloss) out.roughness.resize(texels);
  const auto roughness_of = [](float glossiness) { return quantize(std::clamp(1.0f - glossiness, 0.0f, 1.0f)); };
  out.first_roughness =
      roughness_of(in.glossiness_factor * (in.spec_gloss ? channel(*in.spec_gloss, 0, 3, false) : 1.0f));
  const size_t stride = max_error_samples == 0 ? 1 : std::max<size_t>(1, texels / max_error_samples);
  std::vector<ErrorAccumulator> rows_a(static_cast<size_t>(in.height)), rows_b(static_cast<size_t>(in.height));
  std::vector<ErrorAccumulator> rows_extension_a(in.measure_extension_route ? rows_a.size() : 0);
  std::vector<ErrorAccumulator> rows_extension_b(rows_extension_a.size());

  // The legacy material of texel i: factor x texel, each in its colour space.
  const auto legacy_at = [&](size_t i) {
    SpecGloss legacy;
    legacy.diffuse = glm::vec3(in.diffuse_factor);
    if (in.diffuse)
      for (int c = 0; c < 3; ++c) legacy.diffuse[c] *= channel(*in.diffuse, i, c, true);
    legacy.specular = in.specular_factor;
    legacy.glossiness = in.glossiness_factor;
    if (in.spec_gloss) {
      for (int c = 0; c < 3; ++c) legacy.specular[c] *= channel(*in.spec_gloss, i, c, true);
      legacy.glossiness *= channel(*in.spec_gloss, i, 3, false);
    }
    return legacy;
  };
  out.alpha = quantize(in.diffuse_factor.a * (alpha_texels ? channel(*in.diffuse, 0, 3, false) : 1.0f));
  // Texel i's solve, written out, and its error when the texel is a sample.
  const auto write = [&](size_t i, SolveCache::Entry& solved, const SpecGloss& legacy) {
    std::memcpy(&out.base_color[i * base_channels], solved.base_srgb, 3);
    out.metalness[i] = solved.metalness;
    if (i % stride != 0) return;
    const size_t y = i / static_cast<size_t>(in.width);
    const float* delta_e = SolveCache::error(solved, legacy);
    rows_a[y].add(delta_e[0], delta_e[1]);
    rows_b[y].add(delta_e[2], delta_e[3]);
    if (in.measure_extension_route) {
      const Reflectance route = specular_extension_reflectance(legacy.diffuse, legacy.specular);
      rows_extension_a[y].add(legacy_reflectance(legacy, LegacyReading::A), route);
      rows_extension_b[y].add(legacy_reflectance(legacy, LegacyReading::B), route);
    }
  };

  // Bands of rows handed out one at a time: the distinct colours, and so the solves, gather in
  // parts of a texture, and a static split left one core with most of them. Each thread keeps its
  // cache across its bands (neighbouring rows share colours).
  constexpr std::int64_t kBandRows = 16;
  const std::int64_t bands = (in.height + kBandRows - 1) / kBandRows;
  const std::int64_t threads = std::min(ThreadPool::shared().threads(), bands);
  std::atomic<std::int64_t> next_band{0};
  run_on_threads(threads, [&] {
    SolveCache cache(settings, texels / static_cast<size_t>(std::max<std::int64_t>(1, threads)));
    std::vector<std::pair<size_t, size_t>> waiting;  // (texel, ticket) of the band's misses
    for (std::int64_t band; (band = next_band.fetch_add(1)) < bands;) {
      const size_t first = static_cast<size_t>(band * kBandRows) * static_cast<size_t>(in.width);
      const size_t end = static_cast<size_t>(std::min<std::int64_t>(in.height, (band + 1) * kBandRows)) *
                         static_cast<size_t>(in.width);
      // Hits are written at once; misses wait for the band's batch.
      for (size_t i = first; i < end; ++i) {
        const SpecGloss legacy = legacy_at(i);
        if (alpha_texels) out.base_color[i * 4 + 3] = quantize(in.diffuse_factor.a * channel(*in.diffuse, i, 3, false));
        if (in.spec_gloss) out.roughness[i] = roughness_of(legacy.glossiness);
        const SolveCache::Lookup found = cache.find_or_queue(legacy);
        if (found.found == SolveCache::Found::Solved)
          write(i, *found.entry, legacy);
        else
          waiting.emplace_back(i, found.ticket);
      }
      if (waiting.empty()) continue;
      cache.solve_queued();
      for (const auto& [i, ticket] : waiting) write(i, cache.entry(ticket), legacy_at(i));
      waiting.clear();
    }
  });
  for (size_t y = 0; y < rows_a.size(); ++y) {
    out.error_a.merge(rows_a[y]);
    out.error_b.merge(rows_b[y]);
  }
  for (size_t y = 0; y < rows_extension_a.size(); ++y) {
    out.extension_a.merge(rows_extension_a[y]);
    out.extension_b.merge(rows_extension_b[y]);
  }
  for (size_t i = 1; i < texels; ++i) {
    const std::uint8_t* base = &out.base_color[i * base_channels];
    out.base_constant = out.base_constant && std::equal(base, base + 3, &out.base_color[0]);
    out.alpha_constant = out.alpha_constant && (!alpha_texels || base[3] == out.alpha);
    out.metal_rough_constant = out.metal_rough_constant && out.metalness[i] == out.metalness[0] &&
                               (out.roughness.empty() || out.roughness[i] == out.first_roughness);
  }
  return out;
}

TexelBytes BakedTexels::metal_rough() const {
  TexelBytes texels(metalness.size() * 3);
  for (size_t i = 0; i < metalness.size(); ++i) {
    texels[i * 3] = 0;
    texels[i * 3 + 1] = roughness.empty() ? first_roughness : roughness[i];
    texels[i * 3 + 2] = metalness[i];
  }
  return texels;
}

}  // namespace gltf_pbr
