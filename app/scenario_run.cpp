#include "app/scenario_run.hpp"

#include <algorithm>
#include <memory>
#include <unordered_set>

#include "app/reference_log.hpp"
#include "core/checked_file.hpp"
#include "core/error.hpp"
#include "core/output_budget.hpp"
#include "core/stop_flags.hpp"
#include "core/watchdog.hpp"
#include "gl/egl_context.hpp"
#include "render/video_encoder.hpp"
#include "render/frame_writer.hpp"
#include "scenario_script.hpp"  // lua/: the Lua implementation of sim::ScenarioScript
#include "sim/model.hpp"
#include "sim/outputs.hpp"

namespace fs = std::filesystem;

namespace softcut::app {

namespace {

std::string first_line(const std::string& s) { return s.substr(0, s.find('\n')); }

// The output folder from the final spec, made and resolved once: `--out DIR`
// as the user gave it, else renders/<name>/ with the name checked (after the
// script has run: a script may change s.name at any time) and the folder made
// below renders/ without following a link there.
fs::path make_output_folder(const RunRequest& req, const std::string& name) {
  fs::path dir;
  if (!req.out_dir.empty()) {
    std::error_code ec;
    fs::create_directories(req.out_dir, ec);
    if (ec || !fs::is_directory(req.out_dir))
      fail(req.out_dir.string(), ": cannot create the output folder (", ec ? ec.message() : "not a folder",
           "); choose another with --out or fix the path");
    dir = req.out_dir;
  } else {
    sim::check_scenario_name(name);
    const fs::path root = fs::absolute("renders");
    std::error_code ec;
    fs::create_directories(root, ec);
    if (ec) fail(root.string(), ": cannot create the output root (", ec.message(), "); choose a folder with --out");
    dir = make_folder_below(root, name, "output folder");
  }
  return fs::canonical(dir);
}

// Frame buffers of a rendered frame, bytes: colour and depth per sample,
// the resolved and read-back images and the PNG encoder's copy.
double render_bytes(const sim::RenderSettings& r) {
  const double pixels = double(r.width) * double(r.height);
  const double aux = r.depth || r.labels ? pixels * (4.0 + 1.0 + 4.0) * 2.0 : 0.0;  // label pass targets, read-backs
  return pixels * 8.0 * std::max(1, r.msaa_samples) + pixels * 4.0 * 3.0 + aux;
}

// The command line's choices over the script's: what it renders and how
// large, the backend, the precompute cache, the limits the summary records.
void apply_request(const RunRequest& req, sim::ScenarioSpec& spec) {
  spec.command_line = req.command_line;
  spec.outputs.timeout_s = std::max(0.0, req.timeout_s);
  spec.outputs.max_bytes = req.max_output;
  if (req.render_every > 0) spec.outputs.render.enabled = true, spec.outputs.render.every = req.render_every;
  if (req.width > 0) spec.outputs.render.width = req.width;
  if (req.height > 0) spec.outputs.render.height = req.height;
  if (req.msaa_samples >= 0) spec.outputs.render.msaa_samples = req.msaa_samples;
  sim::RenderSettings& rs = spec.outputs.render;
  if (req.depth) rs.depth = rs.enabled = true;
  if (req.labels) rs.labels = rs.enabled = true;
  if (req.video) rs.video = rs.enabled = true;
  if (req.record) rs.record = *req.record ? sim::RenderSettings::Record::on : sim::RenderSettings::Record::off;
  if (!req.render) rs.enabled = false;
  if (req.backend) spec.solver.backend = *req.backend;
  spec.solver.cache_dir = req.cache_dir;
  if (!req.trusted) {
    // What the scenario's numbers make the engine allocate counts against
    // the sandbox's memory budget too, checked before it is allocated.
    spec.solver.max_bytes = double(req.memory_budget);
    const sim::RenderSettings& r = spec.outputs.render;
    if (r.enabled && render_bytes(r) > double(req.memory_budget))
      fail(req.scenario.string(), ": rendering ", r.width, " x ", r.height, " frames with ", r.msaa_samples,
           " MSAA samples needs about ", int(render_bytes(r) / (1 << 20)), " MiB of frame buffers, more than the ",
           req.memory_budget >> 20, " MiB memory budget of the sandbox; render smaller (--size WxH), with fewer "
           "samples (--msaa N), or run with --trust");
  }
}

// Expectation outcomes, from the engine (never from anything the script
// could forge), listed in the order they were checked (time, then
// declaration), those not reached last; summary.json keeps the declaration
// order.
std::vector<ExpectationResult> expectation_results(const sim::Model& model, const sim::State& state) {
  std::vector<size_t> order;
  for (size_t i = 0; i < model.spec.expectations.size() && i < state.expectations.size(); ++i) order.push_back(i);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const sim::ExpectationOutcome &x = state.expectations[a], &y = state.expectations[b];
    return x.reached != y.reached ? x.reached : x.reached && x.time < y.time;
  });
  std::vector<ExpectationResult> results;
  for (size_t i : order) {
    const sim::ExpectationSpec& e = model.spec.expectations[i];
    const sim::ExpectationOutcome& o = state.expectations[i];
    results.push_back(ExpectationResult{e.name, e.where, o.reached, o.ok, o.message});
  }
  return results;
}

RunOutcome run_watched(const RunRequest& req, const OpenScript& open, const Watchdog& dog) {
  // The run owns --out from its start: a script that fails before the
  // outputs are written must not leave the last run's summary there, where
  // it would read as this run's.
  std::error_code ec;
  // And a killed run's video folder goes (before this run's encoder starts).
  if (!req.out_dir.empty() && fs::is_directory(req.out_dir, ec)) {
    sim::clear_earlier_outputs(req.out_dir);
    sim::remove_stale_video_folders(req.out_dir);
  }
  OutputBudget output(req.max_output);
  const std::unique_ptr<sim::ScenarioScript> script = open(req, &output, &dog);
  sim::ScenarioSpec spec = script->spec();
  RunOutcome out;
  out.name = spec.name;
  out.tolerance = spec.reference_tolerance;
  {
    const std::string file = req.scenario.string();
    try {
      sim::check_spec(spec);  // before anything is made from it (compile checks again)
      out.out_dir = make_output_folder(req, spec.name);
    } catch (const Error& e) {
      const std::string msg = e.what();
      if (msg.rfind(file, 0) == 0) throw;
      fail(file, ": ", msg);
    }
  }
  script->confine_writes(out.out_dir);
  spec.outputs.dir = out.out_dir;
  apply_request(req, spec);

  // One EGL context for the GPU backend and rendering, made here (the engine
  // never creates one) and outliving the Model and the renderer.
  std::unique_ptr<gl::EglContext> context;
  if (sim::wants_gpu_context(spec)) {
    const bool required = spec.solver.backend == backend::Backend::gpu || spec.outputs.render.enabled;
    try {
      context = std::make_unique<gl::EglContext>();
    } catch (const Error& e) {
      if (required) throw;
      out.warnings.push_back(cat("no OpenGL context (", first_line(e.what()), "); solver backend auto uses the CPU"));
    }
  }
  // Ctrl-C and the deadline reach the precompute too (it may take minutes).
  const StopFlags stop{req.interrupt, &dog.expired()};
  const sim::Model model = [&] {
    try {
      return sim::compile(spec, backend::RunResources{context.get(), stop});
    } catch (const InterruptedError&) {
      throw;
    } catch (const TimeoutError&) {
      throw;
    } catch (const Error& e) {  // what compile refuses, named with the scenario file
      const std::string msg = e.what(), file = req.scenario.string();
      if (msg.rfind(file, 0) == 0) throw;
      fail(file, ": ", msg);
    }
  }();
  out.mesh_fingerprint = mesh_fingerprint(model.mesh);
  out.params = spec.params;
  // Frames are drawn on a worker thread while the next frame is simulated,
  // unless the solver (GPU CG, or stage 5's product on the device) needs the
  // shared context on this thread.
  std::unique_ptr<render::FrameWriter> frames;
  if (spec.outputs.render.enabled) {
    const backend::BackendChoice& b = model.solver->backend();
    const bool solver_on_gpu = b.backend == backend::Backend::gpu || b.device_product;
    frames = std::make_unique<render::FrameWriter>(*context,
                                                   solver_on_gpu || req.render_inline
                                                       ? render::FrameWriter::Mode::inline_draw
                                                       : render::FrameWriter::Mode::worker,
                                                   2, &output);
    const sim::RenderSettings& rs = spec.outputs.render;
    if (rs.video)
      frames->attach_video(std::make_unique<render::VideoEncoder>(
          out.out_dir / "video.mp4", rs.width, rs.height, spec.timeline.fps / rs.every));
  }
  out.num_frames = model.num_frames;
  sim::State state = sim::make_state(model);
  script->start();

  sim::RunHooks hooks;
  hooks.check = [&](int index, const sim::Model& m, sim::State& st) { return script->check(index, m, st); };
  hooks.on_frame = [&](const sim::Model& m, sim::State& st) { return script->on_frame(m, st); };
  hooks.interrupt = req.interrupt;
  hooks.timed_out = &dog.expired();
  hooks.seconds_left = dog.seconds_left();
  hooks.max_frames = req.max_frames;
  hooks.progress = req.progress;

  sim::Recorder rec(model, out.out_dir, &output);
  if (frames) rec.set_frame_writer(frames.get());
  out.result = sim::run(model, state, rec, hooks);
  out.step_ms = state.stats.total.sum / std::max(1, state.stats.frames);
  out.frames_rendered = rec.frames_rendered();
  if (out.frames_rendered) {
    out.render_ms = rec.render_frame_thread_ms().sum / out.frames_rendered;
    const render::FrameWriterStats st = frames->stats();  // one locked snapshot
    const double n = std::max(1, st.frames);
    out.render_work_ms = st.work.total_ms() / n;
    out.render_rgb_ms = st.work.rgb_ms() / n;
    out.render_labels_ms = st.work.labels_ms() / n;
    out.render_video_ms = st.work.video_ms / n;
  }
  // Each once, in order of appearance (as summary.json lists them).
  std::unordered_set<std::string> seen(out.warnings.begin(), out.warnings.end());
  const std::vector<std::string>* lists[] = {&model.warnings, &state.warnings};
  for (const std::vector<std::string>* list : lists)
    for (const std::string& w : *list)
      if (seen.insert(w).second) out.warnings.push_back(w);
  out.expectations = expectation_results(model, state);
  return out;
}

}  // namespace

std::unique_ptr<sim::ScenarioScript> open_lua_scenario(const RunRequest& req, OutputBudget* output,
                                                       const Watchdog* watchdog) {
  lua::ScriptRequest s;
  s.scenario = req.scenario;
  s.scenario_root = req.scenario_root;
  s.overrides = req.overrides;
  s.sandbox.trusted = req.trusted;
  s.sandbox.instruction_budget = req.instruction_budget;
  s.sandbox.memory_budget = req.memory_budget;
  s.sandbox.max_tets = req.max_tets;
  s.sandbox.interrupt = req.interrupt;
  s.sandbox.output = output;
  s.watchdog = watchdog;
  return lua::open_scenario(s);
}

sim::ScenarioSpec load_scenario_spec(const RunRequest& req, const OpenScript& open) {
  return open(req, nullptr, nullptr)->spec();
}

RunOutcome run_scenario(const RunRequest& req, const OpenScript& open) {
  // Made before the script: the watchdog outlives it, so a hang while the
  // script's state is closed is still ended.
  Watchdog dog(req.timeout_s, std::clamp(req.timeout_s / 10, 5.0, 60.0),
               cat(req.scenario.string(), ": the wall-clock limit of ", req.timeout_s,
                   " s (--timeout) passed and the run did not stop (stuck outside the script); exiting without "
                   "finishing the outputs"));
  try {
    return run_watched(req, open, dog);
  } catch (const TimeoutError&) {
    throw;
  } catch (const InterruptedError&) {
    throw;
  } catch (const Error& e) {
    // The limit or a stop struck before the frame loop (the script's main
    // chunk, compile): the same exit status as in the loop.
    if (req.interrupt && req.interrupt->load()) throw InterruptedError(e.what());
    if (dog.expired()) throw TimeoutError(e.what());
    throw;
  }
}

}  // namespace softcut::app
