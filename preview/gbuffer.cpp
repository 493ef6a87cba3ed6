// G-buffer packing and the material resolve pass (see gbuffer.hpp).
#include "preview/gbuffer.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <glm/geometric.hpp>
#include <limits>
#include <map>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#include "converter/solver.hpp"
#include "core/color.hpp"
#include "preview/texture_sampler.hpp"

namespace gltf_pbr::preview {
namespace {

// Round half up by truncation: the value is clamped non-negative first (std::lround is a libm call).
std::uint8_t unorm8(float v) {
  const float clamped = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;  // NaN -> 0
  return static_cast<std::uint8_t>(clamped * 255.0f + 0.5f);
}
std::uint8_t srgb8(float linear) { return encode_srgb8(linear); }

}  // namespace

// unorm8(linear_to_srgb(x)) steps from k - 1 to k where linear_to_srgb(x) = (k - 0.5) / 255, that
// is at x = srgb_to_linear((k - 0.5) / 255) (IEC 61966-2-1 is monotonic): 255 transfer-function
// calls build the tables instead of 65536, which a one-image run would pay in its G-buffer time.
const SrgbEncodeTables kSrgbEncode = [] {
  SrgbEncodeTables tables{};
  std::uint32_t step = 0;
  for (std::uint32_t k = 1; k < 256; ++k) {
    const float first = srgb_to_linear((static_cast<float>(k) - 0.5f) / 255.0f) * 65535.0f;
    for (; step < 65536 && static_cast<float>(step) < first; ++step)
      if (step % 16 == 0) tables.bucket_code[step / 16] = static_cast<std::uint8_t>(k - 1);
    tables.first_step[k] = step;
  }
  for (; step < 65536; ++step)
    if (step % 16 == 0) tables.bucket_code[step / 16] = 255;
  tables.first_step[256] = 65536;
  return tables;
}();

float decode_srgb8(std::uint8_t encoded) { return srgb8_to_linear(encoded); }

namespace {

glm::vec2 sign_not_zero(glm::vec2 v) { return {v.x >= 0.0f ? 1.0f : -1.0f, v.y >= 0.0f ? 1.0f : -1.0f}; }

}  // namespace

std::uint32_t pack_octahedral_12_12(glm::vec3 n) {
  // Cigolle et al. 2014, listing 1: project onto the octahedron, fold the lower hemisphere. A
  // normal with no direction (zero, NaN or infinite: a skin that scales past float's range) is
  // stored as +Z rather than converted out of range.
  const float l1 = std::abs(n.x) + std::abs(n.y) + std::abs(n.z);
  n = l1 > 0.0f && std::isfinite(l1) ? n / l1 : glm::vec3(0.0f, 0.0f, 1.0f);
  glm::vec2 e(n.x, n.y);
  if (n.z < 0.0f) e = (glm::vec2(1.0f) - glm::abs(glm::vec2(e.y, e.x))) * sign_not_zero(e);
  auto q = [](float v) {
    return static_cast<std::uint32_t>((std::clamp(v, -1.0f, 1.0f) * 0.5f + 0.5f) * 4095.0f + 0.5f);
  };
  return q(e.x) | (q(e.y) << 12);
}

glm::vec3 unpack_octahedral_12_12(std::uint32_t bits) {
  const glm::vec2 e(static_cast<float>(bits & 4095u) / 4095.0f * 2.0f - 1.0f,
                    static_cast<float>((bits >> 12) & 4095u) / 4095.0f * 2.0f - 1.0f);
  glm::vec3 n(e.x, e.y, 1.0f - std::abs(e.x) - std::abs(e.y));
  if (n.z < 0.0f) {
    const glm::vec2 folded = (glm::vec2(1.0f) - glm::abs(glm::vec2(n.y, n.x))) * sign_not_zero(glm::vec2(n.x, n.y));
    n.x = folded.x, n.y = folded.y;
  }
  return glm::normalize(n);
}

std::uint32_t pack_rgb9e5(glm::vec3 rgb) {
  // EXT_texture_shared_exponent, section "Encoding": N = 9 mantissa bits, B = 15, Emax = 31.
  constexpr float kMax = 511.0f / 512.0f * 65536.0f;
  const float r = std::clamp(rgb.x, 0.0f, kMax), g = std::clamp(rgb.y, 0.0f, kMax), b = std::clamp(rgb.z, 0.0f, kMax);
  const float max_c = std::max({r, g, b});
  if (!(max_c > 0.0f)) return 0;
  int exponent = std::max(-16, static_cast<int>(std::floor(std::log2(max_c)))) + 1 + 15;
  float scale = std::exp2(static_cast<float>(exponent - 15 - 9));
  if (std::lround(max_c / scale) == 512) scale *= 2.0f, ++exponent;
  auto m = [&](float c) { return static_cast<std::uint32_t>(std::lround(c / scale)) & 511u; };
  return m(r) | (m(g) << 9) | (m(b) << 18) | (static_cast<std::uint32_t>(exponent) << 27);
}

glm::vec3 unpack_rgb9e5(std::uint32_t bits) {
  const float scale = std::exp2(static_cast<float>(static_cast<int>(bits >> 27) - 15 - 9));
  return glm::vec3(static_cast<float>(bits & 511u), static_cast<float>((bits >> 9) & 511u),
                   static_cast<float>((bits >> 18) & 511u)) *
         scale;
}

NormalAndScalar pack_normal_and_scalar(glm::vec3 unit_normal, float scalar01) {
  return {pack_octahedral_12_12(unit_normal) | (static_cast<std::uint32_t>(unorm8(scalar01)) << 24)};
}
glm::vec3 normal_of(NormalAndScalar packed) { return unpack_octahedral_12_12(packed.bits & 0xFFFFFFu); }
float scalar_of(NormalAndScalar packed) { return static_cast<float>(packed.bits >> 24) / 255.0f; }

std::vector<BufferSize> GBuffer::layout() const {
  std::vector<BufferSize> out;
  if (!depth.empty()) out.push_back({"depth (float32)", sizeof(Depth)});
  if (!normal.empty())
    out.push_back({albedo.empty() ? "normal octahedral 12+12 + gloss 8" : "normal octahedral 12+12 + roughness 8",
                   sizeof(NormalAndScalar)});
  if (!albedo.empty()) out.push_back({"albedo sRGB8 x3 + metalness 8", sizeof(AlbedoMetalness)});
  if (!diffspec.empty()) out.push_back({"diffuse sRGB8 x3 + specular sRGB8 x3", sizeof(DiffuseSpecular)});
  if (!emissive.empty()) out.push_back({"emissive RGB9E5", sizeof(Emissive)});
  if (!occlusion.empty()) out.push_back({"occlusion 8", sizeof(Occlusion)});
  return out;
}

int GBuffer::bytes_per_pixel() const {
  int total = 0;
  for (const auto& b : layout()) total += b.bytes_per_pixel;
  return total;
}

namespace {

// One side's texel; `unpack_normal` false leaves the normal at its default for callers that
// already hold it (the normal bits are the same on both sides, see light_both).
GBufferTexel read_side(const GBuffer& g, size_t i, bool after, bool unpack_normal) {
  GBufferTexel t;
  t.covered = std::isfinite(g.depth[i]);
  if (!t.covered) return t;
  const auto& lut = srgb8_to_linear_table();
  if (unpack_normal) t.normal = normal_of(g.normal[i]);
  t.scalar = scalar_of(g.normal[i]);
  if (after) {
    const AlbedoMetalness& a = g.albedo[i];
    t.color_a = glm::vec3(lut[a.albedo_srgb[0]], lut[a.albedo_srgb[1]], lut[a.albedo_srgb[2]]);
    t.color_b = glm::vec3(static_cast<float>(a.metalness) / 255.0f, 0.0f, 0.0f);
  } else {
    const DiffuseSpecular& d = g.diffspec[i];
    t.color_a = glm::vec3(lut[d.diffuse_srgb[0]], lut[d.diffuse_srgb[1]], lut[d.diffuse_srgb[2]]);
    t.color_b = glm::vec3(lut[d.specular_srgb[0]], lut[d.specular_srgb[1]], lut[d.specular_srgb[2]]);
  }
  if (!g.emissive.empty()) t.emissive = unpack_rgb9e5(g.emissive[i].rgb9e5);
  if (!g.occlusion.empty()) t.occlusion = static_cast<float>(g.occlusion[i]) / 255.0f;
  return t;
}

// Texture footprint by ray differentials (Igehy 1999, "Tracing Ray Differentials"): the rays
// through the next pixel in x and in y, intersected with the triangle's plane (Moller & Trumbore
// 1997), give the change of barycentrics and so of each UV set. Zero where they are not finite,
// and for an orthographic camera (the sphere grid, which has no textures).
[[gnu::always_inline]] inline UvDerivatives uv_derivatives(const Scene& scene, const Triangle& triangle,
                                                           const Camera& camera, const RayGenerator& rays, int x,
                                                           int y) {
  UvDerivatives derivatives;
  const Vertex& v0 = scene.vertices[triangle.vertex[0]];
  const Vertex& v1 = scene.vertices[triangle.vertex[1]];
  const Vertex& v2 = scene.vertices[triangle.vertex[2]];
  const glm::vec3 e1 = v1.position - v0.position, e2 = v2.position - v0.position;
  const glm::vec3 origin = camera.orthographic ? glm::vec3(0.0f) : glm::vec3(camera.eye - glm::dvec3(v0.position));
  auto barycentric_of_ray = [&](float px, float py) {
    const glm::vec3 d = rays.unnormalised(px, py);  // the scale of d cancels out
    const glm::vec3 pvec = glm::cross(d, e2);
    const float inverse_det = 1.0f / glm::dot(e1, pvec);
    const glm::vec3 qvec = glm::cross(origin, e1);
    return glm::vec2(glm::dot(origin, pvec), glm::dot(d, qvec)) * inverse_det;
  };
  const float cx = static_cast<float>(x) + 0.5f, cy = static_cast<float>(y) + 0.5f;
  const glm::vec2 centre = barycentric_of_ray(cx, cy);
  const glm::vec2 step_x = barycentric_of_ray(cx + 1.0f, cy) - centre;
  const glm::vec2 step_y = barycentric_of_ray(cx, cy + 1.0f) - centre;
  if (std::isfinite(step_x.x + step_x.y + step_y.x + step_y.y) && !camera.orthographic)
    for (int set = 0; set < 2; ++set) {
      const glm::vec2 du1 = v1.uv[set] - v0.uv[set], du2 = v2.uv[set] - v0.uv[set];
      derivatives.dx[set] = du1 * step_x.x + du2 * step_x.y;
      derivatives.dy[set] = du1 * step_y.x + du2 * step_y.y;
    }
  return derivatives;
}

}  // namespace

GBufferTexel read_after(const GBuffer& g, size_t i) { return read_side(g, i, true, true); }
GBufferTexel read_before(const GBuffer& g, size_t i) { return read_side(g, i, false, true); }
GBufferTexel read_before_material(const GBuffer& g, size_t i) { return read_side(g, i, false, false); }

GBuffers fill_gbuffers(const Scene& scene, const VisibilityBuffer& visibility, const Camera& camera) {
  GBuffers out;
  const size_t count = visibility.samples.size();
  // Sized, not cleared: the loop below writes every pixel, empty ones with the defaults.
  for (GBuffer* g : {&out.before, &out.after}) {
    g->width = visibility.width;
    g->height = visibility.height;
    g->depth.resize(count);
    g->normal.resize(count);
    if (scene.stats.uses_emission) g->emissive.resize(count);
    if (scene.stats.uses_occlusion) g->occlusion.resize(count);
  }
  out.after.albedo.resize(count);
  out.before.diffspec.resize(count);
  const int width = visibility.width;
  const RayGenerator rays(camera, visibility.width, visibility.height);
  // Which of a material's textures share texel coordinates and mip level (texture_sampler.hpp).
  std::vector<MaterialSamplingPlan> plans;
  plans.reserve(scene.materials.size());
  for (const PreviewMaterial& material : scene.materials) plans.push_back(plan_sampling(material));
  parallel_dynamic(visibility.height, [&](std::int64_t y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
      const VisibilitySample& s = visibility.samples[i];
      if (s.empty()) {
        out.after.depth[i] = out.before.depth[i] = std::numeric_limits<float>::infinity();
        out.after.normal[i] = out.before.normal[i] = NormalAndScalar{0};
        out.after.albedo[i] = AlbedoMetalness{};
        out.before.diffspec[i] = DiffuseSpecular{};
        if (scene.stats.uses_occlusion) out.after.occlusion[i] = out.before.occlusion[i] = 255;
        if (scene.stats.uses_emission) out.after.emissive[i] = out.before.emissive[i] = Emissive{0};
        continue;
      }
      const std::uint32_t triangle_index = s.index();
      const Triangle& triangle = scene.triangles[triangle_index];
      const PreviewMaterial& m = scene.materials[static_cast<size_t>(triangle.material)];
      const MaterialSamplingPlan& plan = plans[static_cast<size_t>(triangle.material)];
      const SurfacePoint p = interpolate(scene, triangle_index, glm::vec3(1.0f - s.b1 - s.b2, s.b1, s.b2));
      const UvDerivatives derivatives =
          plan.textured ? uv_derivatives(scene, triangle, camera, rays, x, static_cast<int>(y)) : UvDerivatives{};
      PixelSampler sample(plan, p.uv, &derivatives);
      // Shading normal (glTF 2.0 section 3.7.2.1: flat normals without NORMAL; back faces of
      // double-sided materials reverse their normals, section 3.9.5).
      const float face_length = glm::length(p.face_normal);
      glm::vec3 geometric = face_length > 0.0f ? p.face_normal / face_length : glm::vec3(0, 0, 1);
      glm::vec3 n = glm::length(p.normal) > 1e-12f ? glm::normalize(p.normal) : geometric;
      const float facing = s.back_facing() ? -1.0f : 1.0f;
      n *= facing;
      if (m.normal_texture && p.tangent.w != 0.0f) {
        // Section 3.9.3: sampled = (rgb * 2 - 1) * (scale, scale, 1) in the tangent frame.
        const glm::vec3 t0 = glm::vec3(p.tangent) * facing;
        const glm::vec3 t = t0 - n * glm::dot(n, t0);
        const float t_length = glm::length(t);
        if (t_length > 1e-12f) {
          const glm::vec3 tangent = t / t_length;
          const glm::vec3 bitangent = glm::cross(n, tangent) * (p.tangent.w < 0.0f ? -1.0f : 1.0f);
          const glm::vec4 texel = sample(m.normal_texture, kNormalSlot);
          const glm::vec3 local = glm::vec3((texel.x * 2.0f - 1.0f) * m.normal_scale,
                                            (texel.y * 2.0f - 1.0f) * m.normal_scale, texel.z * 2.0f - 1.0f);
          const glm::vec3 mapped = tangent * local.x + bitangent * local.y + n * local.z;
          const float mapped_length = glm::length(mapped);
          if (mapped_length > 1e-12f && std::isfinite(mapped_length)) n = mapped / mapped_length;
        }
      }
      const float depth = 1.0f / s.inverse_depth;
      // "after": core metal-rough (section 3.9.2), COLOR_0 multiplies the base colour.
      glm::vec4 base = m.base_color_factor * p.color;
      if (m.base_color_texture) base *= sample(m.base_color_texture, kBaseColorSlot);
      float metallic = m.metallic_factor, roughness = m.roughness_factor;
      if (m.metallic_roughness_texture) {
        const glm::vec4 mr = sample(m.metallic_roughness_texture, kMetallicRoughnessSlot);
        roughness *= mr.y;
        metallic *= mr.z;
      }
      // "before": the legacy spec-gloss inputs (archived extension: diffuse RGB sRGB, A linear;
      // specularGlossiness RGB sRGB, A linear), or the original metal-rough mapped by to_spec_gloss.
      glm::vec3 diffuse, specular;
      float glossiness;
      if (m.has_spec_gloss) {
        glm::vec4 d = m.diffuse_factor * p.color;
        if (m.diffuse_texture) d *= sample(m.diffuse_texture, kDiffuseSlot);
        glm::vec4 sg(m.specular_factor, m.glossiness_factor);
        if (m.spec_gloss_texture) sg *= sample(m.spec_gloss_texture, kSpecGlossSlot);
        diffuse = glm::vec3(d);
        specular = glm::vec3(sg);
        glossiness = sg.w;
      } else {
        glm::vec4 ob = m.original_base_color_factor * p.color;
        if (m.original_base_color_texture) ob *= sample(m.original_base_color_texture, kOriginalBaseColorSlot);
        MetalRough core{glm::vec3(ob), m.original_metallic_factor, m.original_roughness_factor};
        if (m.original_metallic_roughness_texture) {
          const glm::vec4 mr = sample(m.original_metallic_roughness_texture, kOriginalMetallicRoughnessSlot);
          core.roughness *= mr.y;
          core.metalness *= mr.z;
        }
        const SpecGloss legacy = to_spec_gloss(core);
        diffuse = legacy.diffuse, specular = legacy.specular, glossiness = legacy.glossiness;
      }
      out.after.depth[i] = out.before.depth[i] = depth;
      const std::uint32_t normal_bits = pack_octahedral_12_12(n);  // one encoding for both sides
      out.after.normal[i] = {normal_bits | (static_cast<std::uint32_t>(unorm8(roughness)) << 24)};
      out.before.normal[i] = {normal_bits | (static_cast<std::uint32_t>(unorm8(glossiness)) << 24)};
      out.after.albedo[i] = {{srgb8(base.x), srgb8(base.y), srgb8(base.z)}, unorm8(metallic)};
      out.before.diffspec[i] = {{srgb8(diffuse.x), srgb8(diffuse.y), srgb8(diffuse.z)},
                                {srgb8(specular.x), srgb8(specular.y), srgb8(specular.z)}};
      if (scene.stats.uses_occlusion) {
        float occlusion = 1.0f;  // section 3.9.4: lerp(1, sampled R, strength)
        if (m.occlusion_texture)
          occlusion = 1.0f + m.occlusion_strength * (sample(m.occlusion_texture, kOcclusionSlot).x - 1.0f);
        out.after.occlusion[i] = out.before.occlusion[i] = unorm8(occlusion);
      }
      if (scene.stats.uses_emission) {
        glm::vec3 emissive = m.emissive_factor;
        if (m.emissive_texture) emissive *= glm::vec3(sample(m.emissive_texture, kEmissiveSlot));
        out.after.emissive[i] = out.before.emissive[i] = Emissive{pack_rgb9e5(emissive)};
      }
    }
  });
  return out;
}

std::vector<int> finest_sampled_levels(const Scene& scene, const VisibilityBuffer& visibility, const Camera& camera) {
  std::map<const Texture*, size_t> index_of;
  for (size_t i = 0; i < scene.textures.size(); ++i) index_of[scene.textures[i].get()] = i;
  // Per material and footprint group, the textures its slots read (fill_gbuffers' groups).
  std::vector<MaterialSamplingPlan> plans;
  std::vector<std::vector<std::vector<size_t>>> group_textures;
  for (const PreviewMaterial& material : scene.materials) {
    plans.push_back(plan_sampling(material));
    auto& groups = group_textures.emplace_back(static_cast<size_t>(plans.back().group_count));
    for (int s = 0; s < MaterialSamplingPlan::kSlots; ++s)
      if (const int g = plans.back().group[static_cast<size_t>(s)]; g >= 0)
        groups[static_cast<size_t>(g)].push_back(index_of.at(slot_of(material, static_cast<MaterialSlot>(s)).texture));
  }
  const RayGenerator rays(camera, visibility.width, visibility.height);
  std::vector<std::atomic<int>> finest(scene.textures.size());
  for (auto& level : finest) level = kUnsampled;
  parallel_dynamic(visibility.height, [&](std::int64_t y) {
    std::vector<int> row(scene.textures.size(), kUnsampled);
    for (int x = 0; x < visibility.width; ++x) {
      const VisibilitySample& s =
          visibility.samples[static_cast<size_t>(y) * static_cast<size_t>(visibility.width) + static_cast<size_t>(x)];
      if (s.empty()) continue;
      const Triangle& triangle = scene.triangles[s.index()];
      const auto material = static_cast<size_t>(triangle.material);
      if (!plans[material].textured) continue;
      const UvDerivatives derivatives = uv_derivatives(scene, triangle, camera, rays, x, static_cast<int>(y));
      const SurfacePoint p = interpolate(scene, s.index(), glm::vec3(1.0f - s.b1 - s.b2, s.b1, s.b2));
      for (int g = 0; g < plans[material].group_count; ++g) {
        const TextureSlot& source = *plans[material].group_source[static_cast<size_t>(g)];
        const int level = static_cast<int>(slot_lookup(source, p.uv, &derivatives).lod);  // footprint_of's first
        for (size_t texture : group_textures[material][static_cast<size_t>(g)])
          row[texture] = std::min(row[texture], level);
      }
    }
    for (size_t t = 0; t < row.size(); ++t)
      for (int seen = finest[t]; row[t] < seen && !finest[t].compare_exchange_weak(seen, row[t]);) {
      }
  });
  std::vector<int> out;
  for (const auto& level : finest) out.push_back(level);
  return out;
}

}  // namespace gltf_pbr::preview
