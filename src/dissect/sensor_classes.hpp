#pragma once
// Home Assistant's classes for a point's unit (MQTT discovery): which device_class and
// state_class a sensor with unit "V" or "kWh" gets. The knowledge is data, in
// dissectors/home_assistant/sensor_classes.toml; this reads it.
#include <map>
#include <string>
#include <string_view>

namespace rtu::dissect {

struct SensorClass {
  std::string device_class;  // empty: none (e.g. "%", which can mean many things)
  std::string state_class;   // measurement, total or total_increasing
};

// measurement, total or total_increasing: the state classes Home Assistant knows.
[[nodiscard]] bool is_state_class(std::string_view text);

class SensorClasses {
 public:
  // Throws InputError "file:line: what" for a file that cannot be read, bad TOML, an
  // unknown key or a state_class outside the three Home Assistant knows.
  static SensorClasses load_file(const std::string& path);
  static SensorClasses load_text(std::string_view text, std::string_view file_name);
  // The bundled file, next to the bundled device maps ("" when there is none).
  static std::string bundled_path();

  // Null for a unit the file does not list.
  [[nodiscard]] const SensorClass* for_unit(std::string_view unit) const;
  [[nodiscard]] std::size_t size() const { return by_unit_.size(); }

 private:
  std::map<std::string, SensorClass, std::less<>> by_unit_;
};

}  // namespace rtu::dissect
