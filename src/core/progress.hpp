#pragma once
// Progress bar for long runs, drawn on a stream (stderr from the command line).
// On a terminal it redraws one line; otherwise it prints a line every few
// seconds so logs of batch runs still show progress.
#include <cstdio>
#include <string>

#include "core/timers.hpp"

namespace bakesim {

struct ProgressState {
  int frame = 0;
  int frames = 0;
  double time = 0.0;
  double end_time = 0.0;
  long steps = 0;
  // Bake seconds per simulated second; > 0 shows the bake clock (minutes of
  // oven) instead of the mechanics clock.
  double bake_time_scale = 0.0;
};

class ProgressBar {
 public:
  ProgressBar(std::FILE* stream, bool enabled);
  void update(const ProgressState& s, bool force = false);
  // Text shown after the clock until replaced (e.g. "core 87.3 degC").
  void set_note(std::string note) { note_ = std::move(note); }
  void finish();

 private:
  std::FILE* stream_;
  bool enabled_;
  bool tty_;
  Stopwatch clock_;
  double last_draw_ = -1e9;
  long steps_at_last_ = 0;
  double time_at_last_ = 0.0;
  double rate_ = 0.0;      // steps per wall second, smoothed
  double sim_rate_ = 0.0;  // simulated seconds per wall second, smoothed (the ETA)
  double sim_at_last_ = 0.0;
  std::string note_;
  bool drawn_ = false;
};

std::string format_duration(double seconds);

}  // namespace bakesim
