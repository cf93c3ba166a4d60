#include "progress.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <exception>

namespace parkslam::app {

Progress::Progress(std::string label, int total)
    : label_(std::move(label)),
      total_(std::max(total, 1)),
      tty_(isatty(STDERR_FILENO) != 0),
      uncaught_at_start_(std::uncaught_exceptions()),
      start_(std::chrono::steady_clock::now()) {
  if (tty_) Draw(0, false);
}

Progress::~Progress() {
  if (finished_) return;
  if (std::uncaught_exceptions() > uncaught_at_start_) {
    finished_ = true;
    if (tty_ && last_drawn_ >= 0) {
      std::fputc('\n', stderr);
      std::fflush(stderr);
    }
    return;
  }
  Finish();
}

void Progress::Update(int done) {
  // Redraw only when the bar moves: callers may update once per event.
  if (!tty_ || finished_ || done == last_drawn_) return;
  Draw(done, false);
}

void Progress::Finish() {
  if (finished_) return;
  finished_ = true;
  Draw(total_, true);
}

void Progress::Draw(int done, bool final_line) {
  last_drawn_ = done;
  constexpr int kWidth = 30;
  const int filled = kWidth * std::clamp(done, 0, total_) / total_;
  const double elapsed_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string bar(static_cast<size_t>(filled), '#');
  bar.append(static_cast<size_t>(kWidth - filled), '.');
  std::fprintf(stderr, "%s%-28s [%s] %3d%% %6.1f s%s", tty_ ? "\r" : "", label_.c_str(),
               bar.c_str(), 100 * std::clamp(done, 0, total_) / total_, elapsed_s,
               final_line ? "\n" : "");
  std::fflush(stderr);
}

}  // namespace parkslam::app
