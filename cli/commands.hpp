// The gltf-pbr subcommands. Exit codes (gltfpack style, one per failure class):
#pragma once
#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <memory>

namespace gltf_pbr::cli {

// 3: the inputs were processed but a requested output (a report, stdout) could not be written.
enum ExitCode { kAllDone = 0, kSomeFilesFailed = 1, kBadUsage = 2, kCannotWrite = 3 };

// What an InputError escaping a command's body means. For convert and validate, whose files fail one
// by one inside the body, it is a config or option file: bad usage (2). For compare and preview it is
// the input the command works on: that input failed (1).
enum class InputErrors { AreBadUsage, FailTheInput };

// Runs a subcommand's body and turns what escapes it into one message and the exit code of its
// class: a usage or config error 2, an output that cannot be written 3, anything else 1.
int run_command(const char* name, const std::function<int()>& body,
                InputErrors input_errors = InputErrors::AreBadUsage);

// Registers subcommand `name`: `declare` adds its options, bound to one Args that outlives parsing.
// The runner it returns (main calls it after parsing) runs `run` through run_command, or returns -1
// when another subcommand was given.
template <typename Args>
std::function<int()> add_subcommand(CLI::App& app, const char* name, const char* help,
                                    void (*declare)(CLI::App&, Args&), int (*run)(const Args&),
                                    InputErrors input_errors = InputErrors::AreBadUsage) {
  auto args = std::make_shared<Args>();
  CLI::App* command = app.add_subcommand(name, help);
  declare(*command, *args);
  return [=] {
    return command->parsed() ? run_command(
                                   name, [&] { return run(*args); }, input_errors)
                             : -1;
  };
}

// Writes text to stdout; throws OutputError with the errno text when it cannot (a full disk,
// a closed pipe), so a lost report is an error and not a silent exit 0.
void write_stdout(const std::string& text);

// Writes text to `path` atomically (a temporary file, then a rename); OutputError when it cannot.
void write_atomically(const std::filesystem::path& path, const std::string& text);

// A command's -o: the file when given, else stdout.
void write_output(const std::filesystem::path& path_or_empty, const std::string& text);

// A JSON document as the text every command writes: indented, and a file name that is not UTF-8
// (Latin-1 names exist) written with U+FFFD instead of ending the run with a type_error.
template <typename Json>
std::string json_text(const Json& document) {
  return document.dump(2, ' ', false, Json::error_handler_t::replace) + "\n";
}

// Writes DIR/index.html, the page comparing every preview under DIR (preview/gallery.hpp), and
// says so on stderr unless quiet. For preview and convert --preview the page is a by-product: a
// page that cannot be written, or an index.html gltf-pbr did not write (left as it is), is a
// warning and their exit code stands. For gallery the page is the result: either throws
// OutputError (exit code 3).
enum class PageRole { BesidePreviews, TheResult };
void write_gallery_page(const std::filesystem::path& dir, bool quiet, PageRole role = PageRole::BesidePreviews);

// Each registers a subcommand; the returned callback runs it after parsing, or returns -1 when
// another subcommand was given.
std::function<int()> add_convert_command(CLI::App& app);
std::function<int()> add_compare_command(CLI::App& app);
std::function<int()> add_validate_command(CLI::App& app);
std::function<int()> add_preview_command(CLI::App& app);
std::function<int()> add_merge_command(CLI::App& app);
std::function<int()> add_gallery_command(CLI::App& app);

}  // namespace gltf_pbr::cli
