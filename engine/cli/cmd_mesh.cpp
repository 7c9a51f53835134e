#include "cli/commands.hpp"
#include "core/error.hpp"

namespace softcut::cli {

int cmd_mesh(const Args&) { fail("softcut mesh: not implemented yet"); }

}  // namespace softcut::cli
