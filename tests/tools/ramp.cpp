#include "tools/ramp.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <numbers>

#include "core/error.hpp"

using softcut::tools::Ramp;
using softcut::tools::evaluate;

TEST_SUITE("tools/ramp") {
  TEST_CASE("constant and linear against closed forms") {
    CHECK(evaluate(Ramp::constant_value(2.5), -3.0) == 2.5);
    CHECK(evaluate(Ramp::constant_value(2.5), 1e6) == 2.5);
    const Ramp r = Ramp::linear_ramp(1.0, 3.0, 0.5, 1.5);
    CHECK(evaluate(r, 0.0) == 1.0);
    CHECK(evaluate(r, 0.5) == 1.0);
    CHECK(evaluate(r, 1.0) == doctest::Approx(2.0).epsilon(1e-15));
    CHECK(evaluate(r, 1.25) == doctest::Approx(2.5).epsilon(1e-15));
    CHECK(evaluate(r, 1.5) == 3.0);
    CHECK(evaluate(r, 9.0) == 3.0);
  }

  TEST_CASE("smoothstep: endpoints, midpoint, zero slope at both ends") {
    const Ramp r = Ramp::smoothstep_ramp(-2.0, 4.0, 1.0, 3.0);
    CHECK(evaluate(r, 1.0) == -2.0);
    CHECK(evaluate(r, 3.0) == 4.0);
    CHECK(evaluate(r, 2.0) == doctest::Approx(1.0).epsilon(1e-15));
    // s = 0.25: 3 s^2 - 2 s^3 = 0.15625
    CHECK(evaluate(r, 1.5) == doctest::Approx(-2.0 + 6.0 * 0.15625).epsilon(1e-14));
    const double h = 1e-6;
    CHECK(std::abs(evaluate(r, 1.0 + h) - evaluate(r, 1.0)) / h < 1e-4);
    CHECK(std::abs(evaluate(r, 3.0) - evaluate(r, 3.0 - h)) / h < 1e-4);
    // Slope at the middle: (to - from) * 1.5 / (t1 - t0) = 4.5
    CHECK((evaluate(r, 2.0 + h) - evaluate(r, 2.0 - h)) / (2 * h) == doctest::Approx(4.5).epsilon(1e-6));
  }

  TEST_CASE("keyframes: exact at keys, linear between, held outside, continuous") {
    const Ramp r = Ramp::keyframed({0.0, 0.2, 0.5, 1.0}, {0.0, 1.0, -1.0, 3.0});
    CHECK(evaluate(r, -1.0) == 0.0);
    CHECK(evaluate(r, 0.0) == 0.0);
    CHECK(evaluate(r, 0.2) == 1.0);
    CHECK(evaluate(r, 0.5) == -1.0);
    CHECK(evaluate(r, 1.0) == 3.0);
    CHECK(evaluate(r, 2.0) == 3.0);
    CHECK(evaluate(r, 0.35) == doctest::Approx(0.0).epsilon(1e-14));
    CHECK(evaluate(r, 0.75) == doctest::Approx(1.0).epsilon(1e-14));
    for (double t : {0.2, 0.5, 1.0}) {
      CHECK(std::abs(evaluate(r, t - 1e-9) - evaluate(r, t)) < 1e-7);
      CHECK(std::abs(evaluate(r, t + 1e-9) - evaluate(r, t)) < 1e-7);
    }
  }

  TEST_CASE("sine against the closed form, offset before t0") {
    const Ramp r = Ramp::sine_wave(1.0, 0.5, 2.0, 0.3, 0.25);
    CHECK(evaluate(r, 0.0) == 1.0);
    for (double t : {0.25, 0.4, 1.0, 3.7})
      CHECK(evaluate(r, t) ==
            doctest::Approx(1.0 + 0.5 * std::sin(2 * std::numbers::pi * 2.0 * (t - 0.25) + 0.3)).epsilon(1e-14));
  }

  TEST_CASE("bad ramps are refused with the item named") {
    using softcut::Error;
    CHECK_THROWS_WITH_AS(check_ramp(Ramp::linear_ramp(0, 1, 1.0, 1.0), "load 'push' magnitude"),
                         doctest::Contains("load 'push' magnitude"), Error);
    CHECK_THROWS_WITH_AS(check_ramp(Ramp::keyframed({0.0, 0.7, 0.5}, {1, 2, 3}), "x"),
                         doctest::Contains("key 3"), Error);
    CHECK_THROWS_AS(check_ramp(Ramp::keyframed({0.0, 1.0}, {1}), "x"), Error);
    CHECK_THROWS_AS(check_ramp(Ramp::keyframed({}, {}), "x"), Error);
    CHECK_THROWS_AS(check_ramp(Ramp::constant_value(NAN), "x"), Error);
    CHECK_THROWS_AS(check_ramp(Ramp::sine_wave(0, 1, -1), "x"), Error);
    CHECK_NOTHROW(check_ramp(Ramp::keyframed({0.0, 1.0}, {1, 2}), "x"));
    CHECK(softcut::tools::ramp_kind_from_string("smoothstep", "x") == Ramp::Kind::smoothstep);
    CHECK_THROWS_WITH_AS(softcut::tools::ramp_kind_from_string("cubic", "load 'a'"), doctest::Contains("cubic"), Error);
  }
}
