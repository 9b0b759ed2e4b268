// A generic conforming Modbus device (no shared document). It answers the public function
// codes the four documented models lack, with the ADU shapes of MODBUS Application Protocol
// V1.1b3 §6, and one vendor code (0x41, user-defined range 65-72) whose length no rule
// predicts, so decoders must frame it by silence or by CRC alone.
#include <array>
#include <string_view>

#include "devices.hpp"

namespace rtu::sim {
namespace {

class Generic final : public DeviceProfile {
 public:
  using DeviceProfile::DeviceProfile;
  [[nodiscard]] std::string_view name() const override { return "generic"; }

  void poll_cycle(Rng& rng, std::vector<Exchange>& out) override {
    ++messages_;
    out.push_back(one_exchange(rng));
  }

  Exchange provoke_exception(Rng& rng) override {
    const std::uint8_t a = address();
    switch (rng.below(3)) {
      case 0:  // MEI type 0D (CANopen) is not supported here
        return {AduBuilder(a, 0x2B).u8(0x0D).u8(0x00).u8(0x00).seal(),
                exception_response(a, 0x2B, 0x01)};
      case 1: return {read_request(a, 0x03, 0xFFF0, 8), exception_response(a, 0x03, 0x02)};
      default:  // FIFO queue pointer that does not exist
        return {AduBuilder(a, 0x18).u16(0x9999).seal(), exception_response(a, 0x18, 0x02)};
    }
  }

  Bytes broadcast_write(Rng& rng) override {
    (void)rng;
    // FC0F: switch off coils 0..9 of every device.
    return AduBuilder(0, 0x0F).u16(0x0000).u16(10).u8(2).u8(0x00).u8(0x00).seal();
  }

  Nanos turnaround(Rng& rng) override { return rng.nanos(4 * kNanosPerMilli, 10 * kNanosPerMilli); }

 private:
  static void put_text(AduBuilder& b, std::uint8_t id, std::string_view text) {
    b.u8(id).u8(static_cast<std::uint8_t>(text.size()));
    for (const char c : text) b.u8(static_cast<std::uint8_t>(c));
  }

  Exchange one_exchange(Rng& rng) {
    const std::uint8_t a = address();
    switch (rng.below(13)) {
      case 0:  // FC07 Read Exception Status
        return {AduBuilder(a, 0x07).seal(), AduBuilder(a, 0x07).u8(0x00).seal()};
      case 1: {  // FC08/0000 Return Query Data: any even length, echoed
        AduBuilder b(a, 0x08);
        b.u16(0x0000);
        const auto words = rng.between(1, 3);
        for (std::int64_t i = 0; i < words; ++i) b.u16(rng.word());
        const Bytes req = b.seal();
        return {req, req};
      }
      case 2:  // FC08/000B Return Bus Message Count
        return {AduBuilder(a, 0x08).u16(0x000B).u16(0).seal(),
                AduBuilder(a, 0x08).u16(0x000B).u16(messages_).seal()};
      case 3:  // FC0B Get Comm Event Counter: status, event count
        return {AduBuilder(a, 0x0B).seal(), AduBuilder(a, 0x0B).u16(0).u16(messages_).seal()};
      case 4: {  // FC0F Write Multiple Coils: 10 coils from 0x0013
        const std::uint16_t bits = rng.word() & 0x03FFU;
        return {AduBuilder(a, 0x0F)
                    .u16(0x0013)
                    .u16(10)
                    .u8(2)
                    .u8(static_cast<std::uint8_t>(bits & 0xFFU))
                    .u8(static_cast<std::uint8_t>(bits >> 8U))
                    .seal(),
                AduBuilder(a, 0x0F).u16(0x0013).u16(10).seal()};
      }
      case 5: {  // FC11 Report Server ID: byte count, id, run indicator, text
        AduBuilder b(a, 0x11);
        constexpr std::string_view kText = "GEN-1 v1.2";
        b.u8(static_cast<std::uint8_t>(2 + kText.size())).u8(0x47).u8(0xFF);
        for (const char c : kText) b.u8(static_cast<std::uint8_t>(c));
        return {AduBuilder(a, 0x11).seal(), b.seal()};
      }
      case 6: {  // FC14 Read File Record: one sub-request, file 4, record 1, 2 registers
        const Bytes req = AduBuilder(a, 0x14).u8(7).u8(6).u16(0x0004).u16(0x0001).u16(2).seal();
        const Bytes resp = AduBuilder(a, 0x14)
                               .u8(6)  // response data length: one sub-response of 1 + 5
                               .u8(5)  // sub-response length: reference type + 2 registers
                               .u8(6)
                               .u16(rng.word())
                               .u16(rng.word())
                               .seal();
        return {req, resp};
      }
      case 7: {  // FC16 Mask Write Register: echoed
        const Bytes req = AduBuilder(a, 0x16).u16(0x0004).u16(0x00F2).u16(0x0025).seal();
        return {req, req};
      }
      case 8: {  // FC17 Read/Write Multiple Registers: write 2 at 0x0010, read 3 at 0x0000
        const std::uint16_t w1 = rng.word();
        const std::uint16_t w2 = rng.word();
        return {
            AduBuilder(a, 0x17).u16(0x0000).u16(3).u16(0x0010).u16(2).u8(4).u16(w1).u16(w2).seal(),
            registers_response(a, 0x17, {messages_, w1, w2})};
      }
      case 9: {  // FC18 Read FIFO Queue: 2-byte byte count, 2-byte FIFO count, values
        const auto count = static_cast<std::uint16_t>(rng.between(0, 5));
        AduBuilder b(a, 0x18);
        b.u16(static_cast<std::uint16_t>(2 + 2 * count)).u16(count);
        for (std::uint16_t i = 0; i < count; ++i) b.u16(rng.word());
        return {AduBuilder(a, 0x18).u16(0x04DE).seal(), b.seal()};
      }
      case 10: {  // FC2B/0E Read Device Identification, basic objects, stream access
        AduBuilder b(a, 0x2B);
        b.u8(0x0E).u8(0x01).u8(0x01).u8(0x00).u8(0x00).u8(3);
        put_text(b, 0x00, "Generic");
        put_text(b, 0x01, "GEN-1");
        put_text(b, 0x02, "V1.2");
        return {AduBuilder(a, 0x2B).u8(0x0E).u8(0x01).u8(0x00).seal(), b.seal()};
      }
      case 11:  // FC04 Read Input Registers
        return {read_request(a, 0x04, 0x0000, 2),
                registers_response(a, 0x04, {messages_, rng.word()})};
      default: {  // FC41, vendor-defined: lengths that no public rule predicts
        AduBuilder req(a, 0x41);
        AduBuilder resp(a, 0x41);
        const auto n_req = rng.between(1, 6);
        const auto n_resp = rng.between(2, 12);
        for (std::int64_t i = 0; i < n_req; ++i) req.u8(rng.byte());
        for (std::int64_t i = 0; i < n_resp; ++i) resp.u8(rng.byte());
        return {req.seal(), resp.seal()};
      }
    }
  }

  std::uint16_t messages_ = 0;
};

}  // namespace

std::unique_ptr<DeviceProfile> make_generic(std::uint8_t address) {
  return std::make_unique<Generic>(address);
}

}  // namespace rtu::sim
