#include "app/options.hpp"

#include <cstdio>

#include "core/error.hpp"

namespace softcut::app {

Options::Options(std::string command, const std::string& description, const std::string& footer)
    : command_(std::move(command)), app_(description, command_) {
  app_.footer(footer);
  app_.set_help_flag("-h,--help", "print this help and exit");
  app_.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);  // the last one wins
  app_.get_formatter()->column_width(24);
}

bool Options::parse(const Args& args) {
  // CLI11 takes the arguments last first.
  std::vector<std::string> rev(args.rbegin(), args.rend());
  const std::string see = " (see " + command_ + " --help)";
  try {
    app_.parse(rev);
  } catch (const CLI::CallForHelp&) {
    std::fputs(app_.help().c_str(), stdout);
    return false;
  } catch (const CLI::ExtrasError&) {
    const std::vector<std::string> extra = app_.remaining();
    const std::string first = extra.empty() ? std::string() : extra.front();
    if (!first.empty() && first[0] == '-') usage_fail(command_, ": unknown option '", first, "'", see);
    usage_fail(command_, ": unexpected argument '", first, "'", see);
  } catch (const CLI::ArgumentMismatch& e) {
    // "--out: 1 required TEXT missing" and the like: an option without its value.
    const std::string what = e.what();
    const auto colon = what.find(':');
    if (colon != std::string::npos && what.rfind("-", 0) == 0) {
      const std::string name = what.substr(0, colon);
      const auto it = needs_.find(name);
      usage_fail(command_, ": ", name, " needs ", it == needs_.end() ? "a value" : it->second, see);
    }
    usage_fail(command_, ": ", what, see);
  } catch (const CLI::ValidationError& e) {
    // "--frames: lots: expected ..." from CLI11 and our validators (whose
    // messages start with the value) reads "--frames lots: expected ...".
    std::string what = e.what();
    const auto colon = what.find(": ");
    if (what.rfind("-", 0) == 0 && colon != std::string::npos) {
      what.erase(colon, 1);
      // CLI11's range check says "--smooth: Value 1e9 not in range ...".
      if (what.compare(colon + 1, 6, "Value ") == 0) what.erase(colon + 1, 6);
    }
    usage_fail(command_, ": ", what, see);
  } catch (const CLI::ParseError& e) {
    usage_fail(command_, ": ", e.what(), see);
  }
  return true;
}

}  // namespace softcut::app
