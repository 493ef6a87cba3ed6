// The gallery page (GitHub issue 15): one self-contained index.html over every preview under a
// folder, to compare a library's conversions asset by asset, worst first.
#pragma once
#include <filesystem>

namespace gltf_pbr::preview {

enum class GalleryOutcome {
  Written,          // root/index.html holds the page
  KeptForeignPage,  // root/index.html is not a page this code wrote: left as it was, nothing written
};

struct GalleryPage {
  GalleryOutcome outcome = GalleryOutcome::Written;
  std::filesystem::path written;  // root/index.html
  int entries = 0;                // previews listed
  int skipped = 0;                // report.json files that could not be read as a preview's
};

// Writes `root`/index.html atomically, listing every preview folder under `root` (root itself
// included): a folder with report.json, before.png, after.png and difference.png as
// write_preview leaves them. Symbolic links are not followed, so nothing outside `root` is
// read. A rerun over the same folder rewrites the page with what the folder holds then; an
// index.html that this code did not write (no generator mark) is never replaced. Each text taken
// from a report is capped at 1,000 bytes (and an ellipsis); an entry lists its 256 worst
// materials, and sorts and filters by the outcomes of all. Throws OutputError when
// the page cannot be written.
GalleryPage write_gallery(const std::filesystem::path& root);

// Whether write_gallery would list the preview in `folder` (itself, not a link to one): its images
// and its report.json, read as the page reads them.
bool lists_a_preview(const std::filesystem::path& folder);

}  // namespace gltf_pbr::preview
