// The parts of `rtuscope extcap` that need no Wireshark: the text it lists, the port list,
// the pipe that notices its reader leaving. tests/extcap runs it under the real tshark.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "capture/pipe_output.hpp"
#include "report/extcap_text.hpp"
#include "serial/port_discovery.hpp"

namespace rtu {
namespace {

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(Extcap, InterfaceNamesCarryThePortAndRoundTrip) {
  EXPECT_EQ(extcap::interface_for_port("/dev/ttyUSB0"), "rtuscope/dev/ttyUSB0");
  EXPECT_EQ(extcap::port_for_interface("rtuscope/dev/pts/7"), "/dev/pts/7");
  EXPECT_EQ(extcap::port_for_interface("rtuscope"), std::nullopt);
  EXPECT_EQ(extcap::port_for_interface("rtuscope/"), std::nullopt);
  EXPECT_EQ(extcap::port_for_interface("rtuscopedev"), std::nullopt);
  EXPECT_EQ(extcap::port_for_interface("eth0"), std::nullopt);
}

TEST(Extcap, InterfacesTextHasTheVersionThenOneLinePerPort) {
  const auto lines = lines_of(extcap::interfaces_text({"/dev/ttyUSB0", "/dev/pts/3"}, "1.2.3"));
  ASSERT_EQ(lines.size(), 3U);
  EXPECT_EQ(lines[0], "extcap {version=1.2.3}");
  EXPECT_EQ(lines[1],
            "interface {value=rtuscope/dev/ttyUSB0}{display=Modbus RTU on /dev/ttyUSB0 "
            "(rtuscope)}");
  EXPECT_EQ(lines[2],
            "interface {value=rtuscope/dev/pts/3}{display=Modbus RTU on /dev/pts/3 "
            "(rtuscope)}");
}

TEST(Extcap, DltsAreUpperPduThenRtacSerial) {
  const auto lines = lines_of(extcap::dlts_text());
  ASSERT_EQ(lines.size(), 2U);
  EXPECT_TRUE(lines[0].starts_with("dlt {number=252}{name=USER_PDU}")) << lines[0];
  EXPECT_TRUE(lines[1].starts_with("dlt {number=250}{name=RTAC_SERIAL}")) << lines[1];
}

// "arg {number=0}{call=--baud}" → {"arg", {{"number","0"}, {"call","--baud"}}}; an empty
// keyword when the line is not a keyword followed by {key=value} groups only.
struct ExtcapLine {
  std::string keyword;
  std::map<std::string, std::string> fields;
};
ExtcapLine parse_line(const std::string& line) {
  ExtcapLine parsed;
  const std::size_t space = line.find(' ');
  if (space == std::string::npos) return {};
  std::string rest = line.substr(space + 1);
  while (!rest.empty()) {
    const std::size_t close = rest.find('}');
    const std::size_t equals = rest.find('=');
    if (rest[0] != '{' || close == std::string::npos || equals == std::string::npos ||
        equals > close || rest.find('{', 1) < close) {
      return {};
    }
    const std::string key = rest.substr(1, equals - 1);
    if (key.empty() || key.find_first_not_of("abcdefghijklmnopqrstuvwxyz") != std::string::npos) {
      return {};
    }
    parsed.fields[key] = rest.substr(equals + 1, close - equals - 1);
    rest = rest.substr(close + 1);
  }
  parsed.keyword = line.substr(0, space);
  return parsed;
}

// Every line is a keyword and {key=value} groups; calls are lowercase (an uppercase letter
// makes Wireshark abort); numbers count up from 0; each value points at a selector arg,
// and each selector has one default.
TEST(Extcap, ConfigIsWellFormedForWireshark) {
  std::vector<std::string> calls;
  std::vector<int> selectors;
  int defaults = 0;
  for (const auto& line : lines_of(extcap::config_text())) {
    const ExtcapLine parsed = parse_line(line);
    ASSERT_TRUE(parsed.keyword == "arg" || parsed.keyword == "value") << line;
    if (parsed.keyword == "arg") {
      const std::string& call = parsed.fields.at("call");
      EXPECT_EQ(call.find_first_of("ABCDEFGHIJKLMNOPQRSTUVWXYZ"), std::string::npos) << line;
      EXPECT_EQ(parsed.fields.at("number"), std::to_string(calls.size())) << line;
      calls.push_back(call);
      if (parsed.fields.at("type") == "selector")
        selectors.push_back(static_cast<int>(calls.size()) - 1);
    } else {
      const int arg = std::stoi(parsed.fields.at("arg"));
      EXPECT_NE(std::find(selectors.begin(), selectors.end(), arg), selectors.end()) << line;
      if (parsed.fields.count("default") != 0) ++defaults;
    }
  }
  EXPECT_EQ(calls, (std::vector<std::string>{"--baud", "--parity", "--stop", "--timeout-ms",
                                             "--bus", "--link-type"}));
  EXPECT_EQ(defaults, static_cast<int>(selectors.size()));
}

TEST(Extcap, TheLineParserOfThisTestRejectsMalformedLines) {
  EXPECT_EQ(parse_line("arg {number=0}{call=--baud}").keyword, "arg");
  EXPECT_EQ(parse_line("arg {number=0}call=--baud}").keyword, "");
  EXPECT_EQ(parse_line("arg {Number=0}").keyword, "");
  EXPECT_EQ(parse_line("arg").keyword, "");
}

TEST(Extcap, PortListSplitsOnColonsAndSkipsEmptyEntries) {
  EXPECT_EQ(split_port_list("/dev/pts/3::/tmp/ep1:"),
            (std::vector<std::string>{"/dev/pts/3", "/tmp/ep1"}));
  EXPECT_TRUE(split_port_list("").empty());
}

// A fake /dev: regular files are no terminals, so none is listed; the scan itself must cope
// with a missing serial/by-id folder.
TEST(Extcap, PortScanListsOnlyWhatOpensAsATerminal) {
  const auto dev =
      std::filesystem::temp_directory_path() / ("rtuscope_fake_dev_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dev);
  for (const char* name : {"ttyUSB0", "ttyS1", "ttyACM2", "ttyUSBx"}) {
    std::ofstream(dev / name) << "";
  }
  EXPECT_TRUE(find_serial_ports(dev.string()).empty());
  std::filesystem::remove_all(dev);
}

TEST(Extcap, PipeOutputNoticesItsReaderLeaving) {
  std::signal(SIGPIPE, SIG_IGN);
  const auto fifo =
      std::filesystem::temp_directory_path() / ("rtuscope_fifo_test_" + std::to_string(::getpid()));
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  // The reader opens first (non-blocking), so the writer's open returns at once.
  const int reader = ::open(fifo.c_str(), O_RDONLY | O_NONBLOCK);
  ASSERT_GE(reader, 0);
  {
    PipeOutput out(fifo.string());
    const std::vector<std::uint8_t> unit = {1, 2, 3, 4};
    out.write(unit);
    std::uint8_t got[8] = {};
    EXPECT_EQ(::read(reader, got, sizeof got), 4);  // written at once, nothing held back
    EXPECT_FALSE(out.reader_gone());
    ::close(reader);
    EXPECT_TRUE(out.reader_gone());  // seen without writing
    out.write(unit);
    EXPECT_EQ(out.dropped_units(), 1U);
  }
  std::filesystem::remove(fifo);
}

}  // namespace
}  // namespace rtu
