#pragma once
// A deliberately broken tree for the layer test: the engine may not use Lua.
#include <lua.h>
