#pragma once
// What a run owns in its output folder: the names softcut writes there, and
// the clean-up of an earlier run's files before a new run writes its own.
#include <filesystem>

namespace softcut::sim {

// Removes from `dir` the files softcut writes there and nothing else:
// displacements.csv(.partial), tools.csv(.partial), summary.json, series.pvd,
// contact_sheet.png, camera.json, video.mp4, render_record.bin(.partial),
// frames/{frame,depth,labels}_NNNNNN.png, vtu/frame_NNNNNN.vtu and the temporary files of
// their atomic writes; frames/ and vtu/ go when left empty. Links are
// unlinked, never followed. Returns the number of files removed.
int clear_earlier_outputs(const std::filesystem::path& dir);

// Removes from `dir` the private folders of videos being encoded
// (render::VideoEncoder: ".softcut-video-" and mkdtemp's six letters and
// digits) that a run killed while encoding left behind (SIGKILL: no
// destructor ran), each only when it holds nothing but its partial
// video.mp4 (a plain file); a link, or a folder holding anything else, is
// left alone. Call it before this run's own encoder starts (it would take
// that one's folder too). Returns how many were removed.
int remove_stale_video_folders(const std::filesystem::path& dir);

}  // namespace softcut::sim
