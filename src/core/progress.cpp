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
    rate_ = rate_ > 0 ? 0.7 * rate_ + 0.3 * inst : inst;
    steps_at_last_ = s.steps;
    time_at_last_ = now;
  }
  const double fraction = s.end_time > 0 ? std::clamp(s.time / s.end_time, 0.0, 1.0) : 0.0;
  const double eta = fraction > 1e-6 ? now * (1.0 - fraction) / fraction : -1.0;
  constexpr int width = 28;
  const int filled = static_cast<int>(fraction * width);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(width, '.');
  const std::string line =
      fmt::format("[{}] {:3.0f}%  frame {}/{}  t={:.3f}/{:.3f} s  {:.0f} steps/s  ETA {}", bar, 100.0 * fraction,
                  s.frame, s.frames, s.time, s.end_time, rate_, format_duration(eta));
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
