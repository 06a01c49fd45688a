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
};

class ProgressBar {
 public:
  ProgressBar(std::FILE* stream, bool enabled);
  void update(const ProgressState& s, bool force = false);
  void finish();

 private:
  std::FILE* stream_;
  bool enabled_;
  bool tty_;
  Stopwatch clock_;
  double last_draw_ = -1e9;
  long steps_at_last_ = 0;
  double time_at_last_ = 0.0;
  double rate_ = 0.0;
  bool drawn_ = false;
};

std::string format_duration(double seconds);

}  // namespace bakesim
