// Enumerations' names as the reports, the options and the Python module spell them: one table per
// enumeration, read both ways, so a name is written in one place.
#pragma once
#include <array>
#include <cstddef>
#include <optional>
#include <string_view>
#include <utility>

namespace gltf_pbr {

template <typename Enum, std::size_t N>
using NameTable = std::array<std::pair<Enum, const char*>, N>;

template <typename Enum, std::size_t N>
constexpr const char* name_of(const NameTable<Enum, N>& table, Enum value) {
  for (const auto& [entry, entry_name] : table)
    if (entry == value) return entry_name;
  return "?";
}

template <typename Enum, std::size_t N>
constexpr std::optional<Enum> from_name(const NameTable<Enum, N>& table, std::string_view name) {
  for (const auto& [value, value_name] : table)
    if (name == value_name) return value;
  return std::nullopt;
}

}  // namespace gltf_pbr
