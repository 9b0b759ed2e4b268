// The parts of `rtuscope extcap` that need no Wireshark: the text it lists, the port list,
// the pipe that notices its reader leaving. tests/extcap runs it under the real tshark.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <regex>
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

// Every line is a keyword and {key=value} groups; calls are lowercase (an uppercase letter
// makes Wireshark abort); numbers are unique and each value points at a selector arg.
TEST(Extcap, ConfigIsWellFormedForWireshark) {
  const std::regex line_shape(R"((arg|value) (\{[a-z]+=[^{}]*\})+)");
  const std::regex number(R"(\{number=(\d+)\})");
  const std::regex call(R"(\{call=([^}]*)\})");
  const std::regex value_arg(R"(^value \{arg=(\d+)\})");
  std::vector<std::string> calls;
  std::vector<int> selectors;
  int defaults_per_selector = 0;
  for (const auto& line : lines_of(extcap::config_text())) {
    EXPECT_TRUE(std::regex_match(line, line_shape)) << line;
    std::smatch m;
    if (std::regex_search(line, m, call)) {
      calls.push_back(m[1]);
      EXPECT_EQ(m[1].str().find_first_of("ABCDEFGHIJKLMNOPQRSTUVWXYZ"), std::string::npos);
      ASSERT_TRUE(std::regex_search(line, m, number)) << line;
      EXPECT_EQ(std::stoi(m[1]), static_cast<int>(calls.size()) - 1) << line;
      if (line.find("{type=selector}") != std::string::npos) {
        selectors.push_back(std::stoi(m[1]));
      }
    }
    if (std::regex_search(line, m, value_arg)) {
      EXPECT_NE(std::find(selectors.begin(), selectors.end(), std::stoi(m[1])), selectors.end())
          << line;
      if (line.find("{default=true}") != std::string::npos) ++defaults_per_selector;
    }
  }
  EXPECT_EQ(calls, (std::vector<std::string>{"--baud", "--parity", "--stop", "--timeout-ms",
                                             "--bus", "--link-type"}));
  EXPECT_EQ(defaults_per_selector, static_cast<int>(selectors.size()));
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
