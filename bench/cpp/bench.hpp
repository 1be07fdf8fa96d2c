// What the per-cycle benchmark of manip/a.cs shares between the generated subsystem
// (driver.cpp) and the hand-written loop (baseline.cpp): the links, the source that feeds
// the seven input buffers every cycle, the scenarios and the timing loop.
// Built by bench/cpp_cycle.py against a project generated from the pick-and-place sample.
#pragma once

#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>

#include "earl/port.hpp"
#include "PickAndPlace/types.hpp"

namespace bench {

namespace types = ::PickAndPlace::types;

constexpr std::size_t kJoints = 6;  // N: motorControllerK/ve and motorK/re

/// hold: only the motor controllers' states arrive; cs stays in idle and evaluates the tc
/// of idle/bb (false) every cycle.
/// switching: a fresh joint setpoint arrives every cycle and motionFinished/m is set at
/// start-up, so the tc holds every cycle and the guards of the current state are
/// evaluated: idle -> jointMove once, then jointMove -> jointMove (self-transition) on
/// every cycle.
enum class Scenario { hold, switching };

inline const char* name(Scenario s) noexcept { return s == Scenario::hold ? "hold" : "switching"; }

/// The links of manip/a.cs: seven towards its input buffers, seven from its output buffers.
struct Links {
  // task/a.cs -> manipulatorCommand/ib, a queue of 8 in the sample (at most one command per cycle here)
  earl::QueueChannel<types::ManipulatorCommand, 8> manipulatorCommand;
  std::array<earl::Channel<types::MotorControllerState>, kJoints> motorControllerState;  // -> motorControllerStateK/ib
  earl::Channel<types::ManipulatorState> manipulatorState;  // manipulatorState/ob ->
  std::array<earl::Channel<types::MotorControllerCommand>, kJoints> motorControllerCommand;  // motorControllerCommandK/ob ->
};

/// The other ends of the input links: writes what task/a.cs and the six motor controllers
/// would send in one cycle.
class Source {
 public:
  explicit Source(Scenario scenario) noexcept : scenario_(scenario) {
    types::JointPosition setpoint{};
    for (std::size_t k = 0; k < kJoints; ++k) setpoint.q[k] = 0.1 * static_cast<double>(k + 1);
    command_.jointPosSetpoint.push_back(setpoint);
  }

  void feed(Links& links, std::uint64_t cycle) noexcept {
    const double base = static_cast<double>(cycle) * 1e-6;
    for (std::size_t k = 0; k < kJoints; ++k) {
      links.motorControllerState[k].write(types::MotorControllerState{base + static_cast<double>(k), false});
    }
    if (scenario_ == Scenario::switching) links.manipulatorCommand.write(command_);
  }

 private:
  Scenario scenario_;
  types::ManipulatorCommand command_{};
};

/// ns per call of step(i), i = 0 .. cycles-1, timed with std::chrono::steady_clock.
template <class Step>
double nsPerCycle(std::uint64_t cycles, Step&& step) {
  const auto start = std::chrono::steady_clock::now();
  for (std::uint64_t i = 0; i < cycles; ++i) step(i);
  const auto end = std::chrono::steady_clock::now();
  return std::chrono::duration<double, std::nano>(end - start).count() / static_cast<double>(cycles);
}

/// Where a run ended, to check that both sides did the same thing.
struct Summary {
  const char* state;
  std::uint64_t iteration;
};

/// baseline.cpp: the hand-written loop, one fixture per scenario.
double baselineRun(Scenario scenario, std::uint64_t cycles);
Summary baselineSummary(Scenario scenario);

}  // namespace bench
