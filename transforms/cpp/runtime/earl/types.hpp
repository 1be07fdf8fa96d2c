// earl runtime: value types of generated dataTypes (fixed-capacity, no heap).
// Part of earl-m2t's C++ target; header-only, C++17.
#pragma once

#include <array>
#include <cstddef>
#include <cstring>

namespace earl {

/// A string with a fixed capacity: the EARL primitive String (no heap).
/// Text longer than Capacity is cut at Capacity bytes.
template <std::size_t Capacity>
class String {
 public:
  String() noexcept = default;
  String(const char* text) noexcept { assign(text); }  // NOLINT: implicit, like std::string

  void assign(const char* text) noexcept {
    size_ = 0;
    if (text != nullptr) {
      while (size_ < Capacity && text[size_] != '\0') {
        data_[size_] = text[size_];
        ++size_;
      }
    }
    data_[size_] = '\0';
  }
  String& operator=(const char* text) noexcept {
    assign(text);
    return *this;
  }
  const char* c_str() const noexcept { return data_.data(); }
  std::size_t size() const noexcept { return size_; }
  bool empty() const noexcept { return size_ == 0; }
  static constexpr std::size_t capacity() noexcept { return Capacity; }
  char operator[](std::size_t i) const noexcept { return data_[i]; }

  friend bool operator==(const String& a, const String& b) noexcept {
    return a.size_ == b.size_ && std::memcmp(a.data_.data(), b.data_.data(), a.size_) == 0;
  }
  friend bool operator!=(const String& a, const String& b) noexcept { return !(a == b); }

 private:
  std::array<char, Capacity + 1> data_{};
  std::size_t size_ = 0;
};

/// A variable-length array with a fixed capacity: ``[*]``, ``[0..n]`` and optional ``[0..1]``
/// fields. Storage is inline; push_back() beyond the capacity returns false and drops the value.
template <class T, std::size_t Capacity>
class BoundedArray {
 public:
  std::size_t size() const noexcept { return size_; }
  bool empty() const noexcept { return size_ == 0; }
  static constexpr std::size_t capacity() noexcept { return Capacity; }
  void clear() noexcept { size_ = 0; }
  bool push_back(const T& value) noexcept {
    if (size_ == Capacity) return false;
    items_[size_++] = value;
    return true;
  }
  bool resize(std::size_t n) noexcept {
    if (n > Capacity) return false;
    for (std::size_t i = size_; i < n; ++i) items_[i] = T{};
    size_ = n;
    return true;
  }
  T& operator[](std::size_t i) noexcept { return items_[i]; }
  const T& operator[](std::size_t i) const noexcept { return items_[i]; }
  T& front() noexcept { return items_[0]; }
  const T& front() const noexcept { return items_[0]; }
  T* begin() noexcept { return items_.data(); }
  T* end() noexcept { return items_.data() + size_; }
  const T* begin() const noexcept { return items_.data(); }
  const T* end() const noexcept { return items_.data() + size_; }

 private:
  std::array<T, Capacity> items_{};
  std::size_t size_ = 0;
};

}  // namespace earl
