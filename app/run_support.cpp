#include "app/run_support.hpp"

#include <time.h>

#include <csignal>
#include <cstdio>

#include "core/error.hpp"

namespace softcut::app {

void add_override(std::map<std::string, std::string>& overrides, const std::string& pair) {
  const auto eq = pair.find('=');
  if (eq == std::string::npos || eq == 0)
    usage_fail("--set ", pair, ": expected key=value (e.g. --set force=0.5)");
  overrides[pair.substr(0, eq)] = pair.substr(eq + 1);
}

backend::Backend parse_backend(const std::string& text) {
  try {
    return backend::parse_backend(text);
  } catch (const Error&) {
    usage_fail("--backend ", text, ": expected auto, cpu, gpu, direct or monolithic");
  }
}

int parse_count(const std::string& text, const char* option) {
  size_t used = 0;
  long v = -1;
  try {
    v = std::stol(text, &used);
  } catch (...) {
    used = 0;
  }
  if (used != text.size() || v < 0 || v > 100000000) usage_fail(option, " ", text, ": expected a whole number from 0 to 100000000");
  return int(v);
}

int parse_jobs(const std::string& text, const char* command) {
  const int jobs = parse_count(text, "-j");
  if (jobs < 1) usage_fail(command, ": -j needs at least 1");
  return jobs;
}

std::pair<int, int> parse_size(const std::string& text, const char* option) {
  const size_t x = text.find('x');
  auto side = [&](const std::string& t) {
    size_t used = 0;
    long v = -1;
    try {
      v = std::stol(t, &used);
    } catch (...) {
      used = 0;
    }
    if (t.empty() || used != t.size() || v < 1 || v > 16384)
      usage_fail(option, " ", text, ": expected WIDTHxHEIGHT in pixels, each from 1 to 16384 (e.g. 640x480)");
    return int(v);
  };
  if (x == std::string::npos) side("");
  return {side(text.substr(0, x)), side(text.substr(x + 1))};
}

namespace {
// The number at the start of `text` (std::stod), with *used its length; 0
// characters used when there is none.
double leading_number(const std::string& text, size_t* used) {
  try {
    return std::stod(text, used);
  } catch (...) {
    *used = 0;
    return -1;
  }
}
}  // namespace

double parse_seconds(const std::string& text, const char* option) {
  size_t used = 0;
  const double v = leading_number(text, &used);
  if (used != text.size() || !(v >= 0) || v > 1e7)
    usage_fail(option, " ", text, ": expected seconds from 0 (no limit) to 10000000");
  return v;
}

std::uint64_t parse_bytes(const std::string& text, const char* option) {
  size_t used = 0;
  const double v = leading_number(text, &used);
  double unit = 1;
  const std::string suffix = text.substr(used);
  if (suffix == "K" || suffix == "k") unit = 1 << 10;
  else if (suffix == "M") unit = 1 << 20;
  else if (suffix == "G") unit = double(1 << 30);
  else if (!suffix.empty()) used = 0;
  if (used == 0 || !(v >= 0) || v * unit > 1e18)
    usage_fail(option, " ", text, ": expected a number of bytes (0: no limit), optionally with K, M or G (e.g. 8G)");
  return std::uint64_t(v * unit);
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
    if (now - g_first_signal_ns.load() < 1000000000LL) return;
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
