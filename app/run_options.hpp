#pragma once
// The options of a scenario run, declared once for `softcut run`, `check`
// and `sweep`: one name, type, range, help line and message each, whichever
// command takes them. CLI11 converts and checks the values (option_values.hpp);
// apply() copies those given into a RunRequest, and arguments() gives them
// back as `softcut run` arguments (what `sweep` passes on to every run).
//
//   Options o("softcut run", ...);
//   RunOptions run(o, RunOptions::all);
//   if (!o.parse(args)) return 0;
//   RunRequest req;
//   run.apply(req);
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "app/option_values.hpp"
#include "app/options.hpp"
#include "app/scenario_run.hpp"

namespace softcut::app {

class RunOptions {
 public:
  enum Group : unsigned {
    scenario = 1u,   // --set, --backend, --max-tets, --timeout, --max-output, --trust, --no-cache,
                     // --warnings-as-errors
    frames = 2u,     // --frames
    rendering = 4u,  // --render-every, --size, --msaa, --no-render
    all = 7u,
  };
  // Declares the options of `groups` on `o` (which must outlive this).
  RunOptions(Options& o, unsigned groups);
  RunOptions(const RunOptions&) = delete;  // CLI11 holds pointers to the members
  RunOptions& operator=(const RunOptions&) = delete;

  // The options given (after parsing) into `req`; the cache folder is
  // hybrid::default_cache_dir() unless --no-cache.
  void apply(RunRequest& req) const;
  // The options given, as `softcut run` arguments, in declaration order
  // (--set first, in the order given); values written back from their types.
  std::vector<std::string> arguments() const;
  // --set pairs as given ("key=value").
  const std::vector<std::string>& sets() const { return sets_; }
  bool trusted() const { return trust_; }

 private:
  bool given(const CLI::Option* o) const { return o && o->count() > 0; }

  std::vector<std::string> sets_;
  int frames_ = -1, render_every_ = 0, msaa_ = -1;
  long long max_tets_ = 0;
  backend::Backend backend_ = backend::Backend::automatic;
  FrameSize size_;
  double timeout_s_ = 0;
  std::uint64_t max_output_ = 0;
  bool trust_ = false, no_render_ = false, no_cache_ = false, warnings_as_errors_ = false;
  CLI::Option *set_ = nullptr, *frames_opt_ = nullptr, *backend_opt_ = nullptr, *render_every_opt_ = nullptr,
              *size_opt_ = nullptr, *msaa_opt_ = nullptr, *max_tets_opt_ = nullptr, *timeout_opt_ = nullptr,
              *max_output_opt_ = nullptr, *trust_opt_ = nullptr, *no_render_opt_ = nullptr, *no_cache_opt_ = nullptr,
              *warnings_as_errors_opt_ = nullptr;
};

}  // namespace softcut::app
