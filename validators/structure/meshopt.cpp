// EXT_meshopt_compression: the reference validator cannot look inside compressed bufferViews, we
// can. Each one whose extension object, layout and source range are valid is decoded with
// core/meshopt (the one decoder core's accessor reader also uses); a failure is
// MESHOPT_DECODE_FAILED (our code, rules/structure.json). The decoded bytes then stand for the
// view (buffer_view_bytes), so accessors over it get the same data checks as plain ones.
#include "validators/structure/images.hpp"

namespace gltf_pbr::structure {

void decode_meshopt_views(Context& context) {
  Document& doc = context.doc;
  std::uint64_t stored = 0, decoded = 0;
  for (const BufferModel& buffer : doc.buffers) stored += buffer.data.size();
  const std::uint64_t budget = meshopt_decode_budget(stored);
  for (std::size_t i = 0; i < doc.buffer_views.size(); ++i) {
    BufferViewModel& view = doc.buffer_views[i];
    if (!view.object || !view.meshopt || view.byte_length <= 0) continue;
    const MeshoptView& m = *view.meshopt;
    if (!meshopt_layout_problem(m, static_cast<std::uint64_t>(view.byte_length),
                                static_cast<std::uint64_t>(view.byte_stride))
             .empty())
      continue;  // MESHOPT_INVALID_LAYOUT, from the link pass
    if (m.buffer < 0 || static_cast<std::size_t>(m.buffer) >= doc.buffers.size()) continue;
    const BufferModel& source = doc.buffers[static_cast<std::size_t>(m.buffer)];
    if (!source.object || !source.data_loaded) continue;
    if (m.byte_offset > source.data.size() || m.byte_length > source.data.size() - m.byte_offset) continue;
    // The decoded size is the parent's byteLength: the layout holds.
    std::string problem = meshopt_budget_problem(decoded, m.count * m.byte_stride, budget);
    if (problem.empty())
      view.decoded = decode_meshopt(
          source.data.subspan(static_cast<std::size_t>(m.byte_offset), static_cast<std::size_t>(m.byte_length)), m,
          problem);
    if (view.decoded)
      decoded += view.decoded->size();
    else
      context.issues.at("MESHOPT_DECODE_FAILED",
                        "/bufferViews/" + std::to_string(i) + "/extensions/EXT_meshopt_compression",
                        {arg_raw(problem)});
  }
}

}  // namespace gltf_pbr::structure
