// The MQTT side without a broker: which messages the feed makes of records (tests/mqtt runs
// the whole path against the real Mosquitto), the URL and credentials parsing, and the
// unit → Home Assistant class data.
#include "report/mqtt_feed.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/input_error.hpp"
#include "dissect/device_map.hpp"
#include "dissect/device_stage.hpp"
#include "dissect/sensor_classes.hpp"
#include "pipeline/mqtt_client.hpp"

namespace rtu {
namespace {

constexpr Nanos kT0 = 1'800'000'000 * kNanosPerSecond;  // a wall-clock time
constexpr Nanos kMs = kNanosPerMilli;

struct Collected {
  std::vector<MqttMessage> messages;
  [[nodiscard]] std::vector<std::string> on(const std::string& topic) const {
    std::vector<std::string> payloads;
    for (const auto& m : messages) {
      if (m.topic == topic) payloads.push_back(m.payload);
    }
    return payloads;
  }
};

class FeedTest : public ::testing::Test {
 protected:
  FeedTest() {
    map_.model = "meter";
    map_.name = "Test meter";
    MqttFeedOptions options;
    options.bus = "ttyUSB0";
    options.discovery = true;
    options.classes = &classes_;
    feed_ = std::make_unique<MqttFeed>(
        options, [this](MqttMessage&& m) { out_.messages.push_back(std::move(m)); });
  }

  // A sound response of slave 1 carrying Ua = value at time t.
  void response(Nanos t, double value, bool with_value = true) {
    std::vector<dissect::PointValue> values;
    if (with_value) values.push_back({t, 1, "Ua", value, "V"});
    response_with(t, values);
  }
  // A sound response of slave 1 carrying these values.
  void response_with(Nanos t, const std::vector<dissect::PointValue>& values) {
    Record r;
    r.t_start = t;
    r.t_end = t + kMs;
    r.size = 2;
    r.storage[0] = 1;
    r.storage[1] = 3;
    r.crc_ok = true;
    r.role = Role::kResponse;
    dissect::DeviceReading reading;
    reading.map = &map_;
    reading.values = values;
    r.device = &reading;
    feed_->on_record(r);
  }
  void timed_out_request(Nanos t) {
    Record r;
    r.t_start = t;
    r.size = 2;
    r.storage[0] = 1;
    r.storage[1] = 3;
    r.crc_ok = true;
    r.role = Role::kRequest;
    r.issues.add(IssueId::kTimeout);
    feed_->on_record(r);
  }

  dissect::DeviceMap map_;
  dissect::SensorClasses classes_ = dissect::SensorClasses::load_text(
      "[unit.\"V\"]\ndevice_class = \"voltage\"\n"
      "state_class = \"measurement\"\n"
      "[unit.\"kWh\"]\ndevice_class = \"energy\"\n"
      "state_class = \"total_increasing\"\n",
      "classes.toml");
  Collected out_;
  std::unique_ptr<MqttFeed> feed_;
};

TEST_F(FeedTest, AChangeWithinASecondWaitsAndTheLatestValueWins) {
  response(kT0, 230.0);
  response(kT0 + 200 * kMs, 231.0);
  response(kT0 + 400 * kMs, 232.0);
  EXPECT_EQ(out_.on("rtuscope/ttyUSB0/1/Ua").size(), 1U);
  response(kT0 + 1100 * kMs, 232.0, false);  // any later record lets the held value out
  const auto values = out_.on("rtuscope/ttyUSB0/1/Ua");
  ASSERT_EQ(values.size(), 2U);
  EXPECT_EQ(values[0],
            R"({"value":230,"unit":"V","time":"2027-01-15T08:00:00.000Z","model":"meter"})");
  EXPECT_NE(values[1].find(R"("value":232,)"), std::string::npos) << values[1];
  EXPECT_NE(values[1].find("08:00:00.400Z"), std::string::npos) << values[1];
}

TEST_F(FeedTest, AnUnchangedValueIsNotRepeatedAndFinishSendsWhatIsHeld) {
  response(kT0, 230.0);
  response(kT0 + 2000 * kMs, 230.0);
  EXPECT_EQ(out_.on("rtuscope/ttyUSB0/1/Ua").size(), 1U);
  response(kT0 + 2050 * kMs, 229.0);
  response(kT0 + 2080 * kMs, 228.0);
  feed_->on_finish();
  const auto values = out_.on("rtuscope/ttyUSB0/1/Ua");
  ASSERT_EQ(values.size(), 3U);
  EXPECT_NE(values[2].find(R"("value":228,)"), std::string::npos) << values[2];
}

TEST_F(FeedTest, DiscoveryConfigComesFirstRetainedWithTheUnitsClasses) {
  response(kT0, 230.0);
  ASSERT_GE(out_.messages.size(), 3U);
  const MqttMessage* config = nullptr;
  std::size_t config_at = 0;
  std::size_t value_at = 0;
  for (std::size_t i = 0; i < out_.messages.size(); ++i) {
    if (out_.messages[i].topic == "homeassistant/sensor/rtuscope_ttyUSB0_1/Ua/config") {
      config = &out_.messages[i];
      config_at = i;
    }
    if (out_.messages[i].topic == "rtuscope/ttyUSB0/1/Ua") value_at = i;
  }
  ASSERT_NE(config, nullptr);
  EXPECT_LT(config_at, value_at);
  EXPECT_TRUE(config->retain);
  for (const char* part :
       {R"("device_class":"voltage")", R"("state_class":"measurement")",
        R"("unit_of_measurement":"V")", R"("identifiers":["rtuscope_ttyUSB0_1"])",
        R"("availability_topic":"rtuscope/ttyUSB0/1/status")"}) {
    EXPECT_NE(config->payload.find(part), std::string::npos) << part << " in " << config->payload;
  }
}

TEST_F(FeedTest, APointsOwnClassesWinOverItsUnitsAndEmptyMeansNone) {
  dissect::Point pf;  // no unit, so no classes but its own
  pf.name = "PF";
  pf.device_class = "power_factor";
  pf.state_class = "measurement";
  dissect::Point energy;  // a counter that may be reset: total, not total_increasing
  energy.name = "E";
  energy.unit = "kWh";
  energy.state_class = "total";
  dissect::Point setting;  // a set-point in volts: not a measurement
  setting.name = "Uset";
  setting.unit = "V";
  setting.state_class = "";
  dissect::Point plain;  // says nothing: the unit's classes
  plain.name = "Ua";
  plain.unit = "V";
  dissect::Point counter;  // says nothing either; a class name too long to be stored inline
  counter.name = "Ein";
  counter.unit = "kWh";
  std::vector<dissect::PointValue> values;
  for (const dissect::Point* p : {&pf, &energy, &setting, &plain, &counter}) {
    dissect::PointValue v{kT0, 1, p->name, 1.0, p->unit};
    v.definition = p;
    values.push_back(v);
  }
  response_with(kT0, values);
  auto config = [this](const std::string& point) {
    const auto configs = out_.on("homeassistant/sensor/rtuscope_ttyUSB0_1/" + point + "/config");
    return configs.size() == 1 ? configs[0] : std::string("(" + point + ": no single config)");
  };
  auto has = [](const std::string& text, const char* part) {
    return text.find(part) != std::string::npos;
  };
  const std::string pf_config = config("PF");
  EXPECT_TRUE(has(pf_config, R"("device_class":"power_factor")")) << pf_config;
  EXPECT_TRUE(has(pf_config, R"("state_class":"measurement")")) << pf_config;
  EXPECT_FALSE(has(pf_config, "unit_of_measurement")) << pf_config;
  const std::string energy_config = config("E");
  EXPECT_TRUE(has(energy_config, R"("device_class":"energy")")) << energy_config;
  EXPECT_TRUE(has(energy_config, R"("state_class":"total")")) << energy_config;
  EXPECT_FALSE(has(energy_config, "total_increasing")) << energy_config;
  const std::string setting_config = config("Uset");
  EXPECT_TRUE(has(setting_config, R"("device_class":"voltage")")) << setting_config;
  EXPECT_FALSE(has(setting_config, "state_class")) << setting_config;
  const std::string plain_config = config("Ua");
  EXPECT_TRUE(has(plain_config, R"("device_class":"voltage")")) << plain_config;
  EXPECT_TRUE(has(plain_config, R"("state_class":"measurement")")) << plain_config;
  const std::string counter_config = config("Ein");
  EXPECT_TRUE(has(counter_config, R"("state_class":"total_increasing")")) << counter_config;
}

TEST_F(FeedTest, ASlaveGoesOfflineAfterThreeTimeoutsInARowAndBackOnline) {
  response(kT0, 230.0);
  timed_out_request(kT0 + 1000 * kMs);
  timed_out_request(kT0 + 2000 * kMs);
  EXPECT_EQ(out_.on("rtuscope/ttyUSB0/1/status"), (std::vector<std::string>{"online"}));
  timed_out_request(kT0 + 3000 * kMs);
  timed_out_request(kT0 + 4000 * kMs);
  response(kT0 + 5000 * kMs, 230.0);
  EXPECT_EQ(out_.on("rtuscope/ttyUSB0/1/status"),
            (std::vector<std::string>{"online", "offline", "online"}));
  // The timeout is a finding once, not four times.
  EXPECT_EQ(out_.on("rtuscope/ttyUSB0/findings").size(), 1U);
}

TEST(MqttOptions, UrlsAndTheirMistakes) {
  const auto plain = parse_mqtt_url("mqtt://127.0.0.1");
  EXPECT_FALSE(plain.tls);
  EXPECT_EQ(plain.host, "127.0.0.1");
  EXPECT_EQ(plain.port, 1883);
  const auto tls = parse_mqtt_url("mqtts://broker.example:8884/");
  EXPECT_TRUE(tls.tls);
  EXPECT_EQ(tls.host, "broker.example");
  EXPECT_EQ(tls.port, 8884);
  for (const char* bad : {"tcp://host", "mqtt://", "mqtt://host:0", "mqtt://host:99999",
                          "mqtt://user:pw@host", "mqtt://host:12x"}) {
    EXPECT_THROW((void)parse_mqtt_url(bad), InputError) << bad;
  }
}

TEST(MqttOptions, CredentialsComeFromAFileOfTwoLines) {
  const auto path = std::filesystem::temp_directory_path() /
                    ("rtuscope_mqtt_credentials_" + std::to_string(::getpid()));
  std::ofstream(path) << "sniffer\r\ns3cret\n";
  const auto credentials = read_mqtt_credentials(path.string());
  EXPECT_EQ(credentials.user, "sniffer");
  EXPECT_EQ(credentials.password, "s3cret");
  std::ofstream(path) << "\n";
  try {
    (void)read_mqtt_credentials(path.string());
    ADD_FAILURE() << "an empty user was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string() + ":1:"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

TEST(SensorClasses, TheBundledFileLoadsAndBadEntriesNameTheirLine) {
  const auto bundled = dissect::SensorClasses::load_file(dissect::SensorClasses::bundled_path());
  ASSERT_NE(bundled.for_unit("kWh"), nullptr);
  EXPECT_EQ(bundled.for_unit("kWh")->state_class, "total_increasing");
  EXPECT_EQ(bundled.for_unit("W")->device_class, "power");
  EXPECT_EQ(bundled.for_unit("r/min"), nullptr);
  try {
    (void)dissect::SensorClasses::load_text("[unit.\"V\"]\nstate_class = \"sometimes\"\n",
                                            "x.toml");
    ADD_FAILURE() << "a bad state_class was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("x.toml:1:"), std::string::npos) << e.what();
  }
  EXPECT_THROW(
      (void)dissect::SensorClasses::load_text("[unit.\"V\"]\ncolour = \"red\"\n", "x.toml"),
      InputError);
}

TEST(MqttId, KeepsWhatTopicsAndIdsMayHold) {
  EXPECT_EQ(mqtt_id("Ua"), "Ua");
  EXPECT_EQ(mqtt_id("M/A"), "M_A");
  EXPECT_EQ(mqtt_id("+Wh"), "_Wh");
  EXPECT_EQ(mqtt_id(""), "_");
  EXPECT_EQ(mqtt_base_topic("tty USB0"), "rtuscope/tty_USB0");
}

}  // namespace
}  // namespace rtu
