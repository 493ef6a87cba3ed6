// Helpers for comparing `gltf-pbr preview` with Blender Cycles (bench/preview.sh):
//   gltf-pbr-preview-peer sky OUT.hdr
//     The built-in environment as a Radiance .hdr (Ward 1991, flat RGBE scanlines) for Blender:
//     the procedural sky, plus the analytic sun as a small disc carrying the same irradiance.
//     Columns are turned to Blender's equirectangular convention (see kBlenderQuarterTurn).
//   gltf-pbr-preview-peer fidelity IN.gltf OURS.png PEER.png
//     LDR-FLIP mean over the whole image with Blender's as the reference (preview/flip.hpp),
//     CIEDE2000 mean and p95 over the pixels our default framing covers, and RMS-dB over the
//     whole image (preview/metrics.hpp), as one JSON line.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/files.hpp"
#include "core/image.hpp"
#include "preview/flip.hpp"
#include "preview/preview.hpp"

using namespace gltf_pbr;
using namespace gltf_pbr::preview;

namespace {

// Cycles reads an equirectangular map at u = 0.5 - atan2(d.y, d.x) / 2 pi (Blender axes); the
// glTF importer maps glTF (x, y, z) to Blender (x, -z, y), so a glTF direction lands at
// u = 0.5 + atan2(z, x) / 2 pi, a quarter turn behind our u = 0.5 + atan2(x, -z) / 2 pi
// (environment.hpp). File column u therefore holds our map at u + 1/4. Checked on
// CesiumMilkTruck at 512^2: mean ΔE2000 against our render 5.6 with this turn; 12.8, 7.4 and
// 11.4 with the other three, and only this one puts the lit and shaded sides where ours are.
constexpr float kBlenderQuarterTurn = 0.25f;

// Radiance .hdr: "#?RADIANCE", FORMAT=32-bit_rle_rgbe, "-Y H +X W" (top row first), flat scanlines.
std::vector<std::uint8_t> encode_radiance_hdr(const std::vector<glm::vec3>& texels, int width, int height) {
  const std::string header =
      "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(height) + " +X " + std::to_string(width) + "\n";
  std::vector<std::uint8_t> out(header.begin(), header.end());
  for (const glm::vec3& c : texels) {
    const float largest = std::max({c.x, c.y, c.z});
    if (!(largest > 1e-32f)) {
      out.insert(out.end(), {0, 0, 0, 0});
      continue;
    }
    int exponent = 0;
    const float scale = std::frexp(largest, &exponent) * 256.0f / largest;  // Ward 1991, RGBE
    out.insert(
        out.end(),
        {static_cast<std::uint8_t>(std::max(0.0f, c.x) * scale), static_cast<std::uint8_t>(std::max(0.0f, c.y) * scale),
         static_cast<std::uint8_t>(std::max(0.0f, c.z) * scale), static_cast<std::uint8_t>(exponent + 128)});
  }
  return out;
}

int write_sky(const fs::path& output) {
  const Environment& env = default_environment();
  const EquirectMap& sky = env.specular_levels[0];  // unfiltered radiance (environment.cpp)
  const int width = 1024, height = 512;
  std::vector<glm::vec3> texels(static_cast<size_t>(width) * height);
  // The sun: a disc of 1 degree radius whose radiance times its solid angle is the sun's
  // irradiance at normal incidence (E = L * omega for a small source).
  const float sun_cos = std::cos(1.0f * kPi / 180.0f);
  double sun_solid_angle = 0;
  std::vector<size_t> sun_texels;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float u = (static_cast<float>(x) + 0.5f) / width, v = (static_cast<float>(y) + 0.5f) / height;
      const float ours_u = u + kBlenderQuarterTurn;
      const glm::vec2 uv(ours_u - std::floor(ours_u), v);
      const size_t i = static_cast<size_t>(y) * width + static_cast<size_t>(x);
      texels[i] = sky.sample_uv(uv);
      if (glm::dot(direction_of(uv.x, uv.y), env.sun_direction) > sun_cos) {
        sun_texels.push_back(i);
        // Solid angle of an equirect texel: (2 pi / W) (pi / H) sin(theta).
        sun_solid_angle += (2.0 * kPi / width) * (kPi / height) * std::sin(v * kPi);
      }
    }
  if (sun_solid_angle > 0)
    for (size_t i : sun_texels) texels[i] += env.sun_irradiance / static_cast<float>(sun_solid_angle);
  AtomicWriteSet files;
  files.stage(output, encode_radiance_hdr(texels, width, height));
  files.commit();
  return 0;
}

std::vector<std::uint8_t> read_rgb8(const fs::path& path) {
  const auto bytes = read_file(path);
  if (!bytes) throw std::runtime_error(path.string() + ": cannot read");
  const Pixels pixels = decode_image(*bytes, path.string());
  std::vector<std::uint8_t> rgb(static_cast<size_t>(pixels.width) * pixels.height * 3);
  for (size_t p = 0; p < static_cast<size_t>(pixels.width) * pixels.height; ++p)
    for (size_t c = 0; c < 3; ++c)
      rgb[p * 3 + c] = static_cast<std::uint8_t>(
          std::lround(std::clamp(pixels.value(p * static_cast<size_t>(pixels.channels) + c), 0.0f, 1.0f) * 255.0f));
  return rgb;
}

int fidelity(const fs::path& gltf, const fs::path& ours_png, const fs::path& peer_png) {
  const auto ours = read_rgb8(ours_png), peer = read_rgb8(peer_png);
  if (ours.size() != peer.size()) throw std::runtime_error("images differ in size");
  const int size = static_cast<int>(std::lround(std::sqrt(static_cast<double>(ours.size() / 3))));
  // Coverage of our default framing (PreviewOptions): the object, not the two backgrounds.
  const Asset asset = load_asset(gltf);
  const Scene scene = build_scene(asset, asset);
  const PreviewOptions defaults;
  const Camera camera =
      frame_camera(scene.bounds, defaults.yaw_degrees, defaults.pitch_degrees, defaults.fov_y_degrees, 1.0);
  const VisibilityBuffer visibility = rasterize(scene, camera, size, size);
  std::vector<std::uint8_t> covered(visibility.samples.size());
  for (size_t i = 0; i < covered.size(); ++i) covered[i] = !visibility.samples[i].empty();
  const DifferenceMetrics m = compare_images(ours, peer, covered, size, size);
  const double flip_mean = flip(peer, ours, size, size).mean;
  std::printf(
      "{\"flip_mean\": %.4f, \"delta_e_2000_mean\": %.3f, \"delta_e_2000_p95\": %.3f, \"rms_db\": %.2f, "
      "\"pixels\": %lld}\n",
      flip_mean, m.delta_e_mean, m.delta_e_p95, m.rms_db, m.pixels_compared);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::string command = argc > 1 ? argv[1] : "";
    if (command == "sky" && argc == 3) return write_sky(argv[2]);
    if (command == "fidelity" && argc == 5) return fidelity(argv[2], argv[3], argv[4]);
    std::fprintf(stderr,
                 "usage: gltf-pbr-preview-peer sky OUT.hdr\n"
                 "       gltf-pbr-preview-peer fidelity IN.gltf OURS.png PEER.png\n");
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gltf-pbr-preview-peer: %s\n", e.what());
    return 1;
  }
}
