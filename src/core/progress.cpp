#include "core/progress.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace bakesim {

std::string format_duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "--:--";
  const long s = std::lround(seconds);
  if (s >= 3600) return fmt::format("{}:{:02}:{:02}", s / 3600, (s / 60) % 60, s % 60);
  return fmt::format("{}:{:02}", s / 60, s % 60);
}

ProgressBar::ProgressBar(std::FILE* stream, bool enabled)
    : stream_(stream), enabled_(enabled && stream != nullptr), tty_(false) {
  if (enabled_) tty_ = isatty(fileno(stream_)) != 0;
}

void ProgressBar::update(const ProgressState& s, bool force) {
  if (!enabled_) return;
  const double now = clock_.seconds();
  const double interval = tty_ ? 0.2 : 5.0;
  if (!force && now - last_draw_ < interval) return;
  const double dt_wall = now - time_at_last_;
  if (dt_wall > 0.05) {
    const double inst = double(s.steps - steps_at_last_) / dt_wall;
    const double sim_inst = (s.time - sim_at_last_) / dt_wall;
    rate_ = rate_ > 0 ? 0.7 * rate_ + 0.3 * inst : inst;
    sim_rate_ = sim_rate_ > 0 ? 0.7 * sim_rate_ + 0.3 * sim_inst : sim_inst;
    steps_at_last_ = s.steps;
    sim_at_last_ = s.time;
    time_at_last_ = now;
  }
  const double fraction = s.end_time > 0 ? std::clamp(s.time / s.end_time, 0.0, 1.0) : 0.0;
  // From the recent rate of simulated time, not the average since the start:
  // the step shrinks as dough sets, so the average promised too little.
  const double eta = sim_rate_ > 0 ? (s.end_time - s.time) / sim_rate_ : -1.0;
  constexpr int width = 28;
  const int filled = static_cast<int>(fraction * width);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(width, '.');
  const std::string clock =
      s.bake_time_scale > 0
          ? fmt::format("bake {:.1f}/{:.1f} min", s.time * s.bake_time_scale / 60, s.end_time * s.bake_time_scale / 60)
          : fmt::format("t={:.3f}/{:.3f} s", s.time, s.end_time);
  const std::string line =
      fmt::format("[{}] {:3.0f}%  {}{}{}  frame {}/{}  {:.0f} steps/s  ETA {}", bar, 100.0 * fraction, clock,
                  note_.empty() ? "" : "  ", note_, s.frame, s.frames, rate_, format_duration(eta));
  if (tty_)
    std::fprintf(stream_, "\r%s\033[K", line.c_str());
  else
    std::fprintf(stream_, "%s\n", line.c_str());
  std::fflush(stream_);
  last_draw_ = now;
  drawn_ = true;
}

void ProgressBar::finish() {
  if (enabled_ && tty_ && drawn_) {
    std::fprintf(stream_, "\n");
    std::fflush(stream_);
  }
}

}  // namespace bakesim
