// Golden images with a tolerance; GLTF_PBR_UPDATE_GOLDEN=1 rewrites them (tests/preview/golden).
#include <gtest/gtest.h>

#include <cstdlib>

#include "core/image.hpp"
#include "preview/preview.hpp"

namespace gltf_pbr::preview {
namespace {

// Passes when the mean channel difference is under 1 level and under 0.5% of pixels differ by
// more than 16 levels (platform float differences move a few pixels, not the picture).
void expect_matches_golden(const std::vector<std::uint8_t>& rgb, int width, int height, const std::string& name) {
  const fs::path path = fs::path(GLTF_PBR_GOLDEN_DIR) / (name + ".png");
  const char* update = std::getenv("GLTF_PBR_UPDATE_GOLDEN");
  if (update && std::string(update) == "1") {
    fs::create_directories(path.parent_path());
    AtomicWriteSet files;
    files.stage(path, encode_png(rgb, width, height, 3, 9));
    files.commit();
    return;
  }
  const auto bytes = read_file(path);
  ASSERT_TRUE(bytes) << path << " is missing; run with GLTF_PBR_UPDATE_GOLDEN=1 to create it";
  const Pixels golden = decode_image(*bytes, path.string());
  ASSERT_EQ(golden.width, width);
  ASSERT_EQ(golden.height, height);
  ASSERT_EQ(golden.channels, 3);
  double sum = 0;
  long outliers = 0;
  for (size_t i = 0; i < rgb.size(); ++i) {
    const double d = std::abs(golden.value(i) * 255.0 - rgb[i]);
    sum += d;
    outliers += d > 16.0;
  }
  EXPECT_LT(sum / static_cast<double>(rgb.size()), 1.0) << name;
  EXPECT_LT(static_cast<double>(outliers) / static_cast<double>(rgb.size()), 0.005) << name;
}

TEST(Golden, SphereGridBeforeAndAfter) {
  GridOptions grid;
  grid.albedo = glm::vec3(0.8f, 0.5f, 0.3f);
  grid.rows = grid.columns = 4;
  grid.cell = 40;
  const PreviewResult r = render_grid(grid, PreviewOptions{});
  expect_matches_golden(r.before, r.width, r.height, "grid_before");
  expect_matches_golden(r.after, r.width, r.height, "grid_after");
}

// A shared spec-gloss asset drawn at 128²; without ../shared, load_asset fails the test naming the file.
PreviewResult render_shared_asset(const std::string& relative) {
  PreviewOptions options;
  options.width = options.height = 128;
  return render_preview(load_asset(fs::path(GLTF_PBR_SHARED_DIR) / "assets" / relative), options);
}

TEST(Golden, BoxTexturedBeforeAndAfter) {
  const PreviewResult r = render_shared_asset("BoxTextured/specgloss/BoxTextured.gltf");
  expect_matches_golden(r.before, r.width, r.height, "box_textured_before");
  expect_matches_golden(r.after, r.width, r.height, "box_textured_after");
}

TEST(Golden, DuckAfter) {
  const PreviewResult r = render_shared_asset("Duck/specgloss/Duck.gltf");
  expect_matches_golden(r.after, r.width, r.height, "duck_after");
}

}  // namespace
}  // namespace gltf_pbr::preview
