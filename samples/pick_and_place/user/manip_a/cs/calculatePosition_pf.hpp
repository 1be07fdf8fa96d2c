// earl-m2t user file: pf manip/a.cs.calculatePosition/pf
// The pick-and-place sample's user code (samples/pick_and_place/user). gen never overwrites
// it; if the pf disappears from the model, gen reports this file as orphaned.
#pragma once

#include <cmath>

#include "PickAndPlace/manip_a/cs/data.hpp"

namespace PickAndPlace::manip_a::cs {

/// Joint positions from the motor positions (gear ratio 1: a joint is where its motor is) and
/// the end-effector pose by the forward kinematics of a simple arm: base yaw q1, shoulder and
/// elbow pitch q2, q3 (links kUpperArm, kForearm from a shoulder kBaseHeight above the base)
/// to the wrist centre, and a roll-pitch-roll wrist q4..q6 for the orientation.
class calculatePosition_pf final : public calculatePosition_pf_base {
 public:
  using calculatePosition_pf_base::calculatePosition_pf_base;

  void execute() override {
    auto& joints = currentJointPos_mo();
    for (std::size_t k = 0; k < motorControllerStateK_ib_count; ++k) joints.q[k] = motorControllerStateK_ib(k).motorPos;
    const auto& q = joints.q;
    const double reach = kUpperArm * std::cos(q[1]) + kForearm * std::cos(q[1] + q[2]);
    auto& pose = currentOperationalPos_mo();
    pose.position.x = reach * std::cos(q[0]);
    pose.position.y = reach * std::sin(q[0]);
    pose.position.z = kBaseHeight + kUpperArm * std::sin(q[1]) + kForearm * std::sin(q[1] + q[2]);
    // yaw about z, then the arm's pitch (positive lifts the arm, a negative turn about y),
    // then the wrist's roll about x, pitch about y, roll about x
    types::Quaternion r = about(0.0, 0.0, 1.0, q[0]);
    r = times(r, about(0.0, 1.0, 0.0, -(q[1] + q[2])));
    r = times(r, about(1.0, 0.0, 0.0, q[3]));
    r = times(r, about(0.0, 1.0, 0.0, q[4]));
    pose.orientation = times(r, about(1.0, 0.0, 0.0, q[5]));
  }

 private:
  static constexpr double kBaseHeight = 0.40;  // m
  static constexpr double kUpperArm = 0.40;    // m
  static constexpr double kForearm = 0.35;     // m

  static types::Quaternion about(double x, double y, double z, double angle) noexcept {
    const double s = std::sin(angle / 2.0);
    return types::Quaternion{x * s, y * s, z * s, std::cos(angle / 2.0)};
  }
  static types::Quaternion times(const types::Quaternion& a, const types::Quaternion& b) noexcept {
    return types::Quaternion{a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
                             a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
                             a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
                             a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z};
  }
};

}  // namespace PickAndPlace::manip_a::cs
