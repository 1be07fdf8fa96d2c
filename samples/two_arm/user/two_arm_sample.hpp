// The two-arm sample's shared helpers, used by its user files. Not a file earl-m2t generates:
// gen neither creates nor reports it. It sits in user/, which the generated CMakeLists.txt
// puts on the include path.
//
// The run prints one line per numbered command sent and one per command taken, so that a test
// can check that every command reached exactly the arm of the configuration it was sent in:
//   task/a.cs: sent seq N to manipA/a
//   manipA/a.cs: took seq N
// TWO_ARM_QUIET=1 silences them (printing takes the C library's stream lock).
#pragma once

#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

namespace two_arm {

/// The arms, in the order the system constructs them (the model order of cell/r's parts).
inline constexpr const char* kArms[] = {"manipA/a", "manipB/a"};

inline bool quiet() noexcept {
  static const bool value = std::getenv("TWO_ARM_QUIET") != nullptr;
  return value;
}

/// Joint j of the setpoint of command ``seq``: a small step from the previous command's, so
/// that an arm reaches each setpoint in one iteration (moveArm/pf's step limit).
inline double setpoint(std::int64_t seq, std::size_t j) noexcept {
  return 0.2 * std::sin(0.05 * static_cast<double>(seq) + 0.7 * static_cast<double>(j));
}

/// The largest joint step of one moveArm/pf iteration (rad).
inline constexpr double kMaxStep = 0.05;

/// Which arm a ManipulatorControl instance is: both arms share one subsystem class and its pf
/// classes, so each moveArm/pf takes the next number as it is constructed (the system
/// constructs manipA/a before manipB/a). A second system in the same process counts on. A
/// ROS node runs one instance and names it in EARL_SUBSYSTEM_PATH (its model path).
inline const char* nextArm() noexcept {
  if (const char* path = std::getenv("EARL_SUBSYSTEM_PATH")) {
    for (const char* arm : kArms) {
      if (std::strncmp(path, arm, std::strlen(arm)) == 0) return arm;
    }
  }
  static std::atomic<unsigned> count{0};
  return kArms[count.fetch_add(1) % 2];
}

}  // namespace two_arm
