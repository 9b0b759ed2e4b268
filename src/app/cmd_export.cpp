// rtuscope export FILE... -o OUT.pcapng|OUT.pcap [--raw]: decodes a capture and writes the
// frames (and with --raw the raw reads and line events) for Wireshark.
#include <fmt/format.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/command.hpp"
#include "app/file_replaced_on_success.hpp"
#include "app/line_options.hpp"
#include "app/progress_line.hpp"
#include "capture/byte_output.hpp"
#include "capture/capture_paths.hpp"
#include "core/input_error.hpp"
#include "core/time_format.hpp"
#include "pipeline/replay.hpp"
#include "report/export_formats.hpp"
#include "report/pcap_export.hpp"

namespace rtu::app {
namespace {

struct ExportArgs {
  std::vector<std::string> files;
  std::string output;
  bool raw = false;
  LineOptions line;
  bool quiet = false;
};

std::string seconds_text(Nanos t) {
  fmt::memory_buffer out;
  append_seconds(out, t);
  return fmt::to_string(out);
}

// Decodes the capture as `survey` says into a new export at `path`; with `alongside`, `survey`
// is declared_survey's and the survey runs during the decoding. nullopt when that survey says
// the capture must be decoded again (the file is then written anew).
std::optional<PcapExportCounts> export_once(const CaptureOpener& capture,
                                            const CaptureSurvey& survey, bool alongside,
                                            ReplayOptions replay, const PcapExportOptions& options,
                                            const std::string& path) {
  auto file = std::make_unique<FileOutput>(path);
  FileOutput& written = *file;
  PcapExportSink sink(std::move(file), options);
  if (options.raw) replay.on_chunk = [&sink](const Chunk& chunk) { sink.on_chunk(chunk); };
  // Writing records costs less than framing them: the framing keeps the decoding core
  // (except where reads hold one byte: see ReplayOptions::frame_ahead).
  replay.frame_ahead = false;
  if (alongside) {
    if (!decode_and_survey(capture, survey, replay, sink)) return std::nullopt;
  } else {
    decode_capture(capture, survey, replay, sink);
  }
  written.flush();
  return sink.counts();
}

void setup_export(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<ExportArgs>();
  auto* cmd = app.add_subcommand(
      "export",
      "Decode a capture and write it for Wireshark: OUT.pcapng (frames; --raw adds the raw "
      "reads and line events on a second interface) or OUT.pcap (frames only). Open with "
      "`-o mbrtu.tcp.port:502 -o mbrtu.crc_verification:TRUE` to classify every function "
      "code and check CRCs.");
  cmd->add_option("file", args->files, capture_files_help())->required();
  cmd->add_option("-o,--output", args->output, export_output_help())->required();
  cmd->add_flag("--raw", args->raw,
                "Also write every raw read and line event (LINKTYPE_RTAC_SERIAL; pcapng only)");
  args->line.add_to(*cmd);
  add_quiet_flag(*cmd, args->quiet);
  cmd->callback([args, &exit_code] {
    const auto files = capture_inputs(args->files);
    PcapExportOptions options;
    options.format = export_format_for_path(args->output).factory;
    if (options.format == PcapExportFormat::kPcap && args->raw) {
      throw InputError(fmt::format(
          "{}: --raw needs a .pcapng output (classic pcap holds one link type per file)",
          args->output));
    }
    options.raw = args->raw;
    ReplayOptions replay = args->line.to_replay_options();
    FileReplacedOnSuccess output(args->output);
    ProgressLine progress(progress_wanted(args->quiet, args->output));
    progress.attach(replay, "exporting");
    const CaptureOpener capture = capture_opener(files);
    // The export says nothing that only the whole capture shows (its warnings go to stderr),
    // so a capture that declares its settings needs no survey pass first.
    const PcapExportCounts counts = decode_surveyed<PcapExportCounts>(
        capture, replay, true, [&](const CaptureSurvey& survey, bool alongside) {
          return export_once(capture, survey, alongside, replay, options, output.temporary_path());
        });
    progress.erase();
    output.commit();
    if (counts.shifted_by != 0) {
      fmt::print(stderr,
                 "rtuscope: warning: {}: every time is {} s later than in the capture: its first "
                 "record starts at {} s, and pcap files cannot hold times before 1970\n",
                 args->output, counts.shifted_by / kNanosPerSecond,
                 seconds_text(counts.first_time));
    }
    if (counts.clamped_to_zero != 0) {
      fmt::print(stderr,
                 "rtuscope: warning: {}: {} records still before 1970 after that were written "
                 "at time 0\n",
                 args->output, counts.clamped_to_zero);
    }
    fmt::print(stderr, "rtuscope: {}: {} frames, {} noise records{}\n", args->output, counts.frames,
               counts.noise,
               options.raw ? fmt::format(", {} raw records", counts.raw_records) : "");
    exit_code = 0;
  });
}

RTUSCOPE_REGISTER_COMMAND(setup_export);

}  // namespace
}  // namespace rtu::app
