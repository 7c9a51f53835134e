// engine/backend/spec.cpp: the backend's names (and the storage names beside
// them in SolverSpec) parse once, round-trip, and a wrong one is named.
#include "backend/spec.hpp"

#include <doctest/doctest.h>

#include <string>

#include "core/error.hpp"

using namespace softcut;
using namespace softcut::backend;

TEST_SUITE("backend/spec") {
  TEST_CASE("backend and storage names parse once, round-trip, and a wrong one names the accepted values") {
    for (Backend b : {Backend::automatic, Backend::cpu, Backend::gpu, Backend::direct, Backend::monolithic})
      CHECK(parse_backend(to_string(b)) == b);
    CHECK(std::string(to_string(Backend::automatic)) == "auto");
    CHECK_THROWS_WITH_AS(parse_backend("cuda"), doctest::Contains("unknown backend 'cuda' (use auto, cpu, gpu"), Error);
    CHECK_THROWS_WITH_AS(parse_backend("CPU"), doctest::Contains("unknown backend 'CPU'"), Error);
    CHECK(hybrid::parse_storage("auto") == hybrid::Storage::automatic);
    for (hybrid::Storage st : {hybrid::Storage::dense, hybrid::Storage::product, hybrid::Storage::factor})
      CHECK(hybrid::parse_storage(hybrid::to_string(st)) == st);
    CHECK_THROWS_WITH_AS(hybrid::parse_storage("sparse"),
                         doctest::Contains("unknown mode 'sparse' (use auto, dense, product or factor)"), Error);
  }
}
