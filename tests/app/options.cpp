// app/options.cpp: options declared once through CLI11; its errors
// become UsageErrors in softcut's words, naming the command and the option.
#include "app/options.hpp"

#include <doctest/doctest.h>

#include "core/error.hpp"

using softcut::UsageError;
using softcut::app::Args;
using softcut::app::Options;

namespace {

struct Parsed {
  std::vector<std::string> files, sets;
  std::string out, jobs;
  bool quiet = false;
};

// A command shaped like softcut run: a positional, a value, a list, a flag, -j.
bool parse(const Args& args, Parsed& p) {
  Options o("softcut demo", "A demo command.", "Exit status: 0.");
  o.app().add_option("file", p.files, "files");
  o.app().add_option("--out", p.out, "output folder")->type_name("DIR");
  o.add_list("--set", p.sets, "key=value, repeatable");
  o.app().add_flag("-q,--quiet", p.quiet, "quiet");
  o.app().add_option("-j,--jobs", p.jobs, "jobs");
  o.needs("--out", "a folder");
  return o.parse(args);
}

std::string error_of(const Args& args) {
  Parsed p;
  try {
    parse(args, p);
  } catch (const UsageError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_SUITE("app/options") {
  TEST_CASE("values in any order, --opt=value, repeated lists in order, the last single value wins, -jN") {
    Parsed p;
    REQUIRE(parse({"--set", "a=1", "x.lua", "--out=o1", "-q", "--set=b=2", "--out", "o2", "-j3", "--set", "c=-1"}, p));
    CHECK(p.files == std::vector<std::string>{"x.lua"});
    CHECK(p.sets == std::vector<std::string>{"a=1", "b=2", "c=-1"});
    CHECK(p.out == "o2");
    CHECK(p.quiet);
    CHECK(p.jobs == "3");
    Parsed q;
    REQUIRE(parse({"--jobs", "4", "a", "b"}, q));
    CHECK(q.jobs == "4");
    CHECK(q.files == std::vector<std::string>{"a", "b"});
  }

  TEST_CASE("errors name the command and the option, in softcut's words") {
    CHECK(error_of({"x.lua", "--bogus"}) == "softcut demo: unknown option '--bogus' (see softcut demo --help)");
    CHECK(error_of({"x.lua", "--out"}) == "softcut demo: --out needs a folder (see softcut demo --help)");
    CHECK(error_of({"x.lua", "--set"}) == "softcut demo: --set needs a value (see softcut demo --help)");
    CHECK(error_of({"--quiet=maybe"}).find("softcut demo: ") == 0);
    CHECK(error_of({"x.lua"}).empty());
  }

  TEST_CASE("--help: the generated help holds every option and the footer, and parse() reports it was asked") {
    Options o("softcut demo", "A demo command.", "Exit status: 0.");
    std::string out;
    o.app().add_option("--out", out, "output folder")->type_name("DIR");
    const std::string help = o.help();
    CHECK(help.find("A demo command.") != std::string::npos);
    CHECK(help.find("--out DIR") != std::string::npos);
    CHECK(help.find("output folder") != std::string::npos);
    CHECK(help.find("Exit status: 0.") != std::string::npos);
    CHECK_FALSE(o.parse({"--out", "x", "--help"}));  // prints the help to stdout
  }
}
