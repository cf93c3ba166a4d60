#ifndef PARKSLAM_APPS_INTERRUPTION_H_
#define PARKSLAM_APPS_INTERRUPTION_H_

#include <stdexcept>
#include <string>

namespace parkslam::app {

// A command stopped by SIGINT, SIGTERM or SIGHUP between two of its steps;
// main() exits with 128 + the signal's number, as a shell expects.
class Interrupted : public std::runtime_error {
 public:
  Interrupted(int signal_number, const std::string& what)
      : std::runtime_error(what), signal_number_(signal_number) {}
  int signal_number() const { return signal_number_; }

 private:
  int signal_number_;
};

// While one lives, SIGINT, SIGTERM and SIGHUP only note the signal, so that
// a command filling a staging folder (import-rosbag) stops at its next step
// and removes what it wrote as the exception unwinds; a second signal ends
// the process at once. The handlers before it come back when it ends.
class InterruptionScope {
 public:
  InterruptionScope();
  ~InterruptionScope();
  InterruptionScope(const InterruptionScope&) = delete;
  InterruptionScope& operator=(const InterruptionScope&) = delete;

  // Throws Interrupted, saying `what_stops`, once a signal has come.
  static void ThrowIfInterrupted(const std::string& what_stops);
};

}  // namespace parkslam::app

#endif  // PARKSLAM_APPS_INTERRUPTION_H_
