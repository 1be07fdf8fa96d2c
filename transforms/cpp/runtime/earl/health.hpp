// earl runtime: the health of a subsystem's partial transition functions (pf), read by the
// built-in predicates behaviourOk() and inError(). Part of earl-m2t's C++ target;
// header-only, C++17.
//
// A pf fails in an iteration when its user code calls fail(reason), when its execute()
// throws (caught here, at the pf's boundary), or, under NonFinite::error, when it writes a
// non-finite number (NaN, +-inf) into an output buffer it writes. A failed pf stays failed
// until its subsystem enters a state (a transition is taken, self-transitions included).
//   behaviourOk(): no pf of the current behaviour has failed since the state was entered.
//   inError():     the current behaviour's ec held in this iteration (written right after ec
//                  is evaluated; false in a state's first iteration).
// No heap and no lock on the failure path: a reason is a const char*; an exception's what()
// is copied into a fixed buffer.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <type_traits>

#include "earl/component.hpp"
#include "earl/types.hpp"

namespace earl {

// ---- every number of a value is finite (NaN and +-inf are not)

inline bool allFinite(double value) noexcept { return std::isfinite(value); }
inline bool allFinite(float value) noexcept { return std::isfinite(value); }
inline bool allFinite(long double value) noexcept { return std::isfinite(value); }
template <class T>
std::enable_if_t<std::is_integral_v<T> || std::is_enum_v<T>, bool> allFinite(T) noexcept {
  return true;
}
template <std::size_t Capacity>
bool allFinite(const String<Capacity>&) noexcept {
  return true;
}
template <class T, std::size_t N>
bool allFinite(const std::array<T, N>& values) noexcept {
  for (const T& value : values) {
    if (!allFinite(value)) return false;
  }
  return true;
}
template <class T, std::size_t Capacity>
bool allFinite(const BoundedArray<T, Capacity>& values) noexcept {
  for (const T& value : values) {
    if (!allFinite(value)) return false;
  }
  return true;
}

/// allFinite() of any value: the overloads above, and those generated beside each dataType
/// (found by argument-dependent lookup).
template <class T>
bool finite(const T& value) noexcept {
  return allFinite(value);
}

/// A failure's reason, copied (cut at Capacity - 1 bytes) into storage of its own.
class Reason {
 public:
  static constexpr std::size_t Capacity = 160;
  const char* copy(const char* text) noexcept {
    std::size_t n = 0;
    if (text != nullptr) {
      while (n + 1 < Capacity && text[n] != '\0') {
        text_[n] = text[n];
        ++n;
      }
    }
    text_[n] = '\0';
    return text_.data();
  }
  const char* c_str() const noexcept { return text_.data(); }

 private:
  std::array<char, Capacity> text_{};
};

/// Runs ``pf.execute()``; the reason it failed (its exception's what(), copied into
/// ``reason``, or what it passed to fail()), nullptr when it did not. A pf whose execute()
/// is declared noexcept cannot be protected: an exception leaving it ends the process.
template <class Pf>
const char* runGuarded(Pf& pf, Reason& reason) noexcept {
  try {
    pf.execute();
  } catch (const std::exception& e) {
    pf.takeFailure();
    return reason.copy(e.what());
  } catch (...) {
    pf.takeFailure();
    return "an exception that is not a std::exception";
  }
  return pf.takeFailure();
}

/// The health of one subsystem: which of its pf failed since its current state was entered,
/// and whether the current behaviour's ec held in the last iteration.
class Health {
 public:
  /// The built-in predicate inError().
  bool inError() const noexcept { return inError_; }
  /// The built-in predicate behaviourOk().
  bool behaviourOk() const noexcept { return failed_ == 0; }
  /// States entered so far (the initial one included).
  std::uint64_t entries() const noexcept { return entries_; }

 protected:
  /// The pf number ``pf`` failed; whether it is its first failure since the state was
  /// entered (the one to report). pf from 63 on share one flag.
  bool markFailed(std::size_t pf) noexcept {
    const std::uint64_t bit = std::uint64_t{1} << (pf < 63 ? pf : 63);
    const bool first = (failed_ & bit) == 0;
    failed_ |= bit;
    return first;
  }
  void setInError(bool value) noexcept { inError_ = value; }
  void entered() noexcept {
    failed_ = 0;
    inError_ = false;
    ++entries_;
  }

 private:
  std::uint64_t failed_ = 0;
  std::uint64_t entries_ = 0;
  bool inError_ = false;
};

}  // namespace earl
