#include "app/run_options.hpp"

#include <algorithm>

#include "app/run_support.hpp"
#include "core/error.hpp"
#include "hybrid/precompute_cache.hpp"

namespace softcut::app {

RunOptions::RunOptions(Options& o, unsigned groups) {
  CLI::App& app = o.app();
  if (groups & scenario) {
    set_ = o.add_list("--set", sets_, "override a parameter the scenario declares with softcut.params{...}")
               ->type_name("key=value")->check(key_value());
    o.needs("--set", "key=value");
  }
  if (groups & frames) {
    frames_opt_ = app.add_option("--frames", frames_, "stop after N frames")->type_name("N")
                      ->check(whole_number(0, 100000000));
    o.needs("--frames", "a number");
  }
  if (groups & scenario) {
    backend_opt_ = app.add_option("--backend", backend_, "operational solver: auto, cpu, gpu, direct or monolithic "
                                  "(overrides the scenario's)")->type_name("B")->transform(backend_name());
    o.needs("--backend", "a backend");
  }
  if (groups & rendering) {
    render_every_opt_ = app.add_option("--render-every", render_every_, "render every N-th frame (also when the "
                                       "scenario renders none)")->type_name("N")->check(whole_number(0, 100000000));
    size_opt_ = app.add_option("--size", size_, "rendered frame size in pixels (overrides the scenario's, e.g. "
                               "640x480)")->type_name("WxH")->check(frame_size());
    msaa_opt_ = app.add_option("--msaa", msaa_, "multisample count of rendered frames (0: none; overrides the "
                               "scenario's)")->type_name("N")->check(whole_number(0, 100000000));
    for (const auto& [option, what] : {std::pair{"--render-every", "a number"}, {"--size", "WxH"}, {"--msaa", "a number"}})
      o.needs(option, what);
  }
  if (groups & scenario) {
    max_tets_opt_ = app.add_option("--max-tets", max_tets_, "sandbox: largest mesh a scenario may load or generate "
                                   "(default 2000000 tets)")->type_name("N")->check(whole_number(0, 100000000));
    timeout_opt_ = app.add_option("--timeout", timeout_s_, "wall-clock limit of a run (check: of each scenario) in "
                                  "seconds (default 3600; 0: none); the run then stops, writes its outputs and exits "
                                  "124, as soon as its frames so far show that the rest cannot finish in time")->type_name("S")->check(seconds_limit());
    max_output_opt_ = app.add_option("--max-output", max_output_, "bytes a run may write, all files together "
                                     "(default 4G; 0: none; K/M/G suffix)")->type_name("BYTES")->transform(byte_count());
    for (const auto& [option, what] : {std::pair{"--max-tets", "a number"}, {"--timeout", "seconds"},
                                       {"--max-output", "bytes"}})
      o.needs(option, what);
    trust_opt_ = app.add_flag("--trust", trust_, "no sandbox: full Lua standard library, no instruction, memory or "
                              "mesh budget");
  }
  if (groups & rendering)
    no_render_opt_ = app.add_flag("--no-render", no_render_, "write no frames (also when no OpenGL context can be made)");
  if (groups & scenario)
    no_cache_opt_ = app.add_flag("--no-cache", no_cache_, "redo the hybrid precompute instead of loading it from the "
                                 "cache ($SOFTCUT_CACHE_DIR, else $XDG_CACHE_HOME/softcut or ~/.cache/softcut)");
  if (groups & scenario)
    warnings_as_errors_opt_ = app.add_flag("--warnings-as-errors", warnings_as_errors_, "a run that warned fails "
                                           "(exit status 1; check: that scenario fails), as a compiler's -Werror; "
                                           "docs/outputs.md lists the warnings and their codes");
}

void RunOptions::apply(RunRequest& req) const {
  for (const auto& s : sets_) add_override(req.overrides, s);
  if (given(frames_opt_)) req.max_frames = frames_;
  if (given(backend_opt_)) req.backend = backend_;
  if (given(render_every_opt_)) req.render_every = std::max(1, render_every_);
  if (given(size_opt_)) req.width = size_.width, req.height = size_.height;
  if (given(msaa_opt_)) req.msaa_samples = msaa_;
  if (given(max_tets_opt_)) req.max_tets = double(max_tets_);
  if (given(timeout_opt_)) req.timeout_s = timeout_s_;
  if (given(max_output_opt_)) req.max_output = max_output_;
  if (trust_opt_) req.trusted = trust_;
  if (no_render_) req.render = false;
  if (warnings_as_errors_) req.warnings_as_errors = true;
  req.cache_dir = no_cache_ ? std::filesystem::path() : hybrid::default_cache_dir();
}

std::vector<std::string> RunOptions::arguments() const {
  std::vector<std::string> a;
  for (const auto& s : sets_) a.insert(a.end(), {"--set", s});
  if (given(frames_opt_)) a.insert(a.end(), {"--frames", std::to_string(frames_)});
  if (given(backend_opt_)) a.insert(a.end(), {"--backend", backend::to_string(backend_)});
  if (given(render_every_opt_)) a.insert(a.end(), {"--render-every", std::to_string(render_every_)});
  if (given(size_opt_)) a.insert(a.end(), {"--size", cat(size_.width, "x", size_.height)});
  if (given(msaa_opt_)) a.insert(a.end(), {"--msaa", std::to_string(msaa_)});
  if (given(max_tets_opt_)) a.insert(a.end(), {"--max-tets", std::to_string(max_tets_)});
  if (given(timeout_opt_)) a.insert(a.end(), {"--timeout", cat(timeout_s_)});
  if (given(max_output_opt_)) a.insert(a.end(), {"--max-output", std::to_string(max_output_)});
  if (trust_) a.push_back("--trust");
  if (no_render_) a.push_back("--no-render");
  if (no_cache_) a.push_back("--no-cache");
  if (warnings_as_errors_) a.push_back("--warnings-as-errors");
  return a;
}

}  // namespace softcut::app
