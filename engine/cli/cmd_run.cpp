#include "cli/commands.hpp"
#include "core/error.hpp"

namespace softcut::cli {

int cmd_run(const Args&) { fail("softcut run: not implemented yet"); }

}  // namespace softcut::cli
