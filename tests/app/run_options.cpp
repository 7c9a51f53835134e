// app/run_options.cpp: the run options declared once for run, check and
// sweep; typed values into a RunRequest, and back into arguments.
#include "app/run_options.hpp"

#include <doctest/doctest.h>

#include "core/error.hpp"

using namespace softcut::app;

namespace {

RunRequest request_of(const Args& args, unsigned groups, std::vector<std::string>* arguments = nullptr) {
  Options o("softcut demo", "A demo command.");
  RunOptions run(o, groups);
  if (!o.parse(args)) FAIL("--help was given");
  RunRequest req;
  run.apply(req);
  if (arguments) *arguments = run.arguments();
  return req;
}

std::string usage_error(const Args& args, unsigned groups) {
  try {
    request_of(args, groups);
  } catch (const softcut::UsageError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_SUITE("app/run_options") {
  TEST_CASE("typed values reach the run request - arguments() gives them back as softcut run reads them") {
    const Args args = {"--set", "f=0.5", "--frames", "12", "--backend", "cpu", "--render-every", "0",
                       "--size", "64x48", "--msaa", "2", "--max-tets", "5000", "--timeout", "0.5",
                       "--max-output", "3M", "--trust", "--no-render", "--no-cache", "--warnings-as-errors",
                       "--set", "g=a=b"};
    std::vector<std::string> again;
    const RunRequest a = request_of(args, RunOptions::all, &again);
    CHECK(a.overrides == std::map<std::string, std::string>{{"f", "0.5"}, {"g", "a=b"}});
    CHECK(a.max_frames == 12);
    CHECK(a.backend == softcut::backend::Backend::cpu);
    CHECK(a.render_every == 1);  // 0 renders every frame
    CHECK(a.width == 64);
    CHECK(a.height == 48);
    CHECK(a.msaa_samples == 2);
    CHECK(a.max_tets == 5000);
    CHECK(a.timeout_s == 0.5);
    CHECK(a.max_output == 3u << 20);
    CHECK(a.trusted);
    CHECK(!a.render);
    CHECK(a.cache_dir.empty());
    CHECK(a.warnings_as_errors);
    CHECK(again == std::vector<std::string>{"--set", "f=0.5", "--set", "g=a=b", "--frames", "12", "--backend", "cpu",
                                            "--render-every", "0", "--size", "64x48", "--msaa", "2", "--max-tets",
                                            "5000", "--timeout", "0.5", "--max-output", "3145728", "--trust",
                                            "--no-render", "--no-cache", "--warnings-as-errors"});
    // What sweep passes on reads back the same.
    const RunRequest b = request_of(again, RunOptions::all);
    CHECK(b.overrides == a.overrides);
    CHECK(b.max_frames == a.max_frames);
    CHECK(b.backend == a.backend);
    CHECK(b.max_output == a.max_output);
    CHECK(b.timeout_s == a.timeout_s);
    CHECK(b.warnings_as_errors);
    // Nothing given: the request's defaults stay.
    const RunRequest d = request_of({}, RunOptions::all);
    const RunRequest plain;
    CHECK(d.max_frames == plain.max_frames);
    CHECK(d.timeout_s == plain.timeout_s);
    CHECK(d.max_output == plain.max_output);
    CHECK(!d.backend);
    CHECK(d.render);
    CHECK(!d.warnings_as_errors);
  }

  TEST_CASE("a command takes only its groups - bad values are named with the option") {
    CHECK(usage_error({"--frames", "3"}, RunOptions::scenario) ==
          "softcut demo: unknown option '--frames' (see softcut demo --help)");
    CHECK(usage_error({"--size", "64x48"}, RunOptions::scenario | RunOptions::frames).find("unknown option '--size'") !=
          std::string::npos);
    CHECK(usage_error({"--frames", "lots"}, RunOptions::all) ==
          "softcut demo: --frames lots: expected a whole number from 0 to 100000000 (see softcut demo --help)");
    CHECK(usage_error({"--backend", "cuda"}, RunOptions::all) ==
          "softcut demo: --backend cuda: expected auto, cpu, gpu, direct or monolithic (see softcut demo --help)");
    CHECK(usage_error({"--set", "novalue"}, RunOptions::all) ==
          "softcut demo: --set novalue: expected key=value (e.g. --set force=0.5) (see softcut demo --help)");
    CHECK(usage_error({"--timeout"}, RunOptions::all) == "softcut demo: --timeout needs seconds (see softcut demo --help)");
  }
}
