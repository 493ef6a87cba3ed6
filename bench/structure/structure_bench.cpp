// structure_bench FILE... [--list LIST] [--runs N] [--json]: the median wall time of validate_structure on each
// file (read once, validated N times), with the issue count, to compare against the npm
// gltf-validator (bench/validate.sh times the whole CLI against it). --json prints each report.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "validators/structure/structure.hpp"

int main(int argc, char** argv) {
  int runs = 5;
  bool json = false;
  std::vector<std::string> files;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--json") == 0)
      json = true;
    else if (std::strcmp(argv[i], "--list") == 0 && i + 1 < argc) {
      std::ifstream list(argv[++i]);
      for (std::string line; std::getline(list, line);)
        if (!line.empty()) files.push_back(line);
    } else if (std::strcmp(argv[i], "--runs") == 0 && i + 1 < argc)
      runs = std::max(1, std::atoi(argv[++i]));
    else
      files.push_back(argv[i]);
  }
  for (const std::string& file : files) {
    std::ifstream stream(file, std::ios::binary);
    const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(stream), std::istreambuf_iterator<char>()};
    std::vector<double> seconds;
    std::size_t issues = 0;
    for (int run = 0; run < runs; ++run) {
      gltf_pbr::Report report;
      const auto start = std::chrono::steady_clock::now();
      gltf_pbr::validate_structure(file, bytes, gltf_pbr::builtin_rules(), gltf_pbr::StructureOptions{}, report);
      seconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      issues = report.messages.size();
      if (json && run == 0) {
        report.uri = file;
        std::printf(
            "%s\n",
            gltf_pbr::report_to_json(report).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace).c_str());
      }
    }
    std::sort(seconds.begin(), seconds.end());
    std::printf("%s\t%.1f MB\t%.4f s (median of %d)\t%zu issues\n", file.c_str(), bytes.size() / 1e6,
                seconds[seconds.size() / 2], runs, issues);
  }
  return 0;
}
