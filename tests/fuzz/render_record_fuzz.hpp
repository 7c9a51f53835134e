#pragma once
// How the render_record fuzz target (and its regression replay) reads an
// input: the whole of `softcut render`'s path without GL, from the bytes to
// each frame's extracted scene.
#include <string_view>

#include "render/scene.hpp"
#include "sim/frame_scene.hpp"
#include "sim/render_record.hpp"
#include "sim/render_record_meta.hpp"

namespace softcut::fuzz {

// Bounds as `softcut render` has them, smaller: what a fuzzer's input can
// make the reader allocate stays within a few hundred MiB.
inline void read_render_record(std::string_view bytes) {
  sim::RecordLimits limits;
  limits.max_nodes = 200'000;
  limits.max_tets = 200'000;
  limits.max_chunk_bytes = std::uint64_t(64) << 20;
  sim::RenderRecordReader reader(bytes, "fuzz.bin", limits);
  sim::RecordMeta meta = sim::parse_record_meta(reader.meta(), "fuzz.bin");
  meta.render.width = meta.render.height = 16;  // extraction checks the size; no pixels are drawn
  sim::RecordFrame f;
  Eigen::MatrixX3d x;
  render::SceneContent c;
  render::SceneExtractor extractor;
  while (reader.next(f)) {
    const sim::RecordTopology& topo = reader.topology(f.topology);
    sim::scene_inputs(topo, f, x, c);
    extractor.extract(topo.mesh, x, c, sim::render_settings(meta.render, meta.palette, f.camera));
  }
}

}  // namespace softcut::fuzz
