#pragma once
// Fixture for tests/layout/layers.cmake: core/ may not include a later stage.
#include "core/error.hpp"
#include "sim/model.hpp"
