// rtuscope decode FILE... [--format text|jsonl]: frames, pairs and decodes a capture.
#include <memory>
#include <string>
#include <vector>

#include "app/command.hpp"
#include "app/device_options.hpp"
#include "app/line_options.hpp"
#include "app/progress_line.hpp"
#include "app/record_writer.hpp"
#include "capture/capture_paths.hpp"
#include "core/output_stream.hpp"
#include "dissect/device_stage.hpp"
#include "pipeline/replay.hpp"
#include "report/record_formats.hpp"

namespace rtu::app {
namespace {

struct DecodeArgs {
  std::vector<std::string> files;
  std::string format = "text";
  std::string output = "-";
  LineOptions line;
  DeviceOptions devices;
  bool quiet = false;
};

void setup_decode(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<DecodeArgs>();
  auto* cmd = app.add_subcommand("decode", "Decode a capture file into frames and transactions");
  cmd->add_option("file", args->files, capture_files_help())->required();
  cmd->add_option("--format", args->format, "Output format")
      ->check(CLI::IsMember(format_names(record_formats())));
  cmd->add_option("-o,--output", args->output, "Output file (default: standard output)");
  args->line.add_to(*cmd);
  args->devices.add_to(*cmd);
  add_quiet_flag(*cmd, args->quiet);
  cmd->callback([args, &exit_code] {
    const auto files = capture_inputs(args->files);
    ReplayOptions options = args->line.to_replay_options();
    const auto devices = args->devices.build(options);
    ProgressLine progress(progress_wanted(args->quiet, args->output));
    progress.attach(options, "decoding");
    OutputStream out(args->output);
    const auto writer = make_record_writer(args->format, out);
    dissect::DeviceTable no_devices;  // plain Modbus when no slave is named
    dissect::DeviceStage stage(devices ? devices->table : no_devices, *writer);
    replay_capture(files, options, stage);
    exit_code = 0;
  });
}

RTUSCOPE_REGISTER_COMMAND(setup_decode);

}  // namespace
}  // namespace rtu::app
