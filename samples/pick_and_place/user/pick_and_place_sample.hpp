// The pick-and-place sample's simulation and control parameters, shared by its user files.
// Not a file earl-m2t generates: gen neither creates nor reports it. It sits in user/, which
// the generated CMakeLists.txt puts on the include path.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdlib>

namespace pick_and_place {

/// One cycle of the executors (the threaded executor's period): the integration step of the
/// motor models and of the regulators' integrals.
inline constexpr double kDt = 0.001;  // s

// ---------------------------------------------------------------- the simulated motors

/// Mechanical time constant J/b of every simulated motor (motorK/re, fingerMotor/re).
inline constexpr double kMotorTau = 0.02;  // s
/// Steady-state speed per ampere of winding current, Kt/b.
inline constexpr double kMotorGain = 1.0;  // (rad/s)/A

/// A first-order DC motor with viscous friction and no load: J·dω/dt = Kt·i − b·ω, that is
/// τ·dω/dt = Km·i − ω; the position integrates ω. Semi-implicit Euler with dt = kDt.
class MotorModel {
 public:
  /// One cycle with the winding current `current`; advances `position` (the motor's memory).
  void step(double current, double& position) noexcept {
    velocity_ += (kMotorGain * current - velocity_) * (kDt / kMotorTau);
    position += velocity_ * kDt;
  }

 private:
  double velocity_ = 0.0;
};

// ---------------------------------------------------------------- the motor controllers

/// The winding current a motor controller (motorControllerK/ve, fingerController/ve) passes on.
inline constexpr double kMaxCurrent = 5.0;  // A

inline double limitCurrent(double current) noexcept { return std::clamp(current, -kMaxCurrent, kMaxCurrent); }

/// The current stage both motor controllers run: it passes the commanded winding current on,
/// limited to ±kMaxCurrent, and latches an emergency stop (zero current from then on).
class CurrentStage {
 public:
  double current(double desired, bool emergencyStop) noexcept {
    stopped_ = stopped_ || emergencyStop;
    return stopped_ ? 0.0 : limitCurrent(desired);
  }
  bool stopped() const noexcept { return stopped_; }

 private:
  bool stopped_ = false;
};

// ---------------------------------------------------------------- the position regulators

/// Gains of the PI motor position regulator, paper eqs. 2–3. With the motor above, the loop
/// is Km·(Kp·s + Ki) / (s²·(τ·s + 1)): closed-loop poles at s ≈ −13 and −18 ± 34j 1/s
/// (not counting the few cycles a measurement takes through the motor controllers).
inline constexpr double kKp = 40.0;   // A/rad
inline constexpr double kKi = 400.0;  // A/(rad·s)

/// windingCurrent = Kp·e(t) + Ki·∫e dt (eq. 2), e = desiredMotorPos − currentMotorPos (eq. 3).
class PiRegulator {
 public:
  void reset() noexcept { integral_ = 0.0; }
  double current(double desired, double measured) noexcept {
    const double error = desired - measured;
    integral_ += error * kDt;
    return kKp * error + kKi * integral_;
  }

 private:
  double integral_ = 0.0;
};

/// jointMove/pf interpolates from where the joints are to the setpoint along
/// s(u) = 3u² − 2u³, u = t/T; T makes the fastest joint's peak speed kMaxJointSpeed.
inline constexpr double kMaxJointSpeed = 2.0;  // rad/s
/// A motion is finished when the interpolation is over and every joint is within
/// kPositionTolerance of its setpoint and slower than kSpeedTolerance.
inline constexpr double kPositionTolerance = 5e-4;  // rad
inline constexpr double kSpeedTolerance = 5e-3;     // rad/s

/// The winding current that makes the motor model follow a motion with speed v and
/// acceleration a exactly (its inverse: i = (v + τ·a) / Km).
inline double feedForwardCurrent(double speed, double acceleration) noexcept {
  return (speed + kMotorTau * acceleration) / kMotorGain;
}

// ---------------------------------------------------------------- the trace

/// The sample's user files print one line per cycle (see the sample's README); set the
/// environment variable PICK_AND_PLACE_QUIET to a non-empty value to silence them. Read
/// once, when the pf objects are built (before the first cycle).
inline bool traceEnabled() noexcept {
  const char* quiet = std::getenv("PICK_AND_PLACE_QUIET");
  return quiet == nullptr || *quiet == '\0';
}

}  // namespace pick_and_place
