#include "interruption.h"

#include <signal.h>
#include <unistd.h>

#include <array>
#include <atomic>

namespace parkslam::app {
namespace {

constexpr std::array<int, 3> kSignals{SIGINT, SIGTERM, SIGHUP};
std::atomic<int> g_signal{0};
std::array<struct sigaction, kSignals.size()> g_previous{};

extern "C" void NoteSignal(int signal_number) {
  if (g_signal.exchange(signal_number) != 0) {
    // The second one: end now, as the default action would.
    ::signal(signal_number, SIG_DFL);
    ::raise(signal_number);
    return;
  }
  // write(2) is safe in a handler; a step may take a while to reach its end.
  static constexpr char kNote[] =
      "\nparkslam: stopping at the end of this step (a second signal stops at once)\n";
  [[maybe_unused]] const ssize_t written = ::write(STDERR_FILENO, kNote, sizeof(kNote) - 1);
}

}  // namespace

InterruptionScope::InterruptionScope() {
  g_signal.store(0);
  for (size_t k = 0; k < kSignals.size(); ++k) {
    struct sigaction action {};
    action.sa_handler = NoteSignal;
    ::sigemptyset(&action.sa_mask);
    ::sigaction(kSignals[k], &action, &g_previous[k]);
  }
}

InterruptionScope::~InterruptionScope() {
  for (size_t k = 0; k < kSignals.size(); ++k) ::sigaction(kSignals[k], &g_previous[k], nullptr);
}

void InterruptionScope::ThrowIfInterrupted(const std::string& what_stops) {
  const int signal_number = g_signal.load();
  if (signal_number == 0) return;
  throw Interrupted(signal_number,
                    "interrupted (signal " + std::to_string(signal_number) + "): " + what_stops);
}

}  // namespace parkslam::app
