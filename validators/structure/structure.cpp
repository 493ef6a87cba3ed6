// SCAFFOLD: replaced by the structure validator (issue 4).
#include "validators/structure/structure.hpp"
namespace gltf_pbr {
void validate_structure(const std::filesystem::path&, std::span<const std::uint8_t> bytes, const RuleSet&,
                        const StructureOptions&, Report& report) {
  report.mime_type = bytes.size() >= 4 && bytes[0] == 'g' && bytes[1] == 'l' && bytes[2] == 'T' && bytes[3] == 'F'
                         ? "model/gltf-binary" : "model/gltf+json";
}
}  // namespace gltf_pbr
