#include "cli/inputs.hpp"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>

#include "cli/commands.hpp"
#include "core/asset.hpp"
#include "core/error.hpp"
#include "core/files.hpp"
#include "core/image.hpp"
#include "core/text.hpp"

namespace gltf_pbr::cli {
namespace fs = std::filesystem;

bool is_gltf_file(const fs::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".gltf" || ext == ".glb";
}

namespace {
// The path with symlinks resolved where it exists; its lexical absolute form where it cannot be
// resolved (a folder we may not enter), never the empty path that would contain everything.
fs::path resolved(const fs::path& path) {
  std::error_code ec;
  fs::path canonical = fs::weakly_canonical(path, ec);
  if (ec || canonical.empty()) canonical = fs::absolute(path, ec).lexically_normal();
  return canonical;
}

// The path as named in its folder: the folder resolved, the file's own name kept (a link stays
// itself, not the file it leads to).
fs::path named_in_resolved_folder(const fs::path& path) {
  return resolved(path.parent_path().empty() ? fs::path(".") : path.parent_path()) / path.filename();
}

bool is_under(const fs::path& path, const fs::path& folder) {
  const fs::path file = resolved(path), root = resolved(folder);
  const auto [root_end, ignored] = std::mismatch(root.begin(), root.end(), file.begin(), file.end());
  return root_end == root.end();
}

// The folder a folder input keeps under -o: "lib" keeps "lib"; "lib/", "." and ".." put their
// files straight into the output folder (".." must not lead out of it).
fs::path folder_name(const fs::path& input) {
  const fs::path name = input.filename();
  return name == "." || name == ".." ? fs::path() : name;
}
}  // namespace

FoundInputs find_gltf_files(const GivenInputs& inputs, const fs::path& output_folder) {
  FoundInputs found_inputs;
  std::vector<InputFile>& files = found_inputs.files;
  const std::size_t named_count = inputs.named.size();
  for (std::size_t i = 0; i < named_count + inputs.listed.size(); ++i) {
    const bool listed = i >= named_count;
    const fs::path input = listed ? inputs.listed[i - named_count] : inputs.named[i];
    std::error_code ec;
    if (fs::is_directory(input, ec)) {
      // Earlier outputs are not inputs: what lies under the output folder. A folder that is itself
      // inside the output folder (convert lib -o lib) skips only where its own outputs go
      // (-o/<name>); when even that holds the folder (convert lib/ -o lib), outputs land among the
      // inputs, there is nothing to tell apart, and save_asset refuses to overwrite an input.
      const fs::path name = folder_name(input);
      fs::path outputs = output_folder;
      if (!outputs.empty() && is_under(input, outputs)) outputs = output_folder / name;
      if (!outputs.empty() && is_under(input, outputs)) outputs.clear();
      std::vector<fs::path> found;
      for (const auto& entry : fs::recursive_directory_iterator(input, ec)) {
        if (!entry.is_regular_file() || !is_gltf_file(entry.path())) continue;
        if (!outputs.empty() && is_under(entry.path(), outputs)) {
          ++found_inputs.skipped_under_output;
          continue;
        }
        found.push_back(entry.path());
      }
      std::sort(found.begin(), found.end());
      for (const auto& file : found) {
        const fs::path inside = file.lexically_relative(input);
        files.push_back({file, name / inside, inside});
      }
    } else if (listed && fs::exists(input, ec) && !fs::is_regular_file(input, ec)) {
      throw CLI::ValidationError("--inputs-from", input.string() + ": not a file or a folder");
    } else if (listed && !output_folder.empty() && is_under(input, output_folder)) {
      ++found_inputs.skipped_under_output;  // an earlier output, listed as a changed file
    } else if (listed) {
      const fs::path as_listed = input.lexically_normal();
      const bool stays_below = as_listed.is_relative() && !as_listed.empty() && *as_listed.begin() != "..";
      const fs::path relative = stays_below ? as_listed : input.filename();
      files.push_back({input, relative, relative});
    } else if (fs::is_regular_file(input, ec)) {
      files.push_back({input, input.filename(), input.filename()});
    } else {
      throw CLI::ValidationError("input", input.string() + ": no such file or directory");
    }
  }
  // A file named twice (listed twice, or given beside a folder that holds it) is one input, where
  // it was first found. Compared by its folder resolved and its own name, so a link to a file
  // beside it stays an input of its own.
  std::set<fs::path> seen;
  std::erase_if(files, [&](const InputFile& file) { return !seen.insert(named_in_resolved_folder(file.file)).second; });
  if (files.empty())
    throw CLI::ValidationError("input", found_inputs.skipped_under_output
                                            ? "no .gltf or .glb files found outside the output folder"
                                            : "no .gltf or .glb files found");
  return found_inputs;
}

std::string counted(std::size_t count, const std::string& noun) {
  return std::to_string(count) + " " + noun + (count == 1 ? "" : "s");
}

void add_image_limit_option(CLI::App& command) {
  command
      .add_option_function<std::uint64_t>(
          "--max-image-pixels", [](std::uint64_t pixels) { set_max_image_pixels(pixels); },
          "refuse images whose header claims more pixels than this, before decoding (default 16384x16384)")
      ->check(CLI::Range(std::uint64_t{1}, std::uint64_t{1} << 40));
}

void add_conversion_options(CLI::App& command, ConversionArgs& args) {
  command
      .add_option(
          "--target", args.target,
          "metalness: core glTF only; specular: add KHR_materials_specular + KHR_materials_ior to the materials "
          "whose metalness fit misses by more than the specular tolerance (convert: --specular-tolerance)")
      ->check(CLI::IsMember({"metalness", "specular"}))
      ->capture_default_str();
  command
      .add_option("--solver", args.solver,
                  "fast | balanced | exact: metalness search effort (error against run time); reference: the archived "
                  "extension's brightness formula, for comparison")
      ->check(CLI::IsMember({"fast", "balanced", "exact", "reference"}))
      ->capture_default_str();
  command
      .add_option("--error-model", args.error_model,
                  "normal-incidence: match diffuse weight and F0 at normal incidence; appearance: match the look "
                  "over view angles as well, with the normal-incidence metalness (closer on rounded shapes; on flat "
                  "glossy ones closer or farther by the lighting: see README)")
      ->check(CLI::IsMember({"appearance", "normal-incidence"}))
      ->capture_default_str();
  command
      .add_option("--metalness-tolerance", args.metalness_tolerance,
                  "ΔE2000 a material's error (the error model's figure) may rise by where its metalness map is "
                  "written with fewer distinct values: the fewest of 2 to 16 levels that stay within it "
                  "(smaller files; convert's report gives metalnessLevels); 0 writes every value the solve gave")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
}

void add_batch_options(CLI::App& command, const std::string& verb, unsigned& jobs, bool& allow_outside) {
  command
      .add_option("-j,--jobs", jobs,
                  "files " + verb +
                      " at once, at most one per core: files and the work inside them share one pool of threads "
                      "(default: all cores)")
      ->check(CLI::Range(1u, 4096u));
  add_image_limit_option(command);
  command.add_flag("--allow-outside-uris", allow_outside, "read buffer/image URIs outside the asset's folder");
}

int run_command(const char* name, const std::function<int()>& body, InputErrors input_errors) {
  auto say = [name](const std::exception& e) {
    std::fprintf(stderr, "gltf-pbr %s: %s\n", name, printable(e.what()).c_str());
  };
  try {
    return body();
  } catch (const CLI::ValidationError& e) {
    say(e);
    return kBadUsage;
  } catch (const InputError& e) {  // a config file, an input named on the command line, or the input worked on
    say(e);
    return input_errors == InputErrors::AreBadUsage ? kBadUsage : kSomeFilesFailed;
  } catch (const OutputError& e) {  // a report or stdout that cannot be written, with its reason
    say(e);
    return kCannotWrite;
  } catch (const std::exception& e) {  // the inputs' folders cannot be walked, and the like
    say(e);
    return kSomeFilesFailed;
  }
}

void write_stdout(const std::string& text) {
  if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size() || std::fflush(stdout) != 0)
    throw OutputError(std::string("cannot write to standard output: ") + std::strerror(errno));
}

void write_atomically(const fs::path& path, const std::string& text) {
  AtomicWriteSet files;
  files.stage(path, std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
  files.commit();
}

void write_output(const fs::path& path_or_empty, const std::string& text) {
  if (path_or_empty.empty())
    write_stdout(text);
  else
    write_atomically(path_or_empty, text);
}

void refuse_shared_outputs(const std::vector<InputFile>& files, const std::vector<fs::path>& outputs,
                           const std::string& remedy) {
  std::map<fs::path, std::size_t> first_input;
  for (std::size_t i = 0; i < files.size(); ++i) {
    const auto [it, fresh] = first_input.emplace(resolved(outputs[i]), i);
    if (!fresh)
      throw CLI::ValidationError("input", files[it->second].file.string() + " and " + files[i].file.string() +
                                              " would both be written to " + outputs[i].string() + "; " + remedy);
  }
}

void refuse_writing_over_inputs(const std::vector<InputFile>& files, std::span<const PlannedOutput> outputs,
                                const RunReads& reads) {
  // Only a file that is there can be one the run reads (a folder of named outputs: only one that
  // is there): a fresh run checks nothing further.
  std::multimap<fs::path, const PlannedOutput*> existing;  // by resolved path
  for (const PlannedOutput& output : outputs) {
    std::error_code ec;
    if (!output.path.empty() && fs::exists(output.path, ec)) existing.emplace(resolved(output.path), &output);
    // Found now, not after the run's work: a file output where a folder or a symbolic link stands
    // is not written (AtomicWriteSet: a link is neither renamed over nor written through).
    if (output.path.empty() || output.names || own_descriptor(output.path)) continue;
    if (fs::is_directory(output.path, ec))
      throw CLI::ValidationError(output.option,
                                 "refusing to write " + printable(output.path.string()) + ": it is a folder");
    if (fs::is_symlink(fs::symlink_status(output.path, ec)) &&
        (fs::is_regular_file(output.path, ec) || !fs::exists(output.path, ec)))
      throw CLI::ValidationError(output.option,
                                 "refusing to write " + printable(output.path.string()) +
                                     ": it is a symbolic link; name the file itself, or remove the link");
  }
  if (existing.empty()) return;
  // Files with another name: a file with one link is the file the run reads only under the same
  // resolved path, which `existing` already compares.
  std::vector<const PlannedOutput*> linked_outputs;
  for (const auto& [path, output] : existing) {
    std::error_code ec;
    if (!output->names && fs::is_regular_file(output->path, ec) && fs::hard_link_count(output->path, ec) > 1)
      linked_outputs.push_back(output);
  }
  // `what` says how the run reads the file: "an input", "named by <input>", "the input list".
  const auto refuse_if_written = [&](const fs::path& read, const std::string& what) {
    const fs::path file = resolved(read);
    const auto refuse = [&](const PlannedOutput& output, const fs::path& path) {
      throw CLI::ValidationError(output.option, "refusing to write " + printable(path.string()) +
                                                    ": the run reads it (" + what + "); write it elsewhere");
    };
    for (auto [it, end] = existing.equal_range(file); it != end; ++it)
      if (!it->second->names) refuse(*it->second, it->second->path);
    // The same file under another name (a hard link): refused like the same path, though only an
    // output written in place (--results, appended to) would harm it; the others are renamed over
    // the link. Only outputs with more than one link can be one (linked_outputs).
    for (const PlannedOutput* output : linked_outputs) {
      std::error_code ec;
      if (fs::equivalent(read, output->path, ec)) refuse(*output, output->path);
    }
    // A folder of named outputs: the name the run reads, and the file it leads to (a symbolic link
    // in the folder is refused when written, but its target's name may be one too).
    const fs::path as_named = named_in_resolved_folder(read);
    for (const fs::path& named : {as_named, file})
      for (auto [it, end] = existing.equal_range(named.parent_path()); it != end; ++it)
        if (it->second->names && it->second->names(named.filename().string()))
          refuse(*it->second, it->second->path / named.filename());
  };
  // Paths compare element by element, so the outputs inside a folder follow it in the map.
  const auto holds_an_output = [&](const fs::path& folder) {
    const fs::path root = resolved(folder);
    const auto first = existing.lower_bound(root);
    return first != existing.end() &&
           std::mismatch(root.begin(), root.end(), first->first.begin(), first->first.end()).first == root.end();
  };
  for (const auto& [list, what] :
       {std::pair{reads.inputs_from, "the --inputs-from list"}, std::pair{reads.config, "the --config file"}})
    if (!list.empty() && list != "-") refuse_if_written(list, what);
  // An output file with another name (a hard link) may be any file the inputs name, wherever it is.
  for (const InputFile& input : files) {
    refuse_if_written(input.file, "an input");
    const fs::path folder = input.file.parent_path().empty() ? fs::path(".") : input.file.parent_path();
    if (!reads.allow_outside_uris && linked_outputs.empty() && !holds_an_output(folder)) continue;
    // Mapped, not read: a GLB's binary chunk is never touched for its JSON's URIs.
    const std::optional<MappedFile> mapped = MappedFile::open(input.file, MappedFile::ReadAhead::OnTouch);
    if (!mapped) continue;  // the run reports the unreadable input itself
    for (const std::string& uri : external_uris(mapped->bytes()).value_or(std::vector<std::string>{})) {
      const ResolvedUri named = resolve_uri(folder, uri, reads.allow_outside_uris);
      if (named.status == UriStatus::Readable)
        refuse_if_written(named.path, "named by " + printable(input.file.string()));
    }
  }
}

Progress::Progress(std::size_t total, std::string verb)
    : total_(total), on_terminal_(::isatty(STDERR_FILENO) && total > 1), verb_(std::move(verb)) {
  const std::lock_guard lock(mutex_);
  show_count();
}

Progress::~Progress() {
  if (on_terminal_) std::fprintf(stderr, "\r\033[K");
}

void Progress::show_count() {
  if (on_terminal_ && count_ < total_) std::fprintf(stderr, "[%zu/%zu] %s...", count_, total_, verb_.c_str());
  std::fflush(stderr);
}

void Progress::done(const std::string& line) {
  const std::lock_guard lock(mutex_);
  ++count_;
  if (on_terminal_) std::fprintf(stderr, "\r\033[K");
  std::fputs(line.c_str(), stderr);
  show_count();
}

}  // namespace gltf_pbr::cli
