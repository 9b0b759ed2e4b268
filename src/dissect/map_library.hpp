#pragma once
// The device maps available to a run: the bundled ones (dissectors/ installed beside the
// binary, or the source tree's in a build tree) plus any --dissectors folders, where a
// user's map replaces a bundled map of the same model.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "dissect/device_map.hpp"

namespace rtu::dissect {

class MapLibrary {
 public:
  // Loads every *.toml of `dir` (sorted by name). Returns the loader's messages
  // ("file:line: what"); maps with errors are not added.
  std::vector<std::string> load_dir(const std::string& dir);
  void add(DeviceMap map);  // replaces a map of the same model

  [[nodiscard]] const DeviceMap* find(std::string_view model) const;
  [[nodiscard]] const std::vector<std::unique_ptr<DeviceMap>>& maps() const { return maps_; }
  // "th900, yakotec, yw2050, yw2300"
  [[nodiscard]] std::string model_list() const;

  // Where the bundled maps are: <exe>/../share/rtuscope/dissectors when installed, else the
  // source tree's dissectors/ (RTUSCOPE_DISSECTORS_DIR). Empty when neither exists.
  static std::string bundled_dir();

 private:
  std::vector<std::unique_ptr<DeviceMap>>
      maps_;  // stable addresses for the device tables that point at them
};

}  // namespace rtu::dissect
