#include "dissect/map_library.hpp"

#include <algorithm>
#include <filesystem>
#include <system_error>

#include "dissect/map_loader.hpp"

namespace rtu::dissect {

namespace fs = std::filesystem;

std::vector<std::string> MapLibrary::load_dir(const std::string& dir) {
  std::vector<std::string> errors;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    errors.push_back(dir + ": not a folder of device maps");
    return errors;
  }
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (entry.is_regular_file() && entry.path().extension() == ".toml") {
      files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  for (const auto& file : files) {
    auto result = load_map_file(file.string());
    if (result.ok()) {
      add(std::move(result.map));
    } else {
      errors.insert(errors.end(), result.errors.begin(), result.errors.end());
    }
  }
  return errors;
}

void MapLibrary::add(DeviceMap map) {
  for (auto& existing : maps_) {
    if (existing->model == map.model) {
      *existing = std::move(map);
      return;
    }
  }
  maps_.push_back(std::make_unique<DeviceMap>(std::move(map)));
}

const DeviceMap* MapLibrary::find(std::string_view model) const {
  for (const auto& m : maps_) {
    if (m->model == model) return m.get();
  }
  return nullptr;
}

std::string MapLibrary::model_list() const {
  std::vector<std::string> names;
  for (const auto& m : maps_) names.push_back(m->model);
  std::sort(names.begin(), names.end());
  std::string out;
  for (const auto& n : names) {
    if (!out.empty()) out += ", ";
    out += n;
  }
  return out;
}

std::string MapLibrary::bundled_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / "share/rtuscope/dissectors";
    if (fs::is_directory(installed, ec)) return installed.string();
  }
#ifdef RTUSCOPE_DISSECTORS_DIR
  if (fs::is_directory(RTUSCOPE_DISSECTORS_DIR, ec)) return RTUSCOPE_DISSECTORS_DIR;
#endif
  return {};
}

}  // namespace rtu::dissect
