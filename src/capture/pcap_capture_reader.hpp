#pragma once
// The CaptureReader of pcap/pcapng files: PcapImporter's items (see capture/pcap_import.hpp)
// delivered as chunks, frames, noise and the capture's end, with what the file declares.
#include <optional>
#include <string>
#include <vector>

#include "capture/capture_file.hpp"
#include "capture/capture_reader.hpp"
#include "capture/capture_warnings.hpp"
#include "capture/pcap_import.hpp"

namespace rtu {

class PcapCaptureReader final : public CaptureReader {
 public:
  // Throws InputError when the file cannot be opened or its header is unusable. Times that
  // go backwards are clamped and reported to `warnings` (BackwardTimeClamp).
  PcapCaptureReader(const CaptureFile& file, WarningSink warnings);

  bool read(CaptureConsumer& to) override;
  [[nodiscard]] std::string name() const override { return importer_.name(); }
  [[nodiscard]] std::optional<LineSettings> declared_settings() const override {
    return importer_.declared_settings();
  }
  // The finest timestamp step of the interfaces of the records read so far.
  [[nodiscard]] Nanos timestamp_precision() const override { return precision_; }
  [[nodiscard]] std::optional<Nanos> declared_resolution() const override {
    return importer_.declared_resolution();
  }
  [[nodiscard]] std::optional<Nanos> declared_timeout() const override {
    return importer_.declared_timeout();
  }
  [[nodiscard]] bool holds_frames() const override { return true; }
  [[nodiscard]] std::uint64_t bytes_read() const override { return importer_.bytes_read(); }
  [[nodiscard]] std::uint64_t input_size() const override { return importer_.input_size(); }
  // Records cut short by the capturing tool: the bytes they lack show as damaged frames,
  // and the user must know why.
  [[nodiscard]] std::vector<std::string> capture_warnings() const override;

 private:
  BackwardTimeClamp& chunk_clamp(std::uint8_t port);

  PcapImporter importer_;
  PcapItem item_;
  Nanos precision_ = 0;
  WarningSink warnings_;
  // Frame and noise records are one stream; each port's reads are another (the two ports of
  // a recording are read by two threads, and are put in order by the decoder).
  BackwardTimeClamp record_clamp_;
  std::vector<BackwardTimeClamp> chunk_clamps_;
};

}  // namespace rtu
