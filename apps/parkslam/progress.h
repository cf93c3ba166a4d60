#ifndef PARKSLAM_APPS_PROGRESS_H_
#define PARKSLAM_APPS_PROGRESS_H_

#include <chrono>
#include <string>

namespace parkslam::app {

// A one-line progress bar on stderr. On a terminal it redraws in place; when
// stderr is a file or pipe it prints only the finished line, so logs stay
// clean. Left by an exception (the work failed), it never claims to have
// finished: on a terminal the bar stays where it stopped and the line ends,
// so that the error starts a line of its own; in a log nothing is printed.
class Progress {
 public:
  Progress(std::string label, int total);
  ~Progress();
  void Update(int done);
  void Finish();

 private:
  void Draw(int done, bool final_line);

  std::string label_;
  int total_;
  bool tty_;
  bool finished_ = false;
  int last_drawn_ = -1;
  int uncaught_at_start_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace parkslam::app

#endif  // PARKSLAM_APPS_PROGRESS_H_
