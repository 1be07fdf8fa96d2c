// The hand-written loop the generated manip/a.cs is measured against: the same work per
// cycle, written directly. It reads the seven input buffers from the same kind of links
// (earl::Channel), runs stage 1 (calculatePosition and the pf of the current state) and
// stage 2 (outputManipState, outputMotorCon) with the trivial bodies of the generated
// stubs, writes the seven output buffers, counts the iteration, evaluates the tc of the
// current state and, when it holds, its guards with the same boolean structure as the
// model, and selects the next state with the same priorities.
#include <array>
#include <cstdint>

#include "bench.hpp"

namespace bench {
namespace {

class ManipulatorControlLoop {
 public:
  enum State : std::uint8_t { idle, jointMove, operationalMove, emergencyStop };

  explicit ManipulatorControlLoop(Links& links) noexcept : links_(links) {}

  void cycle() noexcept {
    // the transition function: stage 1, then stage 2
    calculatePosition();
    switch (state_) {
      case idle: passiveRegulation(); break;
      case jointMove: jointMoveFunction(); break;
      case operationalMove: operationalMoveFunction(); break;
      case emergencyStop: emergencyStopFunction(); break;
    }
    outputManipState();
    outputMotorCon();
    // send
    links_.manipulatorState.write(manipulatorState_);
    for (std::size_t k = 0; k < kJoints; ++k) links_.motorControllerCommand[k].write(motorControllerCommand_[k]);
    ++iteration_;
    // receive
    manipulatorCommandNew_ = links_.manipulatorCommand.read(manipulatorCommand_);
    for (std::size_t k = 0; k < kJoints; ++k) {
      motorControllerStateNew_[k] = links_.motorControllerState[k].read(motorControllerState_[k]);
    }
    // tc (every ec is FALSE), then the next state
    if (terminal()) selectState();
  }

  bool& motionFinished() noexcept { return motionFinished_; }
  State state() const noexcept { return state_; }
  std::uint64_t iteration() const noexcept { return iteration_; }

 private:
  // the pf bodies of the generated stubs: nothing
  void calculatePosition() noexcept {}
  void passiveRegulation() noexcept {}
  void jointMoveFunction() noexcept {}
  void operationalMoveFunction() noexcept {}
  void emergencyStopFunction() noexcept {}
  void outputManipState() noexcept {}
  void outputMotorCon() noexcept {}

  // the primitive predicates
  bool emergencyStopPredicate() const noexcept {
    return manipulatorCommand_.emergencyStopCommand || motorControllerState_[0].emergencyStopCommand ||
           motorControllerState_[1].emergencyStopCommand || motorControllerState_[2].emergencyStopCommand ||
           motorControllerState_[3].emergencyStopCommand || motorControllerState_[4].emergencyStopCommand ||
           motorControllerState_[5].emergencyStopCommand;
  }
  bool newJointPos() const noexcept { return manipulatorCommandNew_ && !manipulatorCommand_.jointPosSetpoint.empty(); }
  bool newOperationalPos() const noexcept {
    return manipulatorCommandNew_ && !manipulatorCommand_.operationalPosSetpoint.empty();
  }

  bool terminal() const noexcept {
    switch (state_) {
      case idle: return newJointPos() || newOperationalPos() || emergencyStopPredicate();
      case jointMove:
      case operationalMove: return motionFinished_ || emergencyStopPredicate();
      case emergencyStop: return false;
    }
    return false;
  }

  // priorities: to emergencyStop 2, self-transitions 1, the others 0 (ties: model order)
  void selectState() noexcept {
    switch (state_) {
      case idle:
        if (emergencyStopPredicate()) return enter(emergencyStop);
        if (newJointPos() && !emergencyStopPredicate()) return enter(jointMove);
        if (newOperationalPos() && !emergencyStopPredicate()) return enter(operationalMove);
        break;
      case jointMove:
        if (emergencyStopPredicate()) return enter(emergencyStop);
        if (newJointPos() && !emergencyStopPredicate()) return enter(jointMove);
        if (!emergencyStopPredicate()) return enter(idle);
        break;
      case operationalMove:
        if (emergencyStopPredicate()) return enter(emergencyStop);
        if (newOperationalPos() && !emergencyStopPredicate()) return enter(operationalMove);
        if (!emergencyStopPredicate()) return enter(idle);
        break;
      case emergencyStop: break;
    }
    iteration_ = 0;  // no transition holds: the behaviour starts again
  }

  void enter(State next) noexcept {
    state_ = next;
    iteration_ = 0;
  }

  Links& links_;
  State state_ = idle;
  std::uint64_t iteration_ = 0;
  // input buffers
  types::ManipulatorCommand manipulatorCommand_{};
  bool manipulatorCommandNew_ = false;
  std::array<types::MotorControllerState, kJoints> motorControllerState_{};
  std::array<bool, kJoints> motorControllerStateNew_{};
  // output buffers
  types::ManipulatorState manipulatorState_{};
  std::array<types::MotorControllerCommand, kJoints> motorControllerCommand_{};
  // memory
  bool motionFinished_ = false;
  types::OperPosition currentOperationalPos_{};
  types::JointPosition currentJointPos_{};
  std::array<bool, kJoints> emergencyStopCommand_{};
  std::array<double, kJoints> windingCurrent_{};
};

struct Fixture {
  explicit Fixture(Scenario s) noexcept : source(s), loop(links) {
    if (s == Scenario::switching) loop.motionFinished() = true;
  }
  Links links;
  Source source;
  ManipulatorControlLoop loop;
  std::uint64_t cycle = 0;
};

Fixture& fixture(Scenario scenario) noexcept {
  static Fixture hold(Scenario::hold);
  static Fixture switching(Scenario::switching);
  return scenario == Scenario::hold ? hold : switching;
}

const char* const kStateNames[] = {"idle", "jointMove", "operationalMove", "emergencyStop"};

}  // namespace

double baselineRun(Scenario scenario, std::uint64_t cycles) {
  Fixture& f = fixture(scenario);
  const double ns = nsPerCycle(cycles, [&f](std::uint64_t i) {
    f.source.feed(f.links, f.cycle + i);
    f.loop.cycle();
  });
  f.cycle += cycles;
  return ns;
}

Summary baselineSummary(Scenario scenario) {
  const Fixture& f = fixture(scenario);
  return {kStateNames[f.loop.state()], f.loop.iteration()};
}

}  // namespace bench
