// earl runtime: the opt-in real-time settings of the threaded executor. Each subsystem's thread
// may take a SCHED_FIFO priority and a CPU affinity; the process may lock its memory. A
// setting the system refuses is reported in one line naming the subsystem, the setting and
// the reason, and nothing runs: a setting is never silently ignored.
// Part of earl-m2t's C++ target; header-only, C++17, Linux.
#pragma once

#include <array>
#include <cerrno>
#include <cstddef>
#include <cstdio>
#include <cstring>

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include "earl/component.hpp"

namespace earl {

/// The settings of one subsystem's thread, applied in that thread before its first iteration.
struct ThreadSettings {
  int priority = 0;  // SCHED_FIFO priority 1..99; 0: the default policy
  int cpu = -1;      // the only CPU the thread runs on; -1: any
};

/// How ThreadedRunner gives components threads: periodic components of one period and the
/// same settings share one (perPeriod, the default), or each has its own (perSubsystem).
/// An event-driven component always has its own.
enum class ThreadPlan : std::uint8_t { perPeriod, perSubsystem };

constexpr int kMinPriority = 1;
constexpr int kMaxPriority = 99;

/// "NAME=VALUE" (one subsystem) or "VALUE" (every subsystem): ``name`` is nullptr for the
/// latter; VALUE a whole number in [low, high]. false when the text is not of that form.
inline bool parseSetting(const char* text, const char*& name, std::size_t& nameLength, int& value, int low,
                         int high) noexcept {
  if (text == nullptr || *text == '\0') return false;
  const char* equals = std::strrchr(text, '=');
  const char* digits = equals != nullptr ? equals + 1 : text;
  name = equals != nullptr ? text : nullptr;
  nameLength = equals != nullptr ? static_cast<std::size_t>(equals - text) : 0;
  if (equals != nullptr && nameLength == 0) return false;
  if (*digits == '\0') return false;
  long parsed = 0;
  for (const char* c = digits; *c != '\0'; ++c) {
    if (*c < '0' || *c > '9') return false;
    parsed = parsed * 10 + (*c - '0');
    if (parsed > high) return false;
  }
  if (parsed < low) return false;
  value = static_cast<int>(parsed);
  return true;
}

namespace detail {

inline const char* errorName(int error) noexcept {
  switch (error) {
    case EPERM:
      return "operation not permitted";
    case EINVAL:
      return "invalid argument";
    case ENOMEM:
      return "not enough memory";
    case EAGAIN:
      return "resource temporarily unavailable";
    case ESRCH:
      return "no such thread";
    default:
      return "error";
  }
}

}  // namespace detail

/// One --priority or --cpu argument ("NAME=VALUE" or "VALUE" for every subsystem) into the
/// settings of ``components``; false, after one line on stderr, when it is out of range or
/// names no subsystem (refused before anything starts).
template <std::size_t N>
bool assignSetting(const char* option, const char* text, const std::array<Component*, N>& components,
                   std::array<ThreadSettings, N>& settings) noexcept {
  const bool priority = std::strcmp(option, "--priority") == 0;
  const char* name = nullptr;
  std::size_t length = 0;
  int value = 0;
  const int low = priority ? kMinPriority : 0;
  const int high = priority ? kMaxPriority : CPU_SETSIZE - 1;
  if (!parseSetting(text, name, length, value, low, high)) {
    std::fprintf(stderr, "earl: %s %s refused: expected [SUBSYSTEM=]N with N a whole number from %d to %d\n", option,
                 text, low, high);
    return false;
  }
  bool found = false;
  for (std::size_t i = 0; i < N; ++i) {
    const char* own = components[i]->name();
    if (name != nullptr && (std::strncmp(own, name, length) != 0 || own[length] != '\0')) continue;
    found = true;
    (priority ? settings[i].priority : settings[i].cpu) = value;
  }
  if (!found) {
    std::fprintf(stderr, "earl: %s %s refused: no subsystem %.*s\n", option, text, static_cast<int>(length), name);
    return false;
  }
  return true;
}

/// Applies ``settings`` to the calling thread, the thread of ``component``. false when the
/// system refuses one; ``message`` then holds the line that says which and why.
inline bool applyThreadSettings(const ThreadSettings& settings, const char* component, char* message,
                                std::size_t size) noexcept {
  if (settings.cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(static_cast<std::size_t>(settings.cpu), &set);
    const int error = pthread_setaffinity_np(pthread_self(), sizeof set, &set);
    if (error != 0) {
      std::snprintf(message, size, "earl: subsystem %s: --cpu %d refused: %s (%s)", component, settings.cpu,
                    detail::errorName(error),
                    error == EINVAL ? "no such CPU, or not one this process may use" : "affinity not permitted");
      return false;
    }
  }
  if (settings.priority > 0) {
    sched_param param{};
    param.sched_priority = settings.priority;
    const int error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
    if (error != 0) {
      if (error == EPERM) {
        std::snprintf(message, size,
                      "earl: subsystem %s: --priority %d (SCHED_FIFO) refused: %s (needs CAP_SYS_NICE or an "
                      "RLIMIT_RTPRIO of at least %d)",
                      component, settings.priority, detail::errorName(error), settings.priority);
      } else {
        std::snprintf(message, size, "earl: subsystem %s: --priority %d (SCHED_FIFO) refused: %s", component,
                      settings.priority, detail::errorName(error));
      }
      return false;
    }
  }
  return true;
}

/// --mlockall: every page of the process, now and later, stays in memory (no page fault in a
/// cycle). false with the line that says why when the system refuses.
inline bool lockAllMemory(char* message, std::size_t size) noexcept {
  if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) return true;
  const int error = errno;
  std::snprintf(message, size, "earl: --mlockall refused: %s (%s)", detail::errorName(error),
                error == EPERM || error == ENOMEM ? "needs CAP_IPC_LOCK or a larger RLIMIT_MEMLOCK" : "mlockall failed");
  return false;
}

}  // namespace earl
