#pragma once
// The compact per-frame record a run keeps for `softcut render`
// (render_record.bin, docs/outputs.md): what each rendered frame's scene was
// made of, so that a finished run is redrawn from another camera, size or
// style without simulating it again, frame for frame identical when nothing
// is changed. It holds the current mesh's topology (rest nodes, tets, region,
// cut faces, tissue groups) each time it changes (a cut), and per frame the
// positions of the nodes the frame shows (surface, tissue-group boundaries,
// interface and manipulated nodes), the tool shapes, markers and the camera.
//
// File: "softcut-render-record" magic, a version, then chunks (kind byte,
// compressed and raw sizes, zlib data, CRC-32 of the raw data): one meta
// chunk (JSON), topology and frame chunks in order, an end chunk with the
// frame count. Written while the run goes on into render_record.bin.partial
// and renamed at its end, like displacements.csv. The reader takes the file
// as untrusted: every count and size is checked against its limits and the
// bytes left before anything is allocated or inflated.
#include <Eigen/Core>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/json_text.hpp"
#include "mesh/tet_mesh.hpp"
#include "render/scene.hpp"

namespace softcut {
class OutputBudget;
}

namespace softcut::sim {

inline constexpr const char* kRenderRecordFile = "render_record.bin";
// The topology part of a frame's scene.
struct RecordTopology {
  mesh::TetMesh mesh;               // rest nodes (m) and tets; labels unused
  std::vector<char> operational;    // (ntet) nonzero: operational
  std::vector<char> cut_faces;      // (4 ntet), or empty: no cut
  std::vector<int> tet_group;       // (ntet) tissue group, or empty
  std::vector<std::uint32_t> group_labels;  // label id per tissue group
  std::uint32_t cut_label = 0;              // label id of cut faces
  std::vector<int> interface_nodes;  // node ids
  std::vector<int> shown_nodes;     // sorted ids whose positions each frame holds
};

struct RecordFrame {
  int frame = 0;
  double time = 0;                  // s
  int topology = 0;                 // index into the topologies read so far
  Eigen::MatrixX3d positions;       // (shown_nodes x 3) deformed positions, m
  std::vector<int> extra_nodes;     // manipulated nodes outside shown_nodes ...
  Eigen::MatrixX3d extra_positions; // ... and their positions, m
  render::SceneContent content;     // manipulated, arrows, tools, tool_labels (the topology's fields empty)
  render::CameraSettings camera;    // as the frame resolved it
};

// The inputs of extract_scene for a frame: the mesh (rest nodes, tets),
// positions (every node; those the frame does not show at rest) and content.
void scene_inputs(const RecordTopology& topo, const RecordFrame& f, Eigen::MatrixX3d& positions,
                  render::SceneContent& content);

class RenderRecordWriter {
 public:
  // Creates <dir>/render_record.bin.partial (new, never through a link) and
  // writes the magic and the meta chunk. `budget` (optional) bounds the bytes.
  RenderRecordWriter(const std::filesystem::path& dir, const Json& meta, OutputBudget* budget = nullptr);
  ~RenderRecordWriter();  // removes the partial file when finish() was not called
  RenderRecordWriter(const RenderRecordWriter&) = delete;
  RenderRecordWriter& operator=(const RenderRecordWriter&) = delete;

  // One rendered frame: the scene's inputs (mesh: current rest nodes and
  // tets; positions: nnode x 3; content: as given to extract_scene) and the
  // camera it used. A topology chunk is written first when the mesh or its
  // flags changed since the last frame.
  void add(int frame, double time, const mesh::TetMesh& mesh, const Eigen::MatrixX3d& positions,
           const render::SceneContent& content, const render::CameraSettings& camera);
  // The end chunk; renames the file into place.
  void finish();
  std::uint64_t bytes() const { return bytes_; }

 private:
  void chunk(char kind, const std::string& raw);

  std::filesystem::path dir_, tmp_;
  std::FILE* file_ = nullptr;
  OutputBudget* budget_ = nullptr;
  std::uint64_t bytes_ = 0;
  int frames_ = 0, topologies_ = 0;
  RecordTopology last_;  // the topology written last (its shown nodes with it)
  bool finished_ = false;
};

// Bounds on what a record may make the reader allocate.
struct RecordLimits {
  std::uint64_t max_tets = 2'000'000;       // per topology (the sandbox's mesh bound)
  std::uint64_t max_nodes = 8'000'000;      // per topology
  std::uint64_t max_frames = 10'000'000;
  std::uint64_t max_items = 100'000;        // tools, markers, arrows, extra nodes per frame
  std::uint64_t max_chunk_bytes = std::uint64_t(1) << 30;  // one chunk, inflated
};

class RenderRecordReader {
 public:
  // Parses the magic and the meta chunk of a whole file's bytes (which must
  // outlive the reader); `what` names it in errors. Throws softcut::Error
  // naming the file, the chunk and what is wrong.
  RenderRecordReader(std::string_view bytes, std::string what, RecordLimits limits = {});

  const Json& meta() const { return meta_; }
  // The next frame (and any topology chunk before it) into `f`; false at the
  // end chunk (whose frame count is checked). The topology a frame refers to
  // is topology(f.topology).
  bool next(RecordFrame& f);
  const RecordTopology& topology(int i) const;
  int frames_read() const { return frames_; }

 private:
  std::string read_chunk(char& kind);
  [[noreturn]] void bad(const std::string& why) const;

  std::string_view bytes_;
  std::string what_;
  RecordLimits limits_;
  std::size_t at_ = 0;
  int chunk_ = 0, frames_ = 0;
  Json meta_;
  std::vector<RecordTopology> topologies_;
  bool ended_ = false;
};

}  // namespace softcut::sim
