// Conversion reports: JSON for tools, a short summary for people on stderr.
#pragma once
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "converter/convert.hpp"
#include "core/error.hpp"

namespace gltf_pbr::cli {

struct FileResult {
  std::string input, output;
  std::string status;  // "converted", "copied" (nothing to convert), "failed"
  std::optional<InputError> error;
  std::string failure;  // reason when failed without an InputError
  ConversionReport report;
  double load_ms = 0, save_ms = 0, total_ms = 0;
};

nlohmann::json file_json(const FileResult& result);
nlohmann::json run_json(const std::vector<FileResult>& results, const ConvertOptions& options,
                        const std::string& solver_name);
std::string file_summary(const FileResult& result, bool verbose);

}  // namespace gltf_pbr::cli
