// The gallery page (see gallery.hpp).
#include "preview/gallery.hpp"

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "core/files.hpp"
#include "core/text.hpp"

namespace gltf_pbr {
// preview/gallery.html, embedded by the build (cmake/embed.cmake).
const std::vector<std::pair<std::string, std::string>>& embedded_gallery_files();
}  // namespace gltf_pbr

namespace gltf_pbr::preview {
namespace {

namespace fs = std::filesystem;

// A preview's report.json is a few KiB; a larger one is not ours and is not read into memory.
constexpr std::uintmax_t kLargestReport = 4u << 20;
constexpr const char* kImages[] = {"before.png", "after.png", "difference.png"};
// What the page shows of one report at most: a few long names cannot make it megabytes.
constexpr std::size_t kLongestText = 1000;
constexpr std::size_t kMostMaterials = 256;
constexpr std::size_t kMostIssues = 100;  // of each side's material issues
// The line gallery.html carries, by which a rerun knows index.html as a page it wrote itself; pages
// written before the mark existed open with the comment after it.
constexpr std::string_view kGeneratorMark = R"(<meta name="generator" content="gltf-pbr gallery">)";
constexpr std::string_view kEarlierPageMark = "<!-- The gallery page of gltf-pbr's previews";
constexpr std::size_t kMarkSearched = 4096;  // bytes of an existing index.html looked at for it

// At most kLongestText bytes, cut at a UTF-8 character's start, with an ellipsis when cut.
std::string capped(std::string text) {
  if (text.size() <= kLongestText) return text;
  std::size_t end = kLongestText;
  while (end > 0 && (static_cast<unsigned char>(text[end]) & 0xC0) == 0x80) --end;
  text.resize(end);
  return text + "\u2026";
}

// The outcomes the page knows, worst first: left legacy, needed the specular extension, metalness.
constexpr std::string_view kOutcomesWorstFirst[] = {"legacy", "specular", "metalness"};

// An outcome's place in kOutcomesWorstFirst; one the page does not know comes after them all.
std::size_t outcome_rank(std::string_view outcome) {
  return static_cast<std::size_t>(std::find(std::begin(kOutcomesWorstFirst), std::end(kOutcomesWorstFirst), outcome) -
                                  std::begin(kOutcomesWorstFirst));
}

// A report's outcome as the page shows it: anything it does not know is "unknown".
std::string outcome_of(const std::string& outcome) {
  return outcome_rank(outcome) < std::size(kOutcomesWorstFirst) ? outcome : "unknown";
}

nlohmann::json number_at(const nlohmann::json& report, const char* pointer) {
  const nlohmann::json::json_pointer at(pointer);
  return report.contains(at) && report[at].is_number() ? report[at] : nlohmann::json(nullptr);
}

// Read by type, never by conversion: a report.json of the wrong shape gives the fallback, not a throw.
std::string string_at(const nlohmann::json& report, const char* key, const char* fallback = "") {
  return report.contains(key) && report[key].is_string() ? report[key].get<std::string>() : std::string(fallback);
}

// One material of the report's conversion block, in the page's terms.
nlohmann::json material_of(const nlohmann::json& m) {
  return {{"index", number_at(m, "/index")},
          {"name", capped(string_at(m, "name"))},
          {"outcome", outcome_of(string_at(m, "outcome", "legacy"))},
          {"diffuseP95", number_at(m, "/texel_delta_e_2000_a/diffuse_p95")},
          {"f0P95", number_at(m, "/texel_delta_e_2000_a/f0_p95")},
          {"appearanceP95", number_at(m, "/texel_delta_e_2000_a/appearance_p95")},
          {"timeMs", number_at(m, "/time_ms")},
          {"note", capped(string_at(m, "note"))}};
}

// The material rules' issues on the input and the output (preview --lint, convert --preview-lint),
// the first kMostIssues of each side with the count of all; null when the run did not check them.
nlohmann::json issues_of(const nlohmann::json& report) {
  if (!report.contains("material_issues") || !report["material_issues"].is_object()) return nullptr;
  const nlohmann::json& checked = report["material_issues"];
  nlohmann::json out{{"profile", capped(string_at(checked, "profile"))}};
  for (const char* side : {"before", "after"}) {
    nlohmann::json listed = nlohmann::json::array();
    std::uint64_t total = 0;
    if (checked.contains(side) && checked[side].is_array())
      for (const nlohmann::json& issue : checked[side]) {
        if (!issue.is_object()) continue;
        const std::uint64_t count =
            issue.contains("count") && issue["count"].is_number_unsigned() ? issue["count"].get<std::uint64_t>() : 1;
        total += count;
        if (listed.size() < kMostIssues)
          listed.push_back({{"code", capped(string_at(issue, "code"))},
                            {"severity", capped(string_at(issue, "severity"))},
                            {"pointer", capped(string_at(issue, "pointer"))},
                            {"message", capped(string_at(issue, "message"))},
                            {"count", count}});
      }
    out[side] = std::move(listed);
    out[std::string(side) + "Count"] = total;
  }
  return out;
}

// A regular file itself, not a link to one: nothing outside the root is read or shown.
bool is_plain_file(const fs::path& file) {
  std::error_code ec;
  return fs::is_regular_file(fs::symlink_status(file, ec));
}

// The report.json in `folder` when it is a preview's: a plain file of at most kLargestReport bytes
// holding an object with a difference block, as write_preview leaves it; else null.
nlohmann::json preview_report(const fs::path& folder) {
  std::error_code ec;
  const fs::path file = folder / "report.json";
  if (!is_plain_file(file) || fs::file_size(file, ec) > kLargestReport || ec) return nullptr;
  const std::optional<Bytes> bytes = read_file(file);
  if (!bytes) return nullptr;
  nlohmann::json report = nlohmann::json::parse(bytes->begin(), bytes->end(), nullptr, false);
  return report.is_object() && report.contains("difference") ? report : nullptr;
}

// The page's entry for the preview in `folder` (`path` relative to the root), or null when its
// report is not a preview's.
nlohmann::json entry_of(const fs::path& folder, const std::string& path) {
  const nlohmann::json report = preview_report(folder);
  if (report.is_null()) return nullptr;
  const std::string input = string_at(report, "input");
  std::vector<nlohmann::json> all;
  const nlohmann::json::json_pointer listed("/conversion/materials");
  if (report.contains(listed) && report[listed].is_array())
    for (const nlohmann::json& m : report[listed])
      if (m.is_object()) all.push_back(material_of(m));
  // The page sorts and filters by every material's outcome, and lists the worst kMostMaterials:
  // the worst outcome first, then the largest ΔE2000 p95, then the report's order.
  std::set<std::string> outcomes;
  for (const nlohmann::json& m : all) outcomes.insert(m["outcome"].get<std::string>());
  const auto rank = [](const nlohmann::json& m) { return outcome_rank(m["outcome"].get_ref<const std::string&>()); };
  const auto worst_p95 = [](const nlohmann::json& m) {
    double worst = -1;
    for (const char* key : {"diffuseP95", "f0P95", "appearanceP95"})
      if (m[key].is_number()) worst = std::max(worst, m[key].get<double>());
    return worst;
  };
  const std::size_t left_out = all.size() > kMostMaterials ? all.size() - kMostMaterials : 0;
  if (left_out) {
    std::stable_sort(all.begin(), all.end(), [&](const nlohmann::json& a, const nlohmann::json& b) {
      return rank(a) != rank(b) ? rank(a) < rank(b) : worst_p95(a) > worst_p95(b);
    });
    all.resize(kMostMaterials);
  }
  nlohmann::json materials(std::move(all));
  return {{"path", capped(path)},
          {"href", url_path(path)},
          {"name", capped(input.empty() ? path : fs::path(input).filename().string())},
          {"input", capped(input)},
          {"width", number_at(report, "/width")},
          {"height", number_at(report, "/height")},
          {"flip", number_at(report, "/difference/flip/mean")},
          {"deltaE", number_at(report, "/difference/delta_e_2000/mean")},
          {"p95", number_at(report, "/difference/delta_e_2000/p95")},
          {"rmsDb", number_at(report, "/difference/rms_db")},
          {"materials", std::move(materials)},
          {"materialsLeftOut", left_out},
          {"outcomes", outcomes},
          {"issues", issues_of(report)}};
}

bool holds_a_preview(const fs::path& folder) {
  return std::all_of(std::begin(kImages), std::end(kImages),
                     [&](const char* image) { return is_plain_file(folder / image); });
}

// Whether `file` is absent or a page this code wrote (a plain file carrying the generator mark
// near its start): anything else at root/index.html, or a file that cannot be read to tell, is
// someone's own page and never overwritten.
bool is_ours_or_absent(const fs::path& file) {
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(file, ec);
  if (status.type() == fs::file_type::not_found) return true;
  if (!fs::is_regular_file(status)) return false;
  std::ifstream in(file, std::ios::binary);
  std::string head(kMarkSearched, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head.find(kGeneratorMark) != std::string::npos || head.find(kEarlierPageMark) != std::string::npos;
}

// JSON inside <script>: "</script>" or "<!--" in a name must not end or change the element. The
// three characters only occur inside strings, where their \u escapes mean the same to JSON.parse.
std::string script_safe(const std::string& json) {
  std::string out;
  out.reserve(json.size());
  for (const char c : json) {
    if (c == '<')
      out += "\\u003c";
    else if (c == '>')
      out += "\\u003e";
    else if (c == '&')
      out += "\\u0026";
    else
      out += c;
  }
  return out;
}

}  // namespace

bool lists_a_preview(const fs::path& folder) {
  std::error_code ec;
  return fs::is_directory(fs::symlink_status(folder, ec)) && holds_a_preview(folder) &&
         !preview_report(folder).is_null();
}

GalleryPage write_gallery(const fs::path& root) {
  GalleryPage page;
  std::vector<std::pair<std::string, fs::path>> folders;  // (path relative to root, folder)
  std::error_code ec;
  if (holds_a_preview(root)) folders.emplace_back("", root);
  for (fs::recursive_directory_iterator it(root, fs::directory_options::skip_permission_denied, ec), end;
       !ec && it != end; it.increment(ec)) {
    std::error_code entry_error;  // a dangling link or a loop skips its entry, not the rest of the walk
    if (!fs::is_directory(it->symlink_status(entry_error))) continue;
    if (holds_a_preview(it->path()))
      folders.emplace_back(it->path().lexically_relative(root).generic_string(), it->path());
  }
  std::sort(folders.begin(), folders.end());
  nlohmann::json entries = nlohmann::json::array();
  for (const auto& [path, folder] : folders) {
    nlohmann::json entry = entry_of(folder, path);
    if (entry.is_null()) {
      ++page.skipped;
      continue;
    }
    entries.push_back(std::move(entry));
  }
  page.entries = static_cast<int>(entries.size());
  page.written = root / "index.html";
  if (!is_ours_or_absent(page.written)) {
    page.outcome = GalleryOutcome::KeptForeignPage;
    return page;
  }
  std::string html = embedded_gallery_files().at(0).second;
  const std::string slot = "/*ENTRIES*/";
  html.replace(html.find(slot), slot.size(),
               script_safe(entries.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace)));
  AtomicWriteSet files;
  files.stage(page.written, std::span(reinterpret_cast<const std::uint8_t*>(html.data()), html.size()));
  files.commit();
  page.outcome = GalleryOutcome::Written;
  return page;
}

}  // namespace gltf_pbr::preview
