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

}  // namespace softcut::sim
