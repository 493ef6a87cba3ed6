// The built-in environment, baked at build time (preview/bake_tables.cpp): its prefiltered levels and
// irradiance are the same for every process, so no process computes them (issue 15).
#include <algorithm>

#include "preview/environment.hpp"

namespace gltf_pbr::preview {
namespace baked {  // defined in the generated default_environment_data.cpp
extern const int kSkyLevelCount;
extern const int kSkyLevelSize[][2];  // width, height of each level
extern const float kSkyTexels[];      // the levels one after another, RGB per texel
extern const float kSkyIrradianceSh[27];
}  // namespace baked

const Environment& default_environment() {
  static const Environment env = [] {
    Environment e;
    const float* texel = baked::kSkyTexels;
    for (int level = 0; level < baked::kSkyLevelCount; ++level) {
      EquirectMap map{baked::kSkyLevelSize[level][0], baked::kSkyLevelSize[level][1], {}};
      map.texels.resize(static_cast<size_t>(map.width) * static_cast<size_t>(map.height));
      for (glm::vec3& t : map.texels) t = glm::vec3(texel[0], texel[1], texel[2]), texel += 3;
      e.specular_levels.push_back(std::move(map));
    }
    for (size_t i = 0; i < e.irradiance_sh.size(); ++i)
      e.irradiance_sh[i] = glm::vec3(baked::kSkyIrradianceSh[3 * i], baked::kSkyIrradianceSh[3 * i + 1],
                                     baked::kSkyIrradianceSh[3 * i + 2]);
    e.sun_direction = default_sun_direction();
    e.sun_irradiance = default_sun_irradiance();
    return e;
  }();
  return env;
}

}  // namespace gltf_pbr::preview
