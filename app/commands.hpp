#pragma once
// Subcommands of the softcut program, one file each (cmd_<name>.cpp). Each
// takes the arguments after its name and returns the process exit code;
// softcut::Error thrown out of a command is printed as one line by main().
#include <string>
#include <vector>

namespace softcut::app {

using Args = std::vector<std::string>;

int cmd_mesh(const Args& args);   // softcut mesh info|convert|generate ...
int cmd_mesh_generate(const Args& args);  // softcut mesh generate KIND ... (the arguments from KIND on)
int cmd_bench(const Args& args);  // softcut bench <name> ...
int cmd_run(const Args& args);    // softcut run SCENARIO.lua ...
int cmd_check(const Args& args);  // softcut check PATH...
int cmd_sweep(const Args& args);  // softcut sweep SCENARIO.lua --grid ... | merge DIR
int cmd_render(const Args& args); // softcut render RUNDIR ...

}  // namespace softcut::app
