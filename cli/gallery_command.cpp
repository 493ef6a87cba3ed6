// `gltf-pbr gallery DIR`: the page comparing every preview under DIR (preview/gallery.hpp), which
// preview and convert --preview also write beside their previews.
#include <cstdio>
#include <string>

#include "cli/commands.hpp"
#include "cli/inputs.hpp"
#include "core/error.hpp"
#include "core/text.hpp"
#include "preview/gallery.hpp"

namespace gltf_pbr::cli {
namespace {

struct GalleryArgs {
  std::string dir;
  bool quiet = false;
};

int run(const GalleryArgs& args) {
  write_gallery_page(args.dir, args.quiet, PageRole::TheResult);
  return kAllDone;
}

constexpr const char* kGalleryHelp =
    R"(Write DIR/index.html: one self-contained page (no server or network; opens from file://) comparing
every preview under DIR (the folders gltf-pbr preview -o and convert --preview write): before and
after with a slider, the difference map with its scale, the figures and each material's outcome,
sortable and filterable, worst first. preview and convert --preview write it themselves; this
rebuilds it, for example once after sharded runs into one folder.
An index.html in DIR that gltf-pbr did not write is never replaced.
Exit codes: 0 written, 2 bad usage, 3 the page cannot be written (or DIR/index.html is not ours).)";

void declare_options(CLI::App& cmd, GalleryArgs& args) {
  cmd.add_option("dir", args.dir, "a folder of previews")->required()->check(CLI::ExistingDirectory);
  cmd.add_flag("-q,--quiet", args.quiet, "print nothing but errors");
}

}  // namespace

void write_gallery_page(const std::filesystem::path& dir, bool quiet, PageRole role) {
  preview::GalleryPage page;
  try {
    page = preview::write_gallery(dir);
  } catch (const OutputError& e) {
    if (role == PageRole::TheResult) throw;
    std::fprintf(stderr, "warning: the gallery page was not written (the previews were): %s\n",
                 printable(e.what()).c_str());
    return;
  }
  if (page.outcome == preview::GalleryOutcome::KeptForeignPage) {
    const std::string why = page.written.string() + " is not a page gltf-pbr wrote, or cannot be read: left as it is";
    if (role == PageRole::TheResult) throw OutputError(why + "; move it away to write the gallery there");
    std::fprintf(stderr, "warning: %s (the previews were written; --no-gallery leaves the page alone)\n",
                 printable(why).c_str());
    return;
  }
  if (quiet) return;
  std::fprintf(stderr, "%s: a page comparing %s%s\n", printable(page.written.string()).c_str(),
               counted(static_cast<std::size_t>(page.entries), "preview").c_str(),
               page.skipped
                   ? (", " + counted(static_cast<std::size_t>(page.skipped), "unreadable report") + " left out").c_str()
                   : "");
}

std::function<int()> add_gallery_command(CLI::App& app) {
  return add_subcommand<GalleryArgs>(app, "gallery", kGalleryHelp, declare_options, run);
}

}  // namespace gltf_pbr::cli
