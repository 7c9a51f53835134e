#pragma once
// Command-line options through CLI11 (Debian libcli11-dev): each command
// declares its options once; CLI11 parses them (--opt value, --opt=value,
// -jN, options repeated or in any order) and writes --help from the same
// declarations, so the help can no longer drift from what is accepted.
// CLI11's errors become softcut::UsageError (exit status 2) in softcut's
// words, naming the command:
//   softcut run: unknown option '--bogus' (see softcut run --help)
//   softcut run: --out needs a value (see softcut run --help)
// Values are typed: CLI11 converts them after a validator (option_values.hpp)
// has checked the text, whose message names the option and the value:
//   softcut run: --frames lots: expected a whole number from 0 to 100000000
// The options of a scenario run are declared once (run_options.hpp).
//
//   Options o("softcut run", "Runs a Lua scenario headless ...");
//   o.app().add_option("--out", out, "output folder")->type_name("DIR");
//   if (!o.parse(args)) return 0;  // --help was printed
#include <CLI/CLI.hpp>
#include <map>
#include <string>
#include <vector>

#include "app/commands.hpp"

namespace softcut::app {

class Options {
 public:
  // command: "softcut run" (the help's usage line and every message);
  // description: the help's first paragraph; footer: its last (exit
  // statuses, environment, examples).
  Options(std::string command, const std::string& description, const std::string& footer = "");
  CLI::App& app() { return app_; }
  // A repeatable option collecting its values in order (--set, --only, --tets).
  template <class T>
  CLI::Option* add_list(const std::string& name, std::vector<T>& values, const std::string& help) {
    return app_.add_option(name, values, help)->multi_option_policy(CLI::MultiOptionPolicy::TakeAll)->expected(1)
        ->allow_extra_args(false);
  }
  // How a missing value of `option` is named in its message ("--json needs
  // a file name"); default "a value".
  void needs(const std::string& option, std::string what) { needs_[option] = std::move(what); }
  // Parses args (those after the command's name). Returns false when --help
  // or -h was given: the help is printed to stdout. Throws UsageError.
  bool parse(const Args& args);
  // The generated help text.
  std::string help() const { return app_.help(); }

 private:
  std::string command_;
  CLI::App app_;
  std::map<std::string, std::string> needs_;
};

}  // namespace softcut::app
