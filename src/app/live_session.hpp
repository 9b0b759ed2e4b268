#pragma once
// One live session, as `rtuscope live` and `rtuscope demo` run it: frames decoded once by a
// device stage, written as they come, optionally recorded and reported on; SIGINT/SIGTERM
// end it. The commands differ only in what they hook in (the demo plays traffic onto the
// bus it listens to, and ends when that traffic is over).
#include <functional>
#include <string>
#include <vector>

#include "app/device_options.hpp"
#include "pipeline/live_capture.hpp"
#include "pipeline/pcapng_recorder.hpp"

namespace rtu::app {

struct LiveSessionSetup {
  LiveOptions capture;
  std::string format = "text";  // of the frames: "text" or "jsonl"
  std::string output = "-";     // where the frames go
  std::string record_path;      // pcapng recording ("" = none)
  RotationPolicy rotation;
  std::string report_path;    // traffic report file ("" = none)
  std::string report_format;  // "" = from report_path's name
  // Gather the report's statistics and list its findings even without a report file.
  bool always_report = false;
  std::string prefix = "rtuscope";  // of every message on stderr
  // Set: the frames go to this sink instead of being written to `output` (a pipe to
  // Wireshark). Not owned.
  RecordSink* frames_sink = nullptr;
  // Set: every read goes to this recorder instead of a file at record_path. Not owned.
  ChunkRecorder* chunk_recorder = nullptr;
  // Also get every record, after the frames are written, with the device points' values
  // (e.g. the MQTT feed). Not owned.
  std::vector<RecordSink*> extra_sinks;
  std::string bus_name;         // labels metrics ("" = the first port's file name)
  std::string metrics_address;  // serve Prometheus metrics here ("" = nowhere)
  std::string events_path;      // JSON-lines events ("" = none, "-" = stdout)
  Nanos summary_every = 0;      // health summaries (0 = none)
  // A recording that cannot be written (a full disk) ends the run with exit status 1,
  // instead of stopping the recording while decoding goes on.
  bool stop_on_write_error = false;
};

// What a command adds to the session. Every hook may be left empty.
struct LiveSessionHooks {
  // The capture's ports are open and it is reading.
  std::function<void(const LiveCapture& capture)> on_listening;
  // Asked every 20 ms while it runs: true ends the session (as a stop would).
  std::function<bool()> finished;
  // Called every 20 ms while it runs, on the capture's thread (e.g. to hand queued
  // messages on).
  std::function<void()> periodic;
  // A one-line message for the user (a port note, an unplugged adapter). Empty: printed on
  // stderr after the prefix.
  std::function<void(const std::string& message)> on_note;
  // SIGINT or SIGTERM came. Empty: the session ends.
  std::function<void()> on_signal;
  // The capture stopped and the frames were flushed: say what the run did. The recorder is
  // null when nothing was recorded. The report, if any, comes after.
  std::function<void(const LiveSummary& summary, const PcapngRecorder* recorder)> on_stopped;
};

// Runs the session until it stops: throws InputError (a bad output or report path, a map
// error) or SerialOpenError (a port that cannot be opened) before any frame. When the frames'
// output cannot be written (or, with stop_on_write_error, the recording), the session stops
// as on Ctrl-C, finishes the recording, summary and report, then throws OutputError.
void run_live_session(const LiveSessionSetup& setup, DeviceSetup& devices,
                      const LiveSessionHooks& hooks);

}  // namespace rtu::app
