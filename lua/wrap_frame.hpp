#pragma once
// The frame handle the on_frame glue passes to the bindings: a Lua userdata
// holding pointers to the run's Model and State, valid only during the
// callback (null otherwise, so a Frame kept past its call fails cleanly).
#include "sim/model.hpp"

struct lua_State;

namespace softcut::lua {

struct FrameContext {
  const sim::Model* model = nullptr;
  sim::State* state = nullptr;
};

// Pushes a new frame handle and returns its context (owned by Lua).
FrameContext* push_frame_context(lua_State* L);

}  // namespace softcut::lua
