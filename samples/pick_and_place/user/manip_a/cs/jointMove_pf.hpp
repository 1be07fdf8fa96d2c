// earl-m2t user file: pf manip/a.cs.jointMove/pf
// The pick-and-place sample's user code (samples/pick_and_place/user). gen never overwrites
// it; if the pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

#include "PickAndPlace/manip_a/cs/data.hpp"
#include "pick_and_place_sample.hpp"

namespace PickAndPlace::manip_a::cs {

/// The joint-space motion of paper Fig. 13: interpolates from where the joints are to the
/// setpoint of manipulatorCommand/ib and, per joint, computes the winding current: the PI
/// motor position regulator of eqs. 2–3, Kp·e + Ki·∫e with e = interpolated position − motor
/// position, plus the feed-forward current of the interpolated motion. (The PI alone must
/// overshoot: on a motor, which integrates, the integral that carries the motion has to be
/// unwound by a negative error at its end; the sample's move overshot by 3 % that way.)
/// motionFinished/mo becomes true once the interpolation is over and every joint is within
/// kPositionTolerance of its setpoint and slower than kSpeedTolerance.
class jointMove_pf final : public jointMove_pf_base {
 public:
  using jointMove_pf_base::jointMove_pf_base;

  void execute() override {
    namespace sample = ::pick_and_place;
    // The guards into jointMove hold only on a fresh setpoint, so the first iteration after
    // entering the state sees it (newData lasts until the next receive).
    const auto& command = manipulatorCommand_ib();
    if (manipulatorCommand_ib_newData() && !command.jointPosSetpoint.empty()) {
      start(command.jointPosSetpoint[0].q);
    } else if (!started_) {
      std::array<double, kJoints> here{};
      for (std::size_t k = 0; k < kJoints; ++k) here[k] = motorControllerStateK_ib(k).motorPos;
      start(here);  // not reached through the model's guards: hold where the joints are
    }
    const double u = duration_ > 0.0 ? std::min(elapsed_ / duration_, 1.0) : 1.0;
    const double s = u * u * (3.0 - 2.0 * u);                                       // s(u)
    const double ds = u < 1.0 ? 6.0 * u * (1.0 - u) / duration_ : 0.0;               // ds/dt
    const double dds = u < 1.0 ? (6.0 - 12.0 * u) / (duration_ * duration_) : 0.0;  // d²s/dt²
    bool finished = u >= 1.0;
    for (std::size_t k = 0; k < kJoints; ++k) {
      const double position = motorControllerStateK_ib(k).motorPos;
      const double distance = to_[k] - from_[k];
      windingCurrentK_mo(k) = sample::feedForwardCurrent(distance * ds, distance * dds) +
                              regulators_[k].current(from_[k] + distance * s, position);
      const double speed = (position - previous_[k]) / sample::kDt;
      previous_[k] = position;
      finished = finished && std::abs(to_[k] - position) < sample::kPositionTolerance &&
                 std::abs(speed) < sample::kSpeedTolerance;
    }
    motionFinished_mo() = finished;
    elapsed_ += sample::kDt;
  }

 private:
  static constexpr std::size_t kJoints = windingCurrentK_count;
  static_assert(kJoints == motorControllerStateK_ib_count);

  void start(const std::array<double, kJoints>& setpoint) noexcept {
    namespace sample = ::pick_and_place;
    double longest = 0.0;
    for (std::size_t k = 0; k < kJoints; ++k) {
      from_[k] = motorControllerStateK_ib(k).motorPos;
      to_[k] = setpoint[k];
      previous_[k] = from_[k];
      regulators_[k].reset();
      longest = std::max(longest, std::abs(to_[k] - from_[k]));
    }
    duration_ = 1.5 * longest / sample::kMaxJointSpeed;  // the peak speed of s(u) is 1.5 × the mean
    elapsed_ = 0.0;
    started_ = true;
    motionFinished_mo() = false;
  }

  std::array<::pick_and_place::PiRegulator, kJoints> regulators_{};
  std::array<double, kJoints> from_{};
  std::array<double, kJoints> to_{};
  std::array<double, kJoints> previous_{};
  double duration_ = 0.0;
  double elapsed_ = 0.0;
  bool started_ = false;
};

}  // namespace PickAndPlace::manip_a::cs
