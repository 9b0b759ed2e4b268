// rtuscope probe PORT: finds the line settings of an unknown bus by listening at each
// candidate setting in turn, never transmitting; ranks them by CRC-valid frames against
// line errors and says what the line itself shows. Exit 0 with a winner, 3 without.
#include <fmt/format.h>

#include <cstdio>
#include <memory>
#include <string>

#include "app/command.hpp"
#include "core/output_error.hpp"
#include "pipeline/line_probe.hpp"
#include "report/probe_report.hpp"

namespace rtu::app {
namespace {

constexpr int kExitNothingFits = 3;

struct ProbeArgs {
  std::string port;
  bool quick = false;
  std::string json_path;
  double dwell_s = 2.0;
  double max_time_s = 300.0;
  std::size_t rows = 12;
};

void write_json(const std::string& path, const std::string& text) {
  if (path == "-") {
    std::fwrite(text.data(), 1, text.size(), stdout);
    return;
  }
  std::FILE* f = std::fopen(path.c_str(), "w");
  const bool ok = f != nullptr && std::fwrite(text.data(), 1, text.size(), f) == text.size();
  if (f != nullptr && std::fclose(f) != 0) throw OutputError(fmt::format("{}: cannot write", path));
  if (!ok) throw OutputError(fmt::format("{}: cannot write", path));
}

void setup_probe(CLI::App& app, int& exit_code) {
  auto args = std::make_shared<ProbeArgs>();
  auto* cmd = app.add_subcommand(
      "probe",
      "Find an unknown bus's baud rate and framing by listening (never transmits), and say "
      "what the line shows");
  cmd->add_option("port", args->port, "Serial port (e.g. /dev/ttyUSB0)")->required();
  cmd->add_flag("--quick", args->quick, "Try the common settings first and stop at a clear winner");
  cmd->add_option("--json", args->json_path, "Write the ranked table as JSON to FILE (- = stdout)");
  cmd->add_option("--dwell", args->dwell_s,
                  "Most seconds of listening per setting (default 2); a setting is left early once "
                  "8 bursts of traffic decide it")
      ->check(CLI::Range(0.05, 3600.0));
  cmd->add_option("--max-time", args->max_time_s,
                  "Seconds in all; a quiet bus is listened to this long (default 300)")
      ->check(CLI::Range(0.05, 86400.0));
  cmd->add_option("--rows", args->rows, "Rows of the table shown (default 12)");
  cmd->callback([args, &exit_code] {
    ProbeOptions options;
    options.port = args->port;
    options.quick = args->quick;
    options.candidates = probe_candidates(args->quick);
    options.dwell = static_cast<Nanos>(args->dwell_s * 1e9);
    options.max_time = static_cast<Nanos>(args->max_time_s * 1e9);
    fmt::print(stderr, "probe {}: listening at {} settings, {:.1f} s each, {:.0f} s at most\n",
               args->port, options.candidates.size(), args->dwell_s, args->max_time_s);
    const ProbeRun run = run_probe(
        options,
        [](const SettingEvidence& e) {
          fmt::print(stderr, "  {:<12} {} bytes, {} CRC-valid frames, {} line errors\n",
                     e.line.describe(), e.bytes, e.frames, e.line_errors());
        },
        [&options] {
          fmt::print(stderr,
                     "the bus is quiet: not a byte yet (traffic at any setting would show as "
                     "bytes or errors); listening on, up to {:.0f} s in all, rather than "
                     "guessing\n",
                     static_cast<double>(options.max_time) / 1e9);
        });
    for (const auto& note : run.notes) fmt::print(stderr, "note: {}\n", note);
    const ProbeVerdict verdict = judge_probe(run.table, run.quiet);
    fmt::print("{}", probe_text(run.table, verdict, args->rows));
    std::fflush(stdout);
    if (!args->json_path.empty()) write_json(args->json_path, probe_json(run.table, verdict));
    exit_code = verdict.winner ? 0 : kExitNothingFits;
  });
}

RTUSCOPE_REGISTER_COMMAND(setup_probe);

}  // namespace
}  // namespace rtu::app
