// Structure validation: the passes of validators/structure/, in the reference validator's order.
#include "validators/structure/structure.hpp"

#include <algorithm>
#include <string_view>

#include "validators/structure/structure_internal.hpp"

namespace gltf_pbr {

bool validate_structure(const std::filesystem::path& file, std::span<const std::uint8_t> bytes, const RuleSet& rules,
                        const StructureOptions& options, Report& report) {
  using namespace structure;
  const std::shared_ptr<FileResources> resources =
      options.resources ? options.resources
                        : std::make_shared<FileResources>(file.parent_path(), options.allow_outside_uris);
  Context context(rules, report, options, *resources);
  // The reference picks its reader by file extension; content sniffing covers extension-less input.
  std::string extension = file.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  context.glb = extension == ".glb" || (extension != ".gltf" && bytes.size() >= 4 && bytes[0] == 'g' &&
                                        bytes[1] == 'l' && bytes[2] == 'T' && bytes[3] == 'F');
  report.mime_type = context.glb ? "model/gltf-binary" : "model/gltf+json";

  auto stream_end = [&] {
    for (const auto& [code, offset, args] : context.glb_end_issues) context.issues.at_offset(code, offset, args);
  };
  std::span<const std::uint8_t> json_text = bytes;
  if (context.glb) {
    bool empty_json_ended = false;
    auto json = read_glb(bytes, context, empty_json_ended);
    if (!json) {
      if (empty_json_ended) parse_json({}, context);
      stream_end();
      return context.issues.found_error();
    }
    json_text = *json;
  }
  if (!parse_json(json_text, context)) {
    stream_end();
    return context.issues.found_error();
  }
  if (walk_schema(context)) {
    check_links(context);
    report_unused(context);
    stream_end();
    // A GLB that ends inside a chunk has no trustworthy resources: the reference loads none then
    // (no IO_ERROR, no BUFFER_MISSING_GLB_DATA; checked against the npm validator).
    if (!context.glb_ended_inside_chunk) check_resources(context);
    fill_info(context);
  } else {
    stream_end();
  }
  // The loader of a later step reads the same tree instead of parsing the JSON again.
  if (options.resources)
    options.resources->keep_document({std::move(context.root), std::move(context.json_flaws)}, json_text);
  return context.issues.found_error();
}

}  // namespace gltf_pbr
