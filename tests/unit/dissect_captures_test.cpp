// Every bundled device map has a capture in captures/ whose golden decode uses it: the
// capture's <name>.args names the model with --device ADDR=MODEL or through a --bus file,
// and <name>.expected.txt or .expected.jsonl exists (tests/golden checks the decode).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "dissect/map_library.hpp"
#include "dissect/map_loader.hpp"

namespace rtu::dissect {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> words_of_first_line(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  std::istringstream ss(line);
  std::vector<std::string> words;
  for (std::string w; ss >> w;) words.push_back(w);
  return words;
}

// Models a capture's golden decode uses, from its .args line.
std::set<std::string> models_of_args(const fs::path& args_file) {
  std::set<std::string> models;
  const auto words = words_of_first_line(args_file);
  for (std::size_t i = 0; i + 1 < words.size(); ++i) {
    if (words[i] == "--device") {
      const auto eq = words[i + 1].find('=');
      if (eq != std::string::npos) models.insert(words[i + 1].substr(eq + 1));
    } else if (words[i] == "--bus") {
      const auto bus = load_bus_file(std::string(RTUSCOPE_SOURCE_DIR) + "/" + words[i + 1]);
      for (const auto& s : bus.slaves) models.insert(s.model);
    }
  }
  return models;
}

TEST(DissectCaptures, EveryBundledMapHasACaptureWithAGoldenDecode) {
  MapLibrary library;
  const auto errors = library.load_dir(RTUSCOPE_SOURCE_DIR "/dissectors");
  ASSERT_TRUE(errors.empty()) << errors.front();
  ASSERT_FALSE(library.maps().empty());

  std::set<std::string> covered;
  const fs::path captures = fs::path(RTUSCOPE_SOURCE_DIR) / "captures";
  for (const auto& entry : fs::directory_iterator(captures)) {
    if (entry.path().extension() != ".args") continue;
    const fs::path stem = entry.path().parent_path() / entry.path().stem();
    const bool golden = fs::exists(stem.string() + ".expected.txt") ||
                        fs::exists(stem.string() + ".expected.jsonl");
    if (!golden) continue;
    for (const auto& m : models_of_args(entry.path())) covered.insert(m);
  }
  for (const auto& map : library.maps()) {
    EXPECT_TRUE(covered.count(map->model) > 0)
        << "dissectors/" << map->model << ".toml has no capture in captures/ with a golden "
        << "decode (a <name>.args naming it with --device ADDR=" << map->model
        << " or a --bus file, and <name>.expected.txt or .expected.jsonl)";
  }
}

}  // namespace
}  // namespace rtu::dissect
