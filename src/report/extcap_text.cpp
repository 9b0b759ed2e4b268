#include "report/extcap_text.hpp"

#include <fmt/format.h>

namespace rtu::extcap {

std::string interface_for_port(std::string_view port) {
  return fmt::format("{}{}", kInterfacePrefix, port);
}

std::optional<std::string> port_for_interface(std::string_view interface) {
  if (!interface.starts_with(kInterfacePrefix)) return std::nullopt;
  interface.remove_prefix(kInterfacePrefix.size());
  if (interface.size() < 2 || interface.front() != '/') return std::nullopt;
  return std::string(interface);
}

std::string interfaces_text(const std::vector<std::string>& ports, std::string_view version) {
  std::string text = fmt::format("extcap {{version={}}}\n", version);
  for (const auto& port : ports) {
    text += fmt::format("interface {{value={}}}{{display=Modbus RTU on {} (rtuscope)}}\n",
                        interface_for_port(port), port);
  }
  return text;
}

std::string dlts_text() {
  return "dlt {number=252}{name=USER_PDU}{display=Decoded Modbus RTU frames (Upper PDU)}\n"
         "dlt {number=250}{name=RTAC_SERIAL}{display=Raw serial reads and line events}\n";
}

std::string config_text() {
  std::string text;
  // The numbers say where each option sits in Wireshark's dialog.
  text +=
      "arg {number=0}{call=--baud}{display=Baud rate}{type=integer}{range=50,20000000}"
      "{tooltip=Line speed in bit/s; any rate the adapter can do. Empty: the bus file's, else "
      "9600}{group=Line}\n";
  text += fmt::format(
      "arg {{number=1}}{{call=--parity}}{{display=Parity}}{{type=selector}}{{group=Line}}\n"
      "value {{arg=1}}{{value={0}}}{{display=From the bus file, else even}}{{default=true}}\n"
      "value {{arg=1}}{{value=E}}{{display=Even}}\n"
      "value {{arg=1}}{{value=N}}{{display=None}}\n"
      "value {{arg=1}}{{value=O}}{{display=Odd}}\n"
      "arg {{number=2}}{{call=--stop}}{{display=Stop bits}}{{type=selector}}{{group=Line}}\n"
      "value {{arg=2}}{{value={0}}}{{display=From the bus file, else 1}}{{default=true}}\n"
      "value {{arg=2}}{{value=1}}{{display=1}}\n"
      "value {{arg=2}}{{value=2}}{{display=2}}\n",
      kAuto);
  text +=
      "arg {number=3}{call=--timeout-ms}{display=Response timeout (ms)}{type=integer}"
      "{range=1,600000}{tooltip=A request unanswered this long is a timeout. Empty: the bus "
      "file's, else 1000}{group=Decoding}\n"
      "arg {number=4}{call=--bus}{display=Bus file}{type=fileselect}{mustexist=true}"
      "{tooltip=TOML file with the line settings and which slave is which device model}"
      "{group=Decoding}\n";
  text += fmt::format(
      "arg {{number=5}}{{call=--link-type}}{{display=Link type}}{{type=selector}}"
      "{{group=Decoding}}\n"
      "value {{arg=5}}{{value={}}}{{display=Decoded frames with comments (Upper PDU, "
      "mbrtu)}}{{default=true}}\n"
      "value {{arg=5}}{{value={}}}{{display=Raw reads and line events (RTAC Serial)}}\n",
      kLinkFrames, kLinkRaw);
  return text;
}

}  // namespace rtu::extcap
