// The split-sum terms of image-based lighting (Karis 2013, "Real Shading in Unreal Engine 4",
// section "Image Based Lighting"): under a radiance that is constant over the specular lobe, a
// GGX surface reflects F0 * A + B of it, with (A, B) depending on N.V and roughness only. The
// preview lights with them; the solver's appearance error model (converter/solver.hpp) weighs
// both materials' lobes by them.
#pragma once
#include <cstdint>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace gltf_pbr {

// Split-sum scale and bias (A, B): the specular reflectance is F0 * A + B (Karis 2013, eq. 8),
// for GGX with height-correlated Smith visibility (core/brdf.hpp). dfg_lookup interpolates a
// 64 x 64 table baked at build time (core/dfg_table.cpp); integrate_dfg is the Monte Carlo
// reference, and dfg_table_cell the value baked at a cell. Rows are roughness; columns are
// spaced in sqrt(N.V), where the table changes fastest at grazing angles.
inline constexpr int kDfgTableSize = 64;
glm::vec2 dfg_lookup(float n_dot_v, float roughness);
namespace baked {
// The table dfg_lookup reads: (A, B) by cell, row-major by roughness (generated dfg_table_data.cpp).
extern const float kDfgTable[kDfgTableSize * kDfgTableSize * 2];
}  // namespace baked
glm::vec2 integrate_dfg(float n_dot_v, float roughness, int samples);
glm::vec2 dfg_table_cell(int row, int column);

// Low-discrepancy point i of n (Hammersley set with the radical inverse in base 2).
glm::vec2 hammersley(std::uint32_t i, std::uint32_t n);

// GGX half vector around +Z for a uniform point (Walter et al. 2007, eqs. 35-36; Karis 2013).
glm::vec3 importance_sample_ggx(glm::vec2 xi, float alpha);

}  // namespace gltf_pbr
