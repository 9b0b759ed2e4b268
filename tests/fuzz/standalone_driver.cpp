// main() for fuzz targets built without libFuzzer (GCC builds): runs every file given, and
// every file of every directory given, through LLVMFuzzerTestOneInput once. Files run in
// name order so a failure reproduces. An empty corpus is an error: a replay that tests
// nothing must not pass.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace {

namespace fs = std::filesystem;

bool run_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "%s: cannot open\n", path.c_str());
    return false;
  }
  const std::vector<char> bytes{std::istreambuf_iterator<char>(in), {}};
  std::vector<std::uint8_t> data(bytes.begin(), bytes.end());
  // Own heap copy of exactly the input size, so ASan sees reads one past the end.
  std::fprintf(stderr, "%s (%zu bytes)\n", path.c_str(), data.size());
  LLVMFuzzerTestOneInput(data.data(), data.size());
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<fs::path> files;
  for (int i = 1; i < argc; ++i) {
    const fs::path arg(argv[i]);
    std::error_code ec;
    if (fs::is_directory(arg, ec)) {
      for (const auto& entry : fs::directory_iterator(arg)) {
        if (entry.is_regular_file()) files.push_back(entry.path());
      }
    } else {
      files.push_back(arg);
    }
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) {
    std::fprintf(stderr, "usage: %s CORPUS_DIR|FILE...: no input files found\n", argv[0]);
    return 2;
  }
  std::size_t ran = 0;
  for (const auto& path : files) {
    if (!run_file(path)) return 2;
    ++ran;
  }
  std::fprintf(stderr, "ran %zu inputs\n", ran);
  return 0;
}
