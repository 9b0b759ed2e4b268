#pragma once
// Helpers for reader tests: real files in a fresh temporary folder, and a way to see whether
// code allocates (through the sanitizer's allocator hooks when built with ASan).
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
// From the sanitizer runtime's public interface (sanitizer/allocator_interface.h, which GCC
// does not install).
extern "C" int __sanitizer_install_malloc_and_free_hooks(void (*malloc_hook)(const volatile void*,
                                                                             std::size_t),
                                                         void (*free_hook)(const volatile void*));
#endif

#include "capture/chunk_source.hpp"
#include "capture/chunk_view.hpp"

namespace rtu::testing {

// A folder under the system temp dir, removed with its files when the test ends.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string leaf = "rtuscope-";
    if (info != nullptr) leaf += std::string(info->test_suite_name()) + "-" + info->name() + "-";
    path_ = std::filesystem::temp_directory_path() / (leaf + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  // Writes `content` byte for byte to a file `name` in the folder; returns its path.
  [[nodiscard]] std::string write(const std::string& name, std::string_view content) const {
    const auto file = path_ / name;
    std::ofstream out(file, std::ios::binary);
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    EXPECT_TRUE(out.good()) << file;
    return file.string();
  }
  [[nodiscard]] const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// One chunk copied out of a source (the source's spans die at its next call).
struct CopiedChunk {
  Nanos t_end = 0;
  Nanos t_first_start = kUnknownTime;
  std::vector<std::uint8_t> bytes;
  std::vector<std::uint8_t> errors;
  std::uint64_t origin = 0;
  bool time_clamped = false;
};

inline std::vector<CopiedChunk> read_all(CaptureReader& reader) {
  std::vector<CopiedChunk> out;
  ChunkView source(reader);
  Chunk chunk;
  while (source.next(chunk)) {
    out.push_back({chunk.t_end, chunk.t_first_start,
                   std::vector<std::uint8_t>(chunk.bytes.begin(), chunk.bytes.end()),
                   std::vector<std::uint8_t>(chunk.errors.begin(), chunk.errors.end()),
                   chunk.origin, chunk.time_clamped});
  }
  return out;
}

// Counts heap allocations made between start() and count(). Only an ASan build can see them
// (through __sanitizer_install_malloc_and_free_hooks); elsewhere available() is false.
class AllocationCounter {
 public:
  static bool available() {
#if defined(__SANITIZE_ADDRESS__)
    return true;
#else
    return false;
#endif
  }
  void start() {
#if defined(__SANITIZE_ADDRESS__)
    static const bool installed = [] {
      __sanitizer_install_malloc_and_free_hooks(&on_malloc, &on_free);
      return true;
    }();
    (void)installed;
#endif
    allocations().store(0);
    counting().store(true);
  }
  std::uint64_t count() {
    counting().store(false);
    return allocations().load();
  }

 private:
  static std::atomic<std::uint64_t>& allocations() {
    static std::atomic<std::uint64_t> n{0};
    return n;
  }
  static std::atomic<bool>& counting() {
    static std::atomic<bool> on{false};
    return on;
  }
  static void on_malloc(const volatile void* /*ptr*/, std::size_t /*size*/) {
    if (counting().load()) allocations().fetch_add(1);
  }
  static void on_free(const volatile void* /*ptr*/) {}
};

// The bundled text and CSV captures (captures/*.hex, *.csv, not the expected outputs), sorted.
inline std::vector<std::string> bundled_text_captures() {
  std::vector<std::string> paths;
  for (const auto& entry : std::filesystem::directory_iterator(RTUSCOPE_SOURCE_DIR "/captures")) {
    const auto ext = entry.path().extension();
    const auto name = entry.path().filename().string();
    if ((ext != ".hex" && ext != ".csv") || name.find(".expected.") != std::string::npos) continue;
    paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

}  // namespace rtu::testing
