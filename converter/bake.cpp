#include "converter/bake.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <tuple>
#include <vector>

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

// The cache takes a key's set from the low bits of its hash, so every bit of the key must reach
// them: the finaliser of MurmurHash3 (fmix64). A multiply alone carries a bit only upwards, and
// keys that differed in their glossiness byte alone (bits 48-55) all took one slot, so a
// texture whose glossiness varies solved the same colours again and again (Avocado: 2.2 million
// solves for 273,000 distinct texels).
std::uint64_t mix_bits(std::uint64_t k) {
  k ^= k >> 33;
  k *= 0xFF51AFD7ED558CCDull;
  k ^= k >> 33;
  k *= 0xC4CEB9FE1A85EC53ull;
  return k ^ (k >> 33);
}

// A texel as written, beside the legacy texel it stands for: what an error sample measures.
struct StoredTexel {
  SpecGloss legacy;
  glm::vec3 base;  // linear, as a viewer reads it
  std::uint8_t metalness;
};

// ΔE2000 of stored texels read back as a viewer reads them (core_reflectance and core_appearance
// of the 8-bit sRGB base and metalness, at the texel's roughness) against legacy readings A and B,
// in one batch of CIELAB and ΔE2000 lanes. F0 is the specular colour under either reading. Per
// texel: diffuse A, F0 A, diffuse B, F0 B, and under the appearance model the mean over the
// appearance rings (else 0, unmeasured).
//
// A colour pair is converted and compared once however many of a texel's figures it serves: both
// readings share the converted diffuse, a specular of 0 makes reading B's diffuse reading A's, and
// the F0 pair of a texel often repeats the one before (a specular factor over a dielectric: every
// texel of most of VC's textures). A lane's result never depends on its neighbours, so each figure
// is the one a pair of its own would give.
class StoredTexelErrors {
 public:
  using DeltaE = std::array<float, 5>;
  void measure(std::span<const StoredTexel> texels, bool appearance, std::span<DeltaE> out) {
    const size_t kFigures = appearance ? 3 + kAppearanceRings : 3;  // diffuse A, F0, diffuse B, rings
    const size_t n = texels.size();
    colours_.clear(), expected_.clear(), actual_.clear();
    pair_of_.resize(kFigures * n);
    bool have_f0 = false;
    glm::vec3 last_expected_f0{0.0f}, last_actual_f0{0.0f};
    std::uint32_t f0_pair = 0;
    for (size_t j = 0; j < n; ++j) {
      const StoredTexel& texel = texels[j];
      MetalRough stored;
      stored.base = texel.base;
      stored.metalness = static_cast<float>(texel.metalness) / 255.0f;
      stored.roughness = std::clamp(1.0f - texel.legacy.glossiness, 0.0f, 1.0f);
      const Reflectance converted = core_reflectance(stored);
      const Reflectance a = legacy_reflectance(texel.legacy, LegacyReading::A),
                        b = legacy_reflectance(texel.legacy, LegacyReading::B);
      std::uint32_t* const figures = &pair_of_[kFigures * j];
      const std::uint32_t converted_diffuse = colour(converted.diffuse);
      figures[0] = pair(colour(a.diffuse), converted_diffuse);
      figures[2] = b.diffuse == a.diffuse ? figures[0] : pair(colour(b.diffuse), converted_diffuse);
      if (!have_f0 || a.f0 != last_expected_f0 || converted.f0 != last_actual_f0) {
        f0_pair = pair(colour(a.f0), colour(converted.f0));
        have_f0 = true, last_expected_f0 = a.f0, last_actual_f0 = converted.f0;
      }
      figures[1] = f0_pair;
      if (!appearance) continue;
      const Appearance seen = legacy_appearance(texel.legacy), shown = core_appearance(stored);
      for (int k = 0; k < kAppearanceRings; ++k) figures[3 + k] = pair(colour(seen.ring[k]), colour(shown.ring[k]));
    }
    lab_.resize(colours_.size());
    linear_srgb_to_lab(colours_, lab_);
    const size_t pairs = expected_.size();
    lab1_.resize(pairs), lab2_.resize(pairs), delta_e_.resize(pairs);
    for (size_t p = 0; p < pairs; ++p) lab1_[p] = lab_[expected_[p]], lab2_[p] = lab_[actual_[p]];
    delta_e_2000(lab1_, lab2_, delta_e_);
    for (size_t j = 0; j < n; ++j) {
      const std::uint32_t* figures = &pair_of_[kFigures * j];
      float rings = 0.0f;  // the mean over the rings, as appearance_delta_e
      for (int k = 0; appearance && k < kAppearanceRings; ++k) rings += delta_e_[figures[3 + k]];
      const float f0 = delta_e_[figures[1]];
      out[j] = {delta_e_[figures[0]], f0, delta_e_[figures[2]], f0, rings / kAppearanceRings};
    }
  }

 private:
  std::uint32_t colour(const glm::vec3& linear) {
    colours_.push_back(linear);
    return static_cast<std::uint32_t>(colours_.size() - 1);
  }
  std::uint32_t pair(std::uint32_t expected, std::uint32_t actual) {
    expected_.push_back(expected), actual_.push_back(actual);
    return static_cast<std::uint32_t>(expected_.size() - 1);
  }

  std::vector<glm::vec3> colours_, lab_, lab1_, lab2_;
  std::vector<std::uint32_t> expected_, actual_;  // a pair's two colours (legacy, converted)
  std::vector<std::uint32_t> pair_of_;            // the pair of each figure of each texel
  std::vector<float> delta_e_;                    // by pair
};

// How the bake reads texel i: its legacy material, and the key its solve is cached by: diffuse and
// specular, and glossiness where the solve depends on it (the appearance model weighs the lobes by
// the roughness; the normal-incidence solve does not, and keying it there tripled Avocado's solve).
//
// Any inputs: the key is the legacy colours' float bits.
struct FloatTexels {
  using Key = std::array<std::uint32_t, 7>;
  const BakeInputs& in;
  bool key_glossiness;

  SpecGloss legacy(size_t i) const {
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
  }
  Key key(size_t i) const {
    const SpecGloss l = legacy(i);
    Key key;
    std::memcpy(key.data(), &l.diffuse, sizeof(float) * 3);
    std::memcpy(key.data() + 3, &l.specular, sizeof(float) * 3);
    key[6] = 0;
    if (key_glossiness) std::memcpy(key.data() + 6, &l.glossiness, sizeof(float));
    return key;
  }
  static std::uint64_t hash(const Key& key) {
    std::uint64_t hash = 1469598103934665603ull;  // FNV-1a over the seven words
    for (std::uint32_t word : key) hash = (hash ^ word) * 1099511628211ull;
    return mix_bits(hash);
  }
};

// 8-bit inputs (PNG and JPEG: nearly every texture): the key is the texel's six sRGB bytes (and its glossiness byte
// when keyed on it), so a cache hit costs no colour conversion; the material is built from them only on a miss.
struct ByteTexels {
  using Key = std::uint64_t;
  const BakeInputs& in;
  bool key_glossiness;

  // Where the R, G and B bytes of texel i sit: grey images repeat their one channel.
  struct Source {
    const std::uint8_t* bytes = nullptr;
    size_t step = 0;
    size_t offset[3] = {0, 0, 0};
    explicit Source(const Pixels* p) {
      if (!p) return;
      bytes = p->bytes.data(), step = static_cast<size_t>(p->channels);
      if (p->channels >= 3) offset[1] = 1, offset[2] = 2;
    }
    std::uint64_t rgb(size_t i) const {
      const std::uint8_t* t = bytes + i * step;
      return t[offset[0]] | std::uint64_t{t[offset[1]]} << 8 | std::uint64_t{t[offset[2]]} << 16;
    }
    // The alpha byte (glossiness of a specularGlossiness texture); 255 without an alpha channel.
    std::uint64_t alpha(size_t i) const { return step == 2 || step == 4 ? bytes[i * step + step - 1] : 255; }
  };
  Source diffuse{in.diffuse}, specular{in.spec_gloss};

  static bool serves(const BakeInputs& in) {
    const auto bytes = [](const Pixels* p) { return !p || (p->bits == 8 && !p->bytes.empty()); };
    return bytes(in.diffuse) && bytes(in.spec_gloss);
  }
  Key key(size_t i) const {
    return (diffuse.bytes ? diffuse.rgb(i) : 0) |
           (specular.bytes ? specular.rgb(i) << 24 | (key_glossiness ? specular.alpha(i) << 48 : 0) : 0);
  }
  SpecGloss legacy(size_t i) const {
    const std::array<float, 256>& linear = srgb8_to_linear_table();
    const Key k = key(i);
    SpecGloss legacy;
    legacy.diffuse = glm::vec3(in.diffuse_factor);
    legacy.specular = in.specular_factor;
    for (int c = 0; c < 3; ++c) {
      if (diffuse.bytes) legacy.diffuse[c] *= linear[k >> (8 * c) & 0xFF];
      if (specular.bytes) legacy.specular[c] *= linear[k >> (24 + 8 * c) & 0xFF];
    }
    legacy.glossiness = in.glossiness_factor * (in.spec_gloss ? channel(*in.spec_gloss, i, 3, false) : 1.0f);
    return legacy;
  }
  static std::uint64_t hash(Key key) { return mix_bits(key); }
};

// What a cached solve and its error depend on besides the texel key: the factors, which inputs
// the key reads, and the solver's settings. A thread keeps its cache from one bake to the next
// with the same context (SolveCache::for_this_thread). Like the key, it holds the glossiness only
// where the answer reads it (the appearance model), and the diffuse factor's colour, not its alpha.
struct SolveContext {
  glm::vec3 diffuse_factor;
  glm::vec3 specular_factor;
  float glossiness_factor;
  bool diffuse_texture, spec_gloss_texture, key_glossiness;
  SolverSettings settings;
  bool operator==(const SolveContext&) const = default;
};

// A cache of solves, four ways a set: textures repeat their colour pairs a lot, and a hit skips the
// solve without changing any result. Misses are gathered per band and solved together in SIMD
// lanes (solve_batch), whose answer for an input never depends on its neighbours, so a texel's
// result is the same whichever batch solved it. The ΔE2000 of the stored (quantized) result
// against both legacy readings depends on the same inputs, so it is cached too: computed once
// per entry that a sample texel reads, in SIMD lanes for a batch of entries (measure_errors).
//
// A lookup reads one set, and waiting for it was about a third of a large bake's lookup time
// (Avocado at 4096²): so an entry holds only what a lookup reads (16 bytes with the 8-byte keys of
// 8-bit textures, a set of four one 64-byte line) and the error beside it lives apart, read by
// samples only. Sets of two 48-byte entries spanned two lines, and four times as many of them
// saved a quarter of the solves but lost as much again in lookups (bench/RESULTS.md).
template <class Key>
class SolveCache {
 public:
  struct Entry {
    Key key{};
    std::uint8_t base_srgb[3];
    std::uint8_t metalness;
    std::uint32_t generation : 30 = 0;  // filled and queued hold only in the cache's current generation
    std::uint32_t filled : 1 = 0, queued : 1 = 0;
  };
  enum class Found { Solved, Queued };
  struct Lookup {
    Found found;
    Entry* entry;  // Solved: the entry; Queued: null until solve_queued(), then entry(ticket)
    size_t ticket;
  };

  // The calling thread's cache for a bake in `context`: each pool thread keeps its cache from bake
  // to bake. After a bake in the same context that ran to its end, the entries stay: they hold
  // the same answers (VC's 21 textures are 16 of one context, a diffuse map over specular 0, and
  // their colours recur from texture to texture: 394k distinct inputs bake by bake, 237k within
  // each context). Otherwise it is emptied by starting a new generation instead of allocating and
  // zeroing it again (up to 3 MB a thread a texture: a tenth of the run time on VC). Sized to the
  // texels it will see, a power of two up to kMostEntries; it never shrinks. Nothing inside a
  // bake's work on a thread may start another bake on the pool: that bake would take this cache
  // in the middle of the first (and keep or label entries that are not its own).
  static SolveCache& for_this_thread(size_t texels, const SolveContext& context) {
    thread_local SolveCache cache;
    const size_t size = std::bit_ceil(std::clamp<size_t>(texels, 256, kMostEntries));
    const bool same_answers = cache.finished_ && cache.context_ == context;
    cache.finished_ = false, cache.context_ = context;
    if (cache.sets_.size() * kWays < size || (!same_answers && ++cache.generation_ == kGenerations)) {
      // The side arrays first: were they to fail to grow after the sets did, a later bake would
      // index them past their end.
      const size_t sets = std::max(cache.sets_.size(), size / kWays);
      cache.ticket_of_slot_.resize(sets * kWays), cache.errors_.resize(sets * kWays);
      cache.sets_.assign(sets, Set{});
      cache.generation_ = 1;  // every entry (generation 0) is empty
    }
    cache.queue_.clear(), cache.claimed_.clear(), cache.spill_.clear();  // an earlier bake may have thrown
    cache.error_texels_.clear(), cache.error_slots_.clear(), cache.error_waiting_.clear();
    return cache;
  }

  // The thread's part of the bake ran to its end: no input is left queued, no error job waiting.
  void finish() { finished_ = true; }

  // The solved entry of `key` (valid until the next call), or a ticket for it in the next
  // solve_queued(). `legacy()` gives the material, asked for on a miss only. An input already
  // queued shares its ticket. A queued slot is never taken by another input before the solve:
  // one whose set holds only queued inputs is queued apart, so every ticket stays valid.
  template <class Legacy>
  Lookup find_or_queue(const Key& key, std::uint64_t hash, Legacy&& legacy) {
    Set& set = sets_[hash & (sets_.size() - 1)];
    // The ways whose key matches, compared without a branch a way (which way hits is random).
    unsigned matches = 0;
    for (int w = 0; w < kWays; ++w) matches |= static_cast<unsigned>(set.way[w].key == key) << w;
    for (; matches != 0; matches &= matches - 1) {
      Entry& way = set.way[std::countr_zero(matches)];
      if (way.generation != generation_) continue;  // left by an earlier bake
      if (way.filled) return {Found::Solved, &way, 0};
      if (way.queued) return {Found::Queued, nullptr, ticket_of_slot_[slot_of(way)]};
    }
    Entry* empty = nullptr;
    for (Entry& way : set.way) {
      if (way.generation != generation_) way.filled = way.queued = 0, way.generation = generation_;
      if (!empty && !way.filled && !way.queued) empty = &way;
    }
    // The way to take: an empty one, else the next of the set's filled ones in turn (an older
    // solve there is dropped); never a queued one.
    Entry* victim = empty;
    for (int k = 0; !victim && k < kWays; ++k) {
      Entry& way = set.way[(next_victim_ + static_cast<unsigned>(k)) % kWays];
      if (!way.queued) victim = &way;
    }
    ++next_victim_;
    const SpecGloss material = legacy();
    if (solves_to_its_diffuse(material)) {  // no search needed (solver.hpp); cached all the same
      Entry& into = victim ? *victim : unqueued_;
      into.key = key;
      fill(into, {material.diffuse, 0.0f, 0.0f});
      return {Found::Solved, &into, 0};
    }
    const size_t ticket = queue_.size();
    queue_.push_back(material);
    if (!victim) {
      spill_.push_back(ticket);
    } else {  // claim the way
      victim->key = key;
      victim->filled = 0, victim->queued = 1;
      const size_t slot = slot_of(*victim);
      errors_[slot].job = -1;  // a waiting job keeps its copy of what it measures
      ticket_of_slot_[slot] = ticket;
      claimed_.push_back(slot);
    }
    return {Found::Queued, nullptr, ticket};
  }

  // Solves every queued input in one batch; tickets then name their entries until the next call.
  void solve_queued() {
    std::vector<MetalRough> solved(queue_.size());
    solve_batch(queue_, solved, context_->settings);
    ticket_entries_.assign(queue_.size(), nullptr);
    for (size_t slot : claimed_) {
      Entry& entry = entry_at(slot);
      const size_t ticket = ticket_of_slot_[slot];
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
  // Starts loading the set that `hash` reads, ahead of its lookup.
  void prefetch(std::uint64_t hash) const { __builtin_prefetch(&sets_[hash & (sets_.size() - 1)]); }

  // Sample `sample` takes the ΔE2000 of what `entry` stores, against legacy readings A and B
  // (and the appearance under the appearance model, whose entries are keyed by glossiness too):
  // at once, through set(sample, delta_e), when the entry's slot knows it; else at the next
  // measure_errors(), which computes it once for every slot waiting (an entry outside the sets,
  // spilled or unqueued, is measured for its sample alone). `legacy()` gives the texel's
  // material, asked for only when the error is not known.
  template <class Legacy, class Set>
  void take_error(Entry& entry, Legacy&& legacy, size_t sample, Set&& set) {
    const std::optional<size_t> slot = slot_if_in_sets(entry);
    ErrorSlot* const known = slot ? &errors_[*slot] : nullptr;
    if (known && known->has_delta_e) return set(sample, known->delta_e);
    if (!known || known->job < 0) {
      StoredTexel& texel = error_texels_.emplace_back();
      texel.legacy = legacy();
      for (int c = 0; c < 3; ++c) texel.base[c] = srgb8_to_linear(entry.base_srgb[c]);
      texel.metalness = entry.metalness;
      error_slots_.push_back(slot ? static_cast<std::int64_t>(*slot) : -1);
      if (known) known->job = static_cast<std::int32_t>(error_texels_.size() - 1);
    }
    error_waiting_.emplace_back(sample, known ? static_cast<size_t>(known->job) : error_texels_.size() - 1);
    if (error_texels_.size() >= kErrorBatch) measure_errors(set);
  }

  // The waiting error jobs, in one batch (StoredTexelErrors).
  template <class Set>
  void measure_errors(Set&& set) {
    const size_t jobs = error_texels_.size();
    if (jobs == 0) return;
    // The normal-incidence run leaves the appearance unmeasured: its entries are not keyed by glossiness.
    error_delta_e_.resize(jobs);
    errors_measure_.measure(error_texels_, context_->settings.error_model == ErrorModel::Appearance, error_delta_e_);
    for (size_t j = 0; j < jobs; ++j) {
      if (error_slots_[j] < 0) continue;
      ErrorSlot& slot = errors_[static_cast<size_t>(error_slots_[j])];
      if (slot.job == static_cast<std::int32_t>(j)) {  // its entry still holds what the job measured
        std::memcpy(slot.delta_e, error_delta_e_[j].data(), sizeof slot.delta_e);
        slot.has_delta_e = true, slot.job = -1;
      }
    }
    for (const auto& [sample, job] : error_waiting_) set(sample, error_delta_e_[job].data());
    error_texels_.clear(), error_slots_.clear(), error_waiting_.clear();
  }

 private:
  static constexpr int kWays = 4;
  static constexpr size_t kMostEntries = 65536;
  static constexpr std::uint32_t kGenerations = 1u << 30;  // Entry::generation's range
  struct alignas(64) Set {
    Entry way[kWays];
  };
  // The error of a slot's contents; valid while the slot holds what it was measured on (fill()
  // and a claim reset it).
  struct ErrorSlot {
    float delta_e[5];       // diffuse A, F0 A, diffuse B, F0 B, appearance A (its model only)
    std::int32_t job = -1;  // the waiting error job for the slot's contents, or -1
    bool has_delta_e = false;
  };

  // The slot of an entry in the sets: set by set, way by way.
  size_t slot_of(const Entry& entry) const {
    const auto offset =
        static_cast<size_t>(reinterpret_cast<const char*>(&entry) - reinterpret_cast<const char*>(sets_.data()));
    return offset / sizeof(Set) * kWays + offset % sizeof(Set) / sizeof(Entry);
  }
  std::optional<size_t> slot_if_in_sets(const Entry& entry) const {
    const auto* const at = reinterpret_cast<const char*>(&entry);
    const auto* const first = reinterpret_cast<const char*>(sets_.data());
    if (at < first || at >= first + sets_.size() * sizeof(Set)) return std::nullopt;
    return slot_of(entry);
  }
  Entry& entry_at(size_t slot) { return sets_[slot / kWays].way[slot % kWays]; }

  void fill(Entry& entry, const MetalRough& r) {
    for (int c = 0; c < 3; ++c) entry.base_srgb[c] = quantize(linear_to_srgb(r.base[c]));
    entry.metalness = quantize(r.metalness);
    entry.filled = 1, entry.queued = 0;
    if (const std::optional<size_t> slot = slot_if_in_sets(entry)) errors_[*slot] = ErrorSlot{};
  }

  SolveCache() = default;

  std::optional<SolveContext> context_;  // of this bake (and, until it starts, of the last)
  bool finished_ = false;                // the last bake ran to its end (finish())
  std::vector<Set> sets_;
  std::vector<size_t> ticket_of_slot_;
  std::vector<ErrorSlot> errors_;  // by slot
  std::uint32_t generation_ = 0;
  unsigned next_victim_ = 0;
  std::vector<SpecGloss> queue_;         // inputs to solve, by ticket
  std::vector<size_t> claimed_, spill_;  // slots claimed by tickets; tickets whose set held only queued ones
  std::vector<Entry> spilled_;           // the spilled tickets' solves, until the next batch
  std::vector<Entry*> ticket_entries_;
  Entry unqueued_;  // an answer known without a solve whose set is all queued: good until the next ask

  // The error jobs, each with a copy of what it measures: a slot may be taken by another input
  // before measure_errors(), and then keeps none of it.
  static constexpr size_t kErrorBatch = 4096;  // jobs held at most (memory stays bounded)
  std::vector<StoredTexel> error_texels_;
  std::vector<std::int64_t> error_slots_;                 // the slot of each job, or -1
  std::vector<std::pair<size_t, size_t>> error_waiting_;  // (sample, job)
  std::vector<StoredTexelErrors::DeltaE> error_delta_e_;
  StoredTexelErrors errors_measure_;
};

// A channel's 256 byte values through f, quantized: per-texel alpha and roughness by lookup.
template <class F>
std::array<std::uint8_t, 256> byte_table(F f) {
  std::array<std::uint8_t, 256> table;
  for (int v = 0; v < 256; ++v) table[static_cast<size_t>(v)] = quantize(f(static_cast<float>(v) / 255.0f));
  return table;
}

// Whether a diffuse can be compared with (and overwritten by) the base colour byte for byte.
bool same_layout_as_base(const Pixels* diffuse, const BakedTexels& out) {
  return diffuse && diffuse->bits == 8 && diffuse->channels == out.base_channels && diffuse->width == out.width &&
         diffuse->height == out.height &&
         diffuse->bytes.size() ==
             static_cast<size_t>(out.width) * static_cast<size_t>(out.height) * static_cast<size_t>(out.base_channels);
}

template <class Texels>
void bake_texels(const BakeInputs& in, const SolverSettings& settings, size_t max_error_samples, BakedTexels& out) {
  const Texels texels_of{in, settings.error_model == ErrorModel::Appearance};
  const size_t texels = static_cast<size_t>(in.width) * static_cast<size_t>(in.height);
  const bool alpha_texels = out.base_channels == 4;
  const size_t base_channels = static_cast<size_t>(out.base_channels);
  // The base colour's bytes: the diffuse's own when handed over (see bake(), which hands over only
  // a diffuse of the base colour's layout). Either way texel i's diffuse bytes are read (key,
  // legacy material, comparison) before texel i's base is written.
  std::uint8_t* const base = in.overwrite_diffuse ? in.overwrite_diffuse->data() : out.base_color.data();
  const std::uint8_t* const diffuse_bytes = same_layout_as_base(in.diffuse, out) ? in.diffuse->bytes.data() : nullptr;
  std::atomic<bool> equals_diffuse{diffuse_bytes != nullptr};
  // Every stride-th texel is a sample, in texel order.
  const size_t stride = error_sample_stride(texels, max_error_samples);
  const size_t samples = (texels + stride - 1) / stride;
  out.error_a = ErrorAccumulator(samples, settings.error_model == ErrorModel::Appearance);
  out.error_b = ErrorAccumulator(samples);
  out.sample_stride = stride;
  if (in.measure_as_written || in.keep_sampled_legacy) out.sampled_legacy.resize(samples);
  if (in.measure_extension_route) {
    out.extension_a = ErrorAccumulator(samples, settings.error_model == ErrorModel::Appearance);
    out.extension_b = ErrorAccumulator(samples);
  }

  // Alpha (linear, times the factor) and roughness (1 - glossiness, glossiness linear in the
  // specularGlossiness alpha) of 8-bit texels by table; other precisions channel by channel.
  const auto alpha_table = byte_table([&](float a) { return in.diffuse_factor.a * a; });
  const auto roughness_table = byte_table([&](float g) { return 1.0f - in.glossiness_factor * g; });
  const auto alpha_of = [&](size_t i) {
    const Pixels& d = *in.diffuse;
    return !d.bytes.empty()
               ? alpha_table[d.bytes[i * static_cast<size_t>(d.channels) + static_cast<size_t>(d.channels - 1)]]
               : quantize(in.diffuse_factor.a * channel(d, i, 3, false));
  };
  const auto roughness_of = [&](size_t i) {
    const Pixels& s = *in.spec_gloss;
    if (!s.bytes.empty() && (s.channels == 2 || s.channels == 4))
      return roughness_table[s.bytes[i * static_cast<size_t>(s.channels) + static_cast<size_t>(s.channels - 1)]];
    return quantize(1.0f - in.glossiness_factor * channel(s, i, 3, false));
  };

  // Texel i's solve, its error when the texel is a sample, and its comparison with the diffuse,
  // all before its base bytes are written (they may be the diffuse's).
  const auto set_error = [&](size_t sample, const float* delta_e) {
    out.error_a.set(sample, delta_e[0], delta_e[1]);
    if (settings.error_model == ErrorModel::Appearance) out.error_a.set_appearance(sample, delta_e[4]);
    out.error_b.set(sample, delta_e[2], delta_e[3]);
  };
  // A sample texel's error (every stride-th texel; the band loop knows which without dividing,
  // since a 64-bit division a texel was 2% of a 4096² bake's CPU).
  const auto take_sample = [&](size_t i, auto& solved, auto& cache) {
    const size_t sample = i / stride;
    const bool kept = !out.sampled_legacy.empty();
    if (kept) out.sampled_legacy[sample] = texels_of.legacy(i);
    const auto legacy_texel = [&] { return kept ? out.sampled_legacy[sample] : texels_of.legacy(i); };
    if (!in.measure_as_written) cache.take_error(solved, legacy_texel, sample, set_error);
    if (in.measure_extension_route) {
      const SpecGloss legacy = legacy_texel();
      const Reflectance route = specular_extension_reflectance(legacy.diffuse, legacy.specular);
      out.extension_a.set(sample, legacy_reflectance(legacy, LegacyReading::A), route);
      out.extension_b.set(sample, legacy_reflectance(legacy, LegacyReading::B), route);
      if (settings.error_model == ErrorModel::Appearance)
        out.extension_a.set_appearance(
            sample, appearance_delta_e(legacy_appearance(legacy), specular_extension_appearance(legacy)));
    }
  };
  const auto write = [&](size_t i, bool sample, auto& solved, auto& cache, bool& equal) {
    if (sample) take_sample(i, solved, cache);
    if (equal && diffuse_bytes) {
      const std::uint8_t* diffuse = diffuse_bytes + i * base_channels;
      for (int c = 0; c < 3; ++c) equal = equal && std::abs(int{diffuse[c]} - int{solved.base_srgb[c]}) <= 1;
    }
    std::memcpy(base + i * base_channels, solved.base_srgb, 3);
    out.metalness[i] = solved.metalness;
  };

  // Bands of rows handed out a run of neighbours at a time: the distinct colours, and so the
  // solves, gather in parts of a texture, and a static split left one core with most of them.
  // Each thread keeps its cache across its bands, and neighbouring bands share colours: handed
  // out one by one, alternating between threads, each thread solved them again (Avocado at
  // 4096²: 1.14 M solves for 0.43 M distinct inputs, 1.00 M in runs; bench/RESULTS.md).
  constexpr std::int64_t kBandRows = 16;
  // A lookup's set is a random line of a cache of up to 1 MiB a thread: the load of it was a
  // quarter of the band loop's time (perf, Avocado at 4096²). Each lookup starts the load of the
  // set of the texel this far ahead: 6-9% less CPU where one core bakes, nothing measurable where
  // two bake one file (bench/RESULTS.md).
  constexpr size_t kPrefetchAhead = 16;
  const std::int64_t bands = (in.height + kBandRows - 1) / kBandRows;
  const std::int64_t threads = std::min(ThreadPool::shared().threads(), bands);
  const std::int64_t bands_per_run = std::max<std::int64_t>(1, bands / (threads * 8));
  const std::int64_t runs = (bands + bands_per_run - 1) / bands_per_run;
  std::atomic<std::int64_t> next_run{0};
  using Cache = SolveCache<typename Texels::Key>;
  const SolveContext context{glm::vec3(in.diffuse_factor),
                             in.specular_factor,
                             texels_of.key_glossiness ? in.glossiness_factor : 0.0f,
                             in.diffuse != nullptr,
                             in.spec_gloss != nullptr,
                             texels_of.key_glossiness,
                             settings};
  const auto bake_band = [&](std::int64_t band, Cache& cache, std::vector<std::pair<size_t, size_t>>& waiting,
                             bool& equal) {
    const size_t first = static_cast<size_t>(band * kBandRows) * static_cast<size_t>(in.width);
    const size_t end =
        static_cast<size_t>(std::min<std::int64_t>(in.height, (band + 1) * kBandRows)) * static_cast<size_t>(in.width);
    // Hits are written at once; misses wait for the band's batch. Half the texels of a smooth map
    // repeat the one before (Avocado's), and take its lookup as it is: an entry stays valid until
    // the next lookup, and a queued input keeps its ticket.
    std::optional<std::pair<typename Texels::Key, typename Cache::Lookup>> previous;
    size_t next_sample = (first + stride - 1) / stride * stride;
    for (size_t i = first; i < end; ++i) {
      const bool sample = i == next_sample;
      if (sample) next_sample += stride;
      if (alpha_texels) {  // the key and the legacy material do not read alpha
        const std::uint8_t alpha = alpha_of(i);
        equal = equal && (!diffuse_bytes || diffuse_bytes[i * 4 + 3] == alpha);
        base[i * 4 + 3] = alpha;
      }
      if (in.spec_gloss) out.roughness[i] = roughness_of(i);
      const typename Texels::Key key = texels_of.key(i);
      if (!previous || previous->first != key) {
        if (i + kPrefetchAhead < end) cache.prefetch(Texels::hash(texels_of.key(i + kPrefetchAhead)));
        previous.emplace(key, cache.find_or_queue(key, Texels::hash(key), [&] { return texels_of.legacy(i); }));
      }
      const typename Cache::Lookup& found = previous->second;
      if (found.found == Cache::Found::Solved)
        write(i, sample, *found.entry, cache, equal);
      else
        waiting.emplace_back(i, found.ticket);
    }
    if (!waiting.empty()) {
      cache.solve_queued();
      for (const auto& [i, ticket] : waiting) write(i, i % stride == 0, cache.entry(ticket), cache, equal);
      waiting.clear();
    }
    cache.measure_errors(set_error);
  };
  run_on_threads(threads, [&] {
    Cache& cache = Cache::for_this_thread(texels / static_cast<size_t>(std::max<std::int64_t>(1, threads)), context);
    std::vector<std::pair<size_t, size_t>> waiting;  // (texel, ticket) of the band's misses
    bool equal = equals_diffuse.load();              // this thread's texels so far
    for (std::int64_t run; (run = next_run.fetch_add(1)) < runs;)
      for (std::int64_t band = run * bands_per_run; band < std::min(bands, (run + 1) * bands_per_run); ++band)
        bake_band(band, cache, waiting, equal);
    cache.finish();
    if (!equal) equals_diffuse = false;
  });
  out.equals_diffuse = equals_diffuse;
}

}  // namespace

BakedTexels bake(const BakeInputs& in, const SolverSettings& settings, size_t max_error_samples) {
  BakedTexels out;
  out.width = in.width;
  out.height = in.height;
  const size_t texels = static_cast<size_t>(in.width) * static_cast<size_t>(in.height);
  // Without an alpha channel in the diffuse, alpha is the factor's: the texels need RGB only.
  const bool alpha_texels = in.diffuse && (in.diffuse->channels == 2 || in.diffuse->channels == 4);
  out.base_channels = alpha_texels ? 4 : 3;
  BakeInputs inputs = in;
  if (inputs.overwrite_diffuse &&
      !(same_layout_as_base(in.diffuse, out) && &in.diffuse->bytes == in.overwrite_diffuse &&
        in.spec_gloss != in.diffuse && ByteTexels::serves(in)))
    inputs.overwrite_diffuse = nullptr;  // not a buffer the bake can write over: a new one
  out.base_color.resize(inputs.overwrite_diffuse ? 0 : texels * static_cast<size_t>(out.base_channels));
  out.metalness.resize(texels);
  if (in.spec_gloss) out.roughness.resize(texels);
  // The first texel's alpha: the factor's, unless the texels carry it (below).
  out.alpha = quantize(in.diffuse_factor.a);
  if (texels == 0) return out;

  if (ByteTexels::serves(inputs))
    bake_texels<ByteTexels>(inputs, settings, max_error_samples, out);
  else
    bake_texels<FloatTexels>(inputs, settings, max_error_samples, out);
  if (inputs.overwrite_diffuse) out.base_color = std::move(*inputs.overwrite_diffuse);
  if (alpha_texels) out.alpha = out.base_color[3];
  if (in.spec_gloss) out.first_roughness = out.roughness[0];

  // Until every map is known to vary: one pass on one thread (a 4096² bake took 13 ms of its wall
  // time to the end, where the first texels had settled all three).
  const size_t base_channels = static_cast<size_t>(out.base_channels);
  for (size_t i = 1;
       i < texels && (out.base_constant || (alpha_texels && out.alpha_constant) || out.metal_rough_constant); ++i) {
    const std::uint8_t* base = &out.base_color[i * base_channels];
    out.base_constant = out.base_constant && std::equal(base, base + 3, &out.base_color[0]);
    out.alpha_constant = out.alpha_constant && (!alpha_texels || base[3] == out.alpha);
    out.metal_rough_constant = out.metal_rough_constant && out.metalness[i] == out.metalness[0] &&
                               (out.roughness.empty() || out.roughness[i] == out.first_roughness);
  }
  return out;
}

size_t error_sample_stride(size_t texels, size_t max_error_samples) {
  return max_error_samples == 0 ? 1 : std::max<size_t>(1, texels / max_error_samples);
}

namespace {

// The distinct stored texels of a batch of at most 4096, by their values' bits (an open-addressed
// table of 8192 slots, each the index plus one).
class DistinctTexels {
 public:
  // `texel`'s index in `distinct`, to which it is added unless an equal one is there.
  std::uint32_t index_of(const StoredTexel& texel, std::vector<StoredTexel>& distinct) {
    const Key key = key_of(texel);
    std::uint64_t h = 0;
    for (const std::uint32_t word : key.words) h = h * 0x9E3779B97F4A7C15ull + word;
    h = mix_bits(h);
    for (size_t slot = h & (kSlots - 1);; slot = (slot + 1) & (kSlots - 1)) {
      if (slots_[slot] == 0) {
        distinct.push_back(texel);
        slots_[slot] = static_cast<std::uint32_t>(distinct.size());
        return slots_[slot] - 1;
      }
      if (key_of(distinct[slots_[slot] - 1]).words == key.words) return slots_[slot] - 1;
    }
  }

 private:
  static constexpr size_t kSlots = 8192;
  struct Key {
    std::array<std::uint32_t, 11> words;  // legacy diffuse, specular, glossiness, base, metalness
  };
  static Key key_of(const StoredTexel& t) {
    const auto bits = [](float f) { return std::bit_cast<std::uint32_t>(f); };
    return {{bits(t.legacy.diffuse.r), bits(t.legacy.diffuse.g), bits(t.legacy.diffuse.b), bits(t.legacy.specular.r),
             bits(t.legacy.specular.g), bits(t.legacy.specular.b), bits(t.legacy.glossiness), bits(t.base.r),
             bits(t.base.g), bits(t.base.b), t.metalness}};
  }
  std::vector<std::uint32_t> slots_ = std::vector<std::uint32_t>(kSlots);
};

// error_a and error_b of every `step`-th error sample of `texels` as the texel `store(sample,
// stored)` writes (stored.legacy is the sample's legacy texel), in batches of bounded scratch on
// the pool (ErrorAccumulator takes each sample once, from any thread).
template <typename Store>
std::pair<ErrorAccumulator, ErrorAccumulator> measure_samples(const BakedTexels& texels, const SolverSettings& settings,
                                                              size_t step, Store store) {
  const bool appearance = settings.error_model == ErrorModel::Appearance;
  const size_t samples = (texels.sampled_legacy.size() + step - 1) / step;
  std::pair<ErrorAccumulator, ErrorAccumulator> errors{ErrorAccumulator(samples, appearance),
                                                       ErrorAccumulator(samples)};
  constexpr size_t kBatch = 4096;
  parallel_dynamic(static_cast<std::int64_t>((samples + kBatch - 1) / kBatch), [&](std::int64_t index) {
    const size_t first = static_cast<size_t>(index) * kBatch;
    const size_t count = std::min(kBatch, samples - first);
    // Samples repeat (flat regions, few colours: BoxTextured's 65,536 samples hold a few thousand
    // distinct texels), so each distinct stored texel of the batch is measured once.
    std::vector<StoredTexel> distinct;
    std::vector<std::uint32_t> distinct_of(count);
    DistinctTexels seen;
    for (size_t j = 0; j < count; ++j) {
      const size_t sample = (first + j) * step;
      StoredTexel texel;
      texel.legacy = texels.sampled_legacy[sample];
      store(sample, texel);
      distinct_of[j] = seen.index_of(texel, distinct);
    }
    std::vector<StoredTexelErrors::DeltaE> delta_e(distinct.size());
    StoredTexelErrors().measure(distinct, appearance, delta_e);
    for (size_t j = 0; j < count; ++j) {
      const StoredTexelErrors::DeltaE& e = delta_e[distinct_of[j]];
      errors.first.set(first + j, e[0], e[1]);
      if (appearance) errors.first.set_appearance(first + j, e[4]);
      errors.second.set(first + j, e[2], e[3]);
    }
  });
  return errors;
}

using Levels = std::array<std::uint8_t, 256>;

// The bytes from one error sample's texel to the next in `base`, checked to be 8-bit RGB(A),
// `channels` a texel, on the bake's grid.
size_t sample_bytes_on_grid(const BakedTexels& texels, std::span<const std::uint8_t> base, int channels) {
  const size_t texel_count = static_cast<size_t>(texels.width) * static_cast<size_t>(texels.height);
  if ((channels != 3 && channels != 4) || base.size() != texel_count * static_cast<size_t>(channels))
    throw std::logic_error("bake: the base colour measured is not 8-bit RGB(A) on the bake's grid");
  return texels.sample_stride * static_cast<size_t>(channels);
}

// The texel as written: its 8-bit sRGB base colour, error sample s's at base[s × sample_bytes]
// (the whole image, sample_bytes_on_grid; or base_at_samples, 3), and the bake's metalness,
// through `levels` where given (fewer_metalness_levels).
auto stored_as_written(const BakedTexels& texels, std::span<const std::uint8_t> base, size_t sample_bytes,
                       const Levels* levels = nullptr) {
  return [&texels, base, sample_bytes, levels](size_t sample, StoredTexel& stored) {
    const std::uint8_t* const rgb = &base[sample * sample_bytes];
    for (int c = 0; c < 3; ++c) stored.base[c] = srgb8_to_linear(rgb[c]);
    const std::uint8_t metalness = texels.metalness[sample * texels.sample_stride];
    stored.metalness = levels ? (*levels)[metalness] : metalness;
  };
}

// The dielectric copy: the diffuse texel times the diffuse factor (what the viewer reads of the
// diffuse image under that factor), metalness 0.
void stored_as_dielectric_copy(size_t, StoredTexel& stored) {
  stored.base = stored.legacy.diffuse;
  stored.metalness = 0;
}

}  // namespace

void measure_as_written(BakedTexels& texels, std::span<const std::uint8_t> base, int channels,
                        const SolverSettings& settings) {
  std::tie(texels.error_a, texels.error_b) = measure_samples(
      texels, settings, 1, stored_as_written(texels, base, sample_bytes_on_grid(texels, base, channels)));
}

TexelBytes base_at_samples(const BakedTexels& texels, std::span<const std::uint8_t> base, int channels) {
  const size_t sample_bytes = sample_bytes_on_grid(texels, base, channels);
  const size_t texel_count = static_cast<size_t>(texels.width) * static_cast<size_t>(texels.height);
  TexelBytes out((texel_count + texels.sample_stride - 1) / texels.sample_stride * 3);
  for (size_t sample = 0; sample < out.size() / 3; ++sample)
    std::memcpy(&out[sample * 3], &base[sample * sample_bytes], 3);
  return out;
}

void measure_dielectric_copy(BakedTexels& texels, const SolverSettings& settings) {
  std::tie(texels.error_a, texels.error_b) = measure_samples(texels, settings, 1, stored_as_dielectric_copy);
}

Levels metalness_levels(const std::array<std::uint64_t, 256>& histogram, int levels) {
  Levels to;
  for (int v = 0; v < 256; ++v) to[static_cast<size_t>(v)] = static_cast<std::uint8_t>(v);
  std::vector<int> values;  // the values texels hold, ascending
  for (int v = 0; v < 256; ++v)
    if (histogram[static_cast<size_t>(v)] > 0) values.push_back(v);
  const int n = static_cast<int>(values.size());
  if (levels < 2 || n <= levels) return to;
  // Prefix sums of the weights w, w v and w v² over the sorted values give a cluster's cost,
  // sum w (v - level)², for any level in constant time.
  std::vector<double> w(static_cast<size_t>(n) + 1), wv(w.size()), wvv(w.size());
  for (int i = 0; i < n; ++i) {
    const double weight = static_cast<double>(histogram[static_cast<size_t>(values[static_cast<size_t>(i)])]);
    const double v = values[static_cast<size_t>(i)];
    w[static_cast<size_t>(i) + 1] = w[static_cast<size_t>(i)] + weight;
    wv[static_cast<size_t>(i) + 1] = wv[static_cast<size_t>(i)] + weight * v;
    wvv[static_cast<size_t>(i) + 1] = wvv[static_cast<size_t>(i)] + weight * v * v;
  }
  // The level of the values i..j (indices into `values`): their weighted mean, rounded to a byte,
  // or 0 or 255 where the cluster holds that end of the range.
  const auto level_of = [&](int i, int j) {
    if (values[static_cast<size_t>(i)] == 0) return 0.0;
    if (values[static_cast<size_t>(j)] == 255) return 255.0;
    const auto a = static_cast<size_t>(i), b = static_cast<size_t>(j) + 1;
    return std::round((wv[b] - wv[a]) / (w[b] - w[a]));
  };
  const auto cost = [&](int i, int j) {
    const auto a = static_cast<size_t>(i), b = static_cast<size_t>(j) + 1;
    const double c = level_of(i, j);
    return (wvv[b] - wvv[a]) - 2.0 * c * (wv[b] - wv[a]) + c * c * (w[b] - w[a]);
  };
  // best[k][j]: the least cost of the first j + 1 values in k + 1 clusters; first[k][j]: where
  // its last cluster starts.
  const auto k_count = static_cast<size_t>(levels), n_count = static_cast<size_t>(n);
  std::vector<double> best(k_count * n_count, std::numeric_limits<double>::infinity());
  std::vector<int> first(k_count * n_count, 0);
  for (int j = 0; j < n; ++j) best[static_cast<size_t>(j)] = cost(0, j);
  for (size_t k = 1; k < k_count; ++k)
    for (int j = static_cast<int>(k); j < n; ++j)
      for (int i = static_cast<int>(k); i <= j; ++i) {
        const double total = best[(k - 1) * n_count + static_cast<size_t>(i) - 1] + cost(i, j);
        if (total < best[k * n_count + static_cast<size_t>(j)])
          best[k * n_count + static_cast<size_t>(j)] = total, first[k * n_count + static_cast<size_t>(j)] = i;
      }
  // Back from the last value, cluster by cluster.
  int j = n - 1;
  for (size_t k = k_count; k-- > 0;) {
    const int i = k == 0 ? 0 : first[k * n_count + static_cast<size_t>(j)];
    const auto level = static_cast<std::uint8_t>(level_of(i, j));
    for (int v = i; v <= j; ++v) to[static_cast<size_t>(values[static_cast<size_t>(v)])] = level;
    j = i - 1;
  }
  return to;
}

namespace {

// Texels a metalness value, counted on the pool with four interleaved counts a thread (a run of
// equal bytes would otherwise wait on its own count from one texel to the next).
std::array<std::uint64_t, 256> histogram_of(std::span<const std::uint8_t> values) {
  const auto size = static_cast<std::int64_t>(values.size());
  const std::int64_t parts = std::clamp<std::int64_t>(size >> 20, 1, ThreadPool::shared().threads());
  std::vector<std::array<std::array<std::uint64_t, 256>, 4>> counts(static_cast<size_t>(parts));
  ThreadPool::shared().run(parts, [&](std::int64_t part) {
    auto& count = counts[static_cast<size_t>(part)];
    count = {};
    const auto begin = static_cast<size_t>(size * part / parts), end = static_cast<size_t>(size * (part + 1) / parts);
    size_t i = begin;
    for (; i + 4 <= end; i += 4)
      ++count[0][values[i]], ++count[1][values[i + 1]], ++count[2][values[i + 2]], ++count[3][values[i + 3]];
    for (; i < end; ++i) ++count[0][values[i]];
  });
  std::array<std::uint64_t, 256> histogram{};
  for (const auto& part : counts)
    for (const auto& count : part)
      for (size_t v = 0; v < 256; ++v) histogram[v] += count[v];
  return histogram;
}

// The step between the error samples a decision looks at, to see about `wanted` of them. Odd: the
// samples run along rows, and an even step that divides a row's count (a power-of-two texture's)
// would look at a few columns only (4096²: one).
size_t decision_step(size_t samples, size_t wanted) {
  return std::max<size_t>(1, samples / std::max<size_t>(1, wanted)) | 1;
}

}  // namespace

MetalnessLevels fewer_metalness_levels(BakedTexels& texels, std::span<const std::uint8_t> base_at_samples,
                                       const SolverSettings& settings, double tolerance) {
  const std::array<std::uint64_t, 256> histogram = histogram_of(texels.metalness);
  MetalnessLevels out;
  out.solved = out.written = static_cast<int>(
      std::count_if(histogram.begin(), histogram.end(), [](std::uint64_t count) { return count > 0; }));
  if (!(tolerance > 0) || out.solved <= 2 || texels.sampled_legacy.empty() || texels.metal_rough_constant) return out;
  if (base_at_samples.size() != texels.sampled_legacy.size() * 3)
    throw std::logic_error("fewer_metalness_levels: the base colour is not RGB at each error sample");
  const auto measure = [&](size_t step, const Levels* levels) {
    return measure_samples(texels, settings, step, stored_as_written(texels, base_at_samples, 3, levels));
  };
  const auto judged = [&](const ErrorAccumulator& errors) { return errors.judged(settings.error_model); };
  // A candidate is looked at on kDecisionSamples of the samples first (most that fail, fail
  // there), then judged on every sample against the figures measured on the same base colour,
  // so the rise the report shows is the rise allowed.
  const size_t step = decision_step(texels.sampled_legacy.size(), kDecisionSamples);
  const double solved = judged(texels.error_a);
  const double solved_part = step > 1 ? judged(measure(step, nullptr).first) : solved;
  for (int count = 2; count <= kMostMetalnessLevels && count < out.solved; ++count) {
    const Levels levels = metalness_levels(histogram, count);
    if (step > 1 && !(judged(measure(step, &levels).first) - solved_part <= tolerance)) continue;
    auto errors = measure(1, &levels);
    if (!(judged(errors.first) - solved <= tolerance)) continue;
    std::uint8_t* const metalness = texels.metalness.data();
    parallel_for(0, static_cast<std::int64_t>(texels.metalness.size()),
                 [&](std::int64_t i) { metalness[i] = levels[metalness[i]]; });
    std::tie(texels.error_a, texels.error_b) = std::move(errors);
    std::array<bool, 256> held{};
    for (size_t v = 0; v < 256; ++v)
      if (histogram[v] > 0) held[levels[v]] = true;
    out.written = static_cast<int>(std::count(held.begin(), held.end(), true));
    break;
  }
  return out;
}

WrittenAgainstCopy written_against_copy(const BakedTexels& texels, std::span<const std::uint8_t> base, int channels,
                                        const SolverSettings& settings, size_t samples) {
  const size_t step = decision_step(texels.sampled_legacy.size(), samples);
  WrittenAgainstCopy out;
  out.written = measure_samples(texels, settings, step,
                                stored_as_written(texels, base, sample_bytes_on_grid(texels, base, channels)))
                    .first.finish();
  out.copy = measure_samples(texels, settings, step, stored_as_dielectric_copy).first.finish();
  out.samples = (texels.sampled_legacy.size() + step - 1) / step;
  return out;
}

std::optional<BakedTexels::Indexed> BakedTexels::metal_rough_indexed() const {
  // One pass, no hashing: the (roughness, metalness) pair is a 16-bit key, and its slot in the
  // palette (plus one; 0: not seen yet) sits in a 128 KB table. Interleaving the map, then
  // scanning it for its colours (hashed) and looking each texel's index up again, took about
  // 125 ms of CPU for Avocado's 4096² map, on the thread beside the base colour's deflate, against
  // about 25 here (perf samples; bench/RESULTS.md, session 32).
  std::vector<std::uint16_t> slot_of(1u << 16, 0);
  Indexed out;
  out.indices = TexelBytes(metalness.size());
  for (size_t i = 0; i < metalness.size(); ++i) {
    const std::uint8_t rough = roughness.empty() ? first_roughness : roughness[i];
    std::uint16_t& slot = slot_of[static_cast<size_t>(rough) << 8 | metalness[i]];
    if (slot == 0) {
      if (out.palette.size() == 256) return std::nullopt;
      out.palette.push_back(std::uint32_t{rough} << 8 | std::uint32_t{metalness[i]} << 16 | 0xFF000000u);
      slot = static_cast<std::uint16_t>(out.palette.size());
    }
    out.indices[i] = static_cast<std::uint8_t>(slot - 1);
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
