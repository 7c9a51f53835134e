#pragma once
// Rendered frames to an H.264 video through the `ffmpeg` program (Debian's
// ffmpeg package): raw RGBA frames are piped to its standard input and it
// encodes them on its own threads, in its own process. The file is written
// in a private temporary folder beside it and renamed into place by finish(),
// so a reader never sees half a video.
#include <cstdint>
#include <filesystem>
#include <string>

#include "render/image.hpp"

namespace softcut::render {

// The ffmpeg program on PATH (or $SOFTCUT_FFMPEG); empty when there is none.
std::filesystem::path find_ffmpeg();

class VideoEncoder {
 public:
  // Starts ffmpeg encoding `width` x `height` RGBA frames at `fps` frames per
  // second into `path` (H.264, yuv420p, MP4; an odd width or height is padded
  // by one black row or column). Throws softcut::Error when ffmpeg is not
  // installed (saying how to install it) or does not start.
  VideoEncoder(std::filesystem::path path, int width, int height, double fps);
  // Without finish(): stops ffmpeg and removes the temporary file.
  ~VideoEncoder();
  VideoEncoder(const VideoEncoder&) = delete;
  VideoEncoder& operator=(const VideoEncoder&) = delete;

  // Hands one frame to ffmpeg (blocks while its pipe is full). Throws naming
  // the video and quoting ffmpeg when it has stopped, or when the frame's
  // size differs from the video's.
  void add(const Image& frame);
  // Ends the stream, waits for ffmpeg and renames the file into place;
  // returns its bytes. Throws quoting ffmpeg when it failed.
  std::uintmax_t finish();

  int frames() const { return frames_; }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::string ffmpeg_says();  // the tail of what ffmpeg wrote to its stderr
  void stop();
  void remove_tmp();

  std::filesystem::path path_, tmpdir_, tmp_;
  int width_, height_;
  int frames_ = 0;
  int pipe_ = -1;    // ffmpeg's stdin
  int stderr_ = -1;  // a memfd holding its stderr
  int pid_ = -1;
  bool finished_ = false;
};

}  // namespace softcut::render
