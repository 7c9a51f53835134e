#include "app/run_support.hpp"

#include <time.h>

#include <csignal>
#include <cstdio>

#include "core/error.hpp"

namespace softcut::app {

std::string warned_message(const std::vector<std::string>& warnings) {
  return cat(warnings.size(), warnings.size() == 1 ? " warning" : " warnings",
             " with --warnings-as-errors: ", warnings.empty() ? std::string() : warnings.front());
}

void add_override(std::map<std::string, std::string>& overrides, const std::string& pair) {
  const auto eq = pair.find('=');
  if (eq == std::string::npos || eq == 0)
    usage_fail("--set ", pair, ": expected key=value (e.g. --set force=0.5)");
  overrides[pair.substr(0, eq)] = pair.substr(eq + 1);
}

void Progress::update(int frame, int num_frames, double elapsed_s) {
  if (mode_ == Mode::quiet || num_frames <= 0) return;
  const int done = frame + 1;
  const double eta = done > 0 ? elapsed_s * (num_frames - done) / done : 0.0;
  if (mode_ == Mode::bar) {
    if (done < num_frames && last_draw_s_ >= 0 && elapsed_s - last_draw_s_ < 0.1) return;
    last_draw_s_ = elapsed_s;
    constexpr int kWidth = 30;
    const int fill = int(double(kWidth) * done / num_frames);
    std::fprintf(stderr, "\r[%.*s%*s] %d/%d frames  %.1f s  ETA %.1f s ", fill,
                 "##############################", kWidth - fill, "", done, num_frames, elapsed_s, eta);
    std::fflush(stderr);
    drawn_ = true;
  } else {
    const int decile = 10 * done / num_frames;
    if (decile != last_decile_) {
      last_decile_ = decile;
      std::fprintf(stderr, "frame %d/%d (%d%%), %.1f s elapsed, ETA %.1f s\n", done, num_frames,
                   100 * done / num_frames, elapsed_s, eta);
    }
  }
}

void Progress::done() {
  if (drawn_) std::fputc('\n', stderr);
  drawn_ = false;
}

namespace {
struct sigaction g_old_int, g_old_term;
std::atomic<long long> g_first_signal_ns{0};
// First signal: finish the frame and stop cleanly. Second: the default action
// (e.g. a script stuck in Lua under --trust), unless it comes within a second
// of the first: the same stop delivered twice (a scheduler signals every
// process of a job, and `softcut sweep` passes the stop on to its runs too).
extern "C" void on_signal(int sig) {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);  // async-signal-safe
  const long long now = ts.tv_sec * 1000000000LL + ts.tv_nsec;
  if (SignalGuard::flag().exchange(true)) {
    // 0: the first copy, on another thread, has not stored its time yet.
    const long long first = g_first_signal_ns.load();
    if (first == 0 || now - first < 1000000000LL) return;
    std::signal(sig, SIG_DFL);
    std::raise(sig);
  }
  g_first_signal_ns.store(now);
}
}  // namespace

std::atomic<bool>& SignalGuard::flag() {
  static std::atomic<bool> f{false};
  return f;
}

SignalGuard::SignalGuard() {
  flag().store(false);
  g_first_signal_ns.store(0);
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &g_old_int);
  sigaction(SIGTERM, &sa, &g_old_term);
}

SignalGuard::~SignalGuard() {
  sigaction(SIGINT, &g_old_int, nullptr);
  sigaction(SIGTERM, &g_old_term, nullptr);
}

}  // namespace softcut::app
