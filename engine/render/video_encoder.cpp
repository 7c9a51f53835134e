#include "render/video_encoder.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/error.hpp"

extern char** environ;

namespace softcut::render {

namespace fs = std::filesystem;

namespace {

bool executable(const fs::path& p) {
  struct stat st {};
  return ::stat(p.c_str(), &st) == 0 && S_ISREG(st.st_mode) && ::access(p.c_str(), X_OK) == 0;
}

// Writes all of `bytes` to the pipe. SIGPIPE is blocked on this thread
// while it writes (ffmpeg may have exited), so a dead reader is an EPIPE
// error here, not the end of the process; a SIGPIPE raised meanwhile is
// taken before the mask is restored.
bool write_all(int fd, const std::uint8_t* bytes, std::size_t n) {
  sigset_t pipe_set, old;
  sigemptyset(&pipe_set);
  sigaddset(&pipe_set, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_set, &old);
  bool ok = true;
  while (n > 0) {
    const ssize_t w = ::write(fd, bytes, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      ok = false;
      break;
    }
    bytes += w, n -= std::size_t(w);
  }
  if (!ok) {
    const timespec zero{0, 0};
    while (sigtimedwait(&pipe_set, nullptr, &zero) > 0) {
    }
  }
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
  return ok;
}

std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

}  // namespace

fs::path find_ffmpeg() {
  if (const char* env = std::getenv("SOFTCUT_FFMPEG"); env && *env) return executable(env) ? fs::path(env) : fs::path();
  const char* path = std::getenv("PATH");
  std::string dirs = path ? path : "/usr/bin:/bin";
  std::size_t at = 0;
  while (at <= dirs.size()) {
    const std::size_t end = std::min(dirs.find(':', at), dirs.size());
    const fs::path candidate = fs::path(dirs.substr(at, end - at).empty() ? "." : dirs.substr(at, end - at)) / "ffmpeg";
    if (executable(candidate)) return candidate;
    at = end + 1;
  }
  return {};
}

VideoEncoder::VideoEncoder(fs::path path, int width, int height, double fps)
    : path_(std::move(path)), width_(width), height_(height) {
  if (width < 1 || height < 1 || !(fps > 0) || fps > 1000)
    fail("video ", path_.string(), ": ", width, " x ", height, " frames at ", fps, " frames per second");
  const fs::path ffmpeg = find_ffmpeg();
  if (ffmpeg.empty())
    fail("video ", path_.string(), ": the ffmpeg program is not installed (or not on PATH); install it with "
         "`sudo apt-get install ffmpeg` (Debian/Ubuntu; ./scripts/install-deps.sh --video does it), or run without "
         "--video");
  // ffmpeg writes into a fresh private folder beside the video (mkdtemp:
  // nothing can be planted under the name it opens), renamed into place by
  // finish().
  std::string tmpdir = (path_.parent_path() / ".softcut-video-XXXXXX").string();
  if (!::mkdtemp(tmpdir.data()))
    fail("video ", path_.string(), ": cannot make a temporary folder beside it (", std::strerror(errno), ")");
  tmpdir_ = tmpdir;
  tmp_ = tmpdir_ / path_.filename();
  stderr_ = ::memfd_create("softcut-ffmpeg-stderr", MFD_CLOEXEC);
  int fds[2] = {-1, -1};
  if (stderr_ < 0 || ::pipe2(fds, O_CLOEXEC) != 0) {
    const int err = errno;
    if (stderr_ >= 0) ::close(stderr_), stderr_ = -1;
    remove_tmp();
    fail("video ", path_.string(), ": cannot start ffmpeg (", std::strerror(err), ")");
  }
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  std::vector<std::string> args = {
      ffmpeg.string(), "-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo", "-pix_fmt", "rgba",
      "-video_size", size, "-framerate", number(fps), "-i", "pipe:0", "-an",
      // yuv420p (what every player decodes) needs an even width and height.
      "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264", "-preset", "veryfast", "-crf", "18",
      "-pix_fmt", "yuv420p", "-movflags", "+faststart", "-f", "mp4", tmp_.string()};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[0], STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&actions, stderr_, STDERR_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  // The child starts with default signal handling: a Ctrl-C of the run
  // reaches it through the process group and the run's own handler decides.
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t none, all;
  sigemptyset(&none);
  sigfillset(&all);
  posix_spawnattr_setsigmask(&attr, &none);
  posix_spawnattr_setsigdefault(&attr, &all);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, ffmpeg.c_str(), &actions, &attr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  ::close(fds[0]);
  if (rc != 0) {
    ::close(fds[1]);
    ::close(stderr_), stderr_ = -1;
    remove_tmp();
    fail("video ", path_.string(), ": cannot start ", ffmpeg.string(), " (", std::strerror(rc), ")");
  }
  pid_ = pid;
  pipe_ = fds[1];
}

VideoEncoder::~VideoEncoder() {
  if (!finished_) stop();
  remove_tmp();
  if (stderr_ >= 0) ::close(stderr_);
}

void VideoEncoder::stop() {
  if (pipe_ >= 0) ::close(pipe_), pipe_ = -1;
  if (pid_ > 0) {
    ::kill(pid_, SIGKILL);
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
  }
  remove_tmp();
}

void VideoEncoder::remove_tmp() {
  std::error_code ec;
  if (!tmpdir_.empty()) fs::remove_all(tmpdir_, ec);
  tmpdir_.clear();
}

std::string VideoEncoder::ffmpeg_says() {
  if (stderr_ < 0) return "";
  const off_t size = ::lseek(stderr_, 0, SEEK_END);
  const off_t from = size > 2000 ? size - 2000 : 0;
  std::string text(std::size_t(size - from), '\0');
  const ssize_t got = ::pread(stderr_, text.data(), text.size(), from);
  text.resize(got > 0 ? std::size_t(got) : 0);
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  return text.empty() ? "no message" : text;
}

void VideoEncoder::add(const Image& frame) {
  if (finished_ || pipe_ < 0) fail("video ", path_.string(), ": a frame after the video was finished");
  if (frame.width != width_ || frame.height != height_)
    fail("video ", path_.string(), ": a ", frame.width, " x ", frame.height, " frame in a ", width_, " x ", height_,
         " video");
  if (!write_all(pipe_, frame.rgba.data(), frame.rgba.size())) {
    ::close(pipe_), pipe_ = -1;
    int status = 0;
    while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    pid_ = -1;
    fail("video ", path_.string(), ": ffmpeg stopped after ", frames_, " frames: ", ffmpeg_says());
  }
  ++frames_;
}

std::uintmax_t VideoEncoder::finish() {
  if (finished_ || pid_ < 0) fail("video ", path_.string(), ": finished twice, or after ffmpeg stopped");
  finished_ = true;
  ::close(pipe_), pipe_ = -1;
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  pid_ = -1;
  std::error_code ec;
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    remove_tmp();
    fail("video ", path_.string(), ": ffmpeg failed (", WIFEXITED(status) ? "exit status " : "signal ",
         WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status), "): ", ffmpeg_says());
  }
  fs::rename(tmp_, path_, ec);
  const std::string why = ec ? ec.message() : "";
  remove_tmp();
  if (!why.empty()) fail("video ", path_.string(), ": cannot rename the encoded file into place: ", why);
  return fs::file_size(path_, ec);
}

}  // namespace softcut::render
