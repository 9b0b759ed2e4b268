// rtuscope report FILE... [--format text|json|html] [-o OUT] [--csv FILE]: statistics, timing
// diagnostics and ranked findings for a whole capture, in bounded memory.
#include <fmt/format.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/command.hpp"
#include "app/identify_models.hpp"
#include "app/line_options.hpp"
#include "app/progress_line.hpp"
#include "capture/capture_formats.hpp"
#include "capture/capture_paths.hpp"
#include "core/input_error.hpp"
#include "core/output_stream.hpp"
#include "dissect/device_stage.hpp"
#include "pipeline/record_fanout.hpp"
#include "pipeline/replay.hpp"
#include "report/findings.hpp"
#include "report/point_csv_writer.hpp"
#include "report/report_formats.hpp"
#include "report/traffic_stats.hpp"

namespace rtu::app {
namespace {

struct ReportArgs {
  std::vector<std::string> files;
  std::string format = "text";
  std::string output = "-";
  std::string csv;
  LineOptions line;
  DeviceOptions devices;
  bool no_identify = false;
  std::uint64_t identify_frames = kIdentifySampleFrames;
  bool quiet = false;
};

// The statistics of one decoding of a capture, and the device models they name.
struct Analysis {
  std::unique_ptr<DeviceSetup> devices;
  std::unique_ptr<TrafficStats> stats;
  // Where the input was damaged (the reader's message), empty if it was read to its end:
  // the statistics then cover what could be read (up to the damage; in a set of files, the
  // files after a damaged one too).
  std::string damage;
};

// What a report of a damaged capture says about it, among the capture's warnings.
std::string damage_warning(const std::string& damage) {
  return fmt::format(
      "the capture is damaged: {}; this report covers every record that could be read", damage);
}

// Identifies the slaves no option names (unless asked not to), then decodes the capture into
// the statistics and the CSV. With `alongside`, `survey` is declared_survey's and the survey
// runs during the decoding; nullopt when it says the capture must be decoded again.
std::optional<Analysis> analyse(const ReportArgs& args, const CaptureOpener& capture,
                                ReplayOptions options, const CaptureSurvey& survey, bool alongside,
                                std::unique_ptr<DeviceSetup> devices, ProgressLine& progress) {
  // Slaves no option names are identified from a first look at the capture: a sample that
  // the decoding looks at before it decodes the sample with what it found. The whole capture
  // (--identify-frames 0) is too much to hold meanwhile: it gets a pass of its own, which
  // shares the survey.
  std::optional<IdentifyingLook> look;
  std::optional<IdentificationSample> whole;
  if (!args.no_identify && !devices->library.maps().empty()) {
    if (args.identify_frames > 0) {
      options.first_look = &look.emplace(*devices, args.identify_frames);
    } else {
      whole = identify_from_whole_capture(*devices, options,
                                          [&](const ReplayOptions& o, RecordSink& sink) {
                                            ReplayOptions silent = o;
                                            silent.on_progress = nullptr;
                                            decode_capture(capture, survey, silent, sink);
                                          });
    }
  }
  Analysis analysis{std::move(devices), nullptr, {}};
  analysis.stats = std::make_unique<TrafficStats>(&analysis.devices->table);
  if (whole) analysis.stats->note_identification(*whole);
  RecordFanout sinks;
  sinks.add(*analysis.stats);
  std::optional<OutputStream> csv_out;
  std::optional<PointCsvWriter> csv;
  if (!args.csv.empty()) {
    csv_out.emplace(args.csv);
    csv.emplace(*csv_out);
    sinks.add(*csv);
  }
  dissect::DeviceStage stage(analysis.devices->table, sinks, true);
  progress.attach(options, "decoding");
  if (alongside) {
    const std::optional<CaptureInfo> info =
        decode_and_survey(capture, survey, options, stage, &analysis.damage);
    progress.erase();
    if (!info) return std::nullopt;
    analysis.stats->complete_capture(*info);
  } else {
    // Every record before any damage is decoded and counted: the report still covers them.
    analysis.stats->complete_capture(
        decode_capture(capture, survey, options, stage, &analysis.damage));
    progress.erase();
  }
  if (!analysis.damage.empty()) {
    CaptureInfo info = analysis.stats->capture();
    info.warnings.push_back(damage_warning(analysis.damage));
    analysis.stats->complete_capture(info);
  }
  if (csv) csv->flush();
  if (look) analysis.stats->note_identification(look->looked_at());
  return analysis;
}

void setup_report(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<ReportArgs>();
  auto* cmd = app.add_subcommand(
      "report", "Statistics, timing diagnostics and likely causes of problems for a capture");
  cmd->add_option("file", args->files, capture_files_help())->required();
  cmd->add_option("--format", args->format, "Report format")
      ->check(CLI::IsMember(format_names(report_formats())));
  cmd->add_option("-o,--output", args->output, "Report file (default: standard output)");
  cmd->add_option("--csv", args->csv,
                  "Also write register values over time as CSV (time,slave,point,value,unit)");
  args->line.add_to(*cmd);
  args->devices.add_to(*cmd);
  cmd->add_flag("--no-identify", args->no_identify,
                "Do not recognise unnamed slaves' models from the traffic; they keep raw "
                "registers");
  cmd->add_option("--identify-frames", args->identify_frames,
                  "Recognise unnamed slaves' models from this many first frames, a byte of noise "
                  "counting as a frame (0 = the whole capture); slaves first heard later keep "
                  "raw registers")
      ->capture_default_str();
  add_quiet_flag(*cmd, args->quiet);
  cmd->callback([args, &exit_code] {
    const CaptureOpener capture = capture_opener(capture_inputs(args->files));
    ReplayOptions options = args->line.to_replay_options();
    auto devices = args->devices.build_with_maps(options);
    // The report is written at the end, so only a CSV on standard output competes with the line.
    ProgressLine progress(progress_wanted(args->quiet, args->csv));
    progress.attach(options, "decoding");
    // A capture that declares its settings (a live recording) needs no survey pass first:
    // the report is written at the end, so what only the whole capture shows is learned
    // alongside the decoding. Not with a CSV, which is written as the decoding goes.
    const Analysis analysis = decode_surveyed<Analysis>(
        capture, options, args->csv.empty(), [&](const CaptureSurvey& survey, bool alongside) {
          // A second decoding starts again from the models the options name.
          if (!devices) devices = args->devices.build_with_maps(options);
          return analyse(*args, capture, options, survey, alongside, std::move(devices), progress);
        });
    const std::vector<Finding> findings = find_problems(*analysis.stats);
    OutputStream out(args->output);
    find_format_or_default(report_formats(), args->format).factory(out, *analysis.stats, findings);
    if (!analysis.damage.empty()) {
      // The report is written; the damage still fails the command, as it fails decode.
      out.flush();
      throw InputError(
          fmt::format("{} (the report covers every record that could be read)", analysis.damage));
    }
    exit_code = 0;
  });
}

RTUSCOPE_REGISTER_COMMAND(setup_report);

}  // namespace
}  // namespace rtu::app
