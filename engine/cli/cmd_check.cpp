#include "cli/commands.hpp"
#include "core/error.hpp"

namespace softcut::cli {

int cmd_check(const Args&) { fail("softcut check: not implemented yet"); }

}  // namespace softcut::cli
