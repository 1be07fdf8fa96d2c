// The harmoniser sample's shared helpers, used by its user files. Not a file earl-m2t generates:
// gen neither creates nor reports it. It sits in user/, which the generated CMakeLists.txt
// puts on the include path.
//
// The lidar sees the person fall once, at a scripted scan, and get up again later. The task
// agents print what they do, so that a test can follow guide/a across the fall:
//   guide/a.cs: lead to waypoint N
//   guide/a.cs: park at waypoint N
//   fallHelp/a.cs: assist step N
// HARMONISER_QUIET=1 silences them.
#pragma once

#include <cstdint>
#include <cstdlib>

namespace harmoniser {

inline bool quiet() noexcept {
  static const bool value = std::getenv("HARMONISER_QUIET") != nullptr;
  return value;
}

/// The scans (numbered from 0) in which the person lies on the floor: [kFallFrom, kFallUntil).
/// The lidar's links hold their latest value, so a reader sees the fall only if it runs while
/// the person lies: 120 scans (0.12 s at 1 ms) outlast a reader starved on a loaded machine,
/// where 30 did not.
inline constexpr std::int64_t kFallFrom = 40;
inline constexpr std::int64_t kFallUntil = 160;

/// What the lidar sees of the person: the height of their highest point (m), in ranges[0].
inline constexpr double kStanding = 1.7;
inline constexpr double kLying = 0.3;
inline constexpr double kFallenBelow = 0.8;

}  // namespace harmoniser
