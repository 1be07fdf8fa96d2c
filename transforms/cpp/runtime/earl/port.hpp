// earl runtime: input and output buffers (Orocos-style ports) and the channels of links.
// Part of earl-m2t's C++ target; header-only, C++17.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace earl {

/// One link: a single-producer single-consumer "latest value" mailbox (a triple buffer).
/// write() and read() are wait-free, never allocate and never lock, so the two ends may
/// run in different threads. read() returns true when a value written since the last
/// read() was delivered (the Orocos RTT NewData case).
template <class T>
class Channel {
 public:
  Channel() noexcept = default;
  Channel(const Channel&) = delete;
  Channel& operator=(const Channel&) = delete;

  void write(const T& value) noexcept {
    slots_[back_] = value;
    const unsigned previous = middle_.exchange(back_ | kFresh, std::memory_order_acq_rel);
    back_ = previous & kIndex;
  }

  bool read(T& out) noexcept {
    if ((middle_.load(std::memory_order_acquire) & kFresh) == 0u) return false;
    const unsigned previous = middle_.exchange(front_, std::memory_order_acq_rel);
    front_ = previous & kIndex;
    out = slots_[front_];
    return true;
  }

 private:
  static constexpr unsigned kFresh = 4u;
  static constexpr unsigned kIndex = 3u;
  std::array<T, 3> slots_{};
  unsigned back_ = 0;   // the producer's slot
  unsigned front_ = 1;  // the consumer's slot
  std::atomic<unsigned> middle_{2u};
};

/// An Input Buffer (ib): ``msg`` holds the last value received; receive() takes the
/// newest value of every linked channel (in link order) and sets newData().
template <class T, std::size_t MaxLinks = 1>
class InputPort {
 public:
  using value_type = T;

  /// Wiring, at initialisation only; false when more than MaxLinks links are connected.
  bool connect(Channel<T>& channel) noexcept {
    if (count_ == MaxLinks) return false;
    links_[count_++] = &channel;
    return true;
  }

  /// EARL receive(): newData() is true until the next receive() when this one delivered
  /// a value; otherwise msg() keeps the previous value and newData() is false.
  bool receive() noexcept {
    bool fresh = false;
    for (std::size_t i = 0; i < count_; ++i) {
      if (links_[i]->read(msg_)) fresh = true;
    }
    newData_ = fresh;
    if (fresh) ++received_;
    return fresh;
  }

  const T& msg() const noexcept { return msg_; }
  bool newData() const noexcept { return newData_; }
  std::uint64_t received() const noexcept { return received_; }
  std::size_t links() const noexcept { return count_; }

 private:
  T msg_{};
  bool newData_ = false;
  std::uint64_t received_ = 0;
  std::array<Channel<T>*, MaxLinks> links_{};
  std::size_t count_ = 0;
};

/// An Output Buffer (ob): pf write msg(); send() copies it to every linked channel.
template <class T, std::size_t MaxLinks = 1>
class OutputPort {
 public:
  using value_type = T;

  bool connect(Channel<T>& channel) noexcept {
    if (count_ == MaxLinks) return false;
    links_[count_++] = &channel;
    return true;
  }

  /// EARL send(): the current msg() goes to every linked Input Buffer.
  void send() noexcept {
    for (std::size_t i = 0; i < count_; ++i) links_[i]->write(msg_);
    ++sent_;
  }

  T& msg() noexcept { return msg_; }
  const T& msg() const noexcept { return msg_; }
  std::uint64_t sent() const noexcept { return sent_; }
  std::size_t links() const noexcept { return count_; }

 private:
  T msg_{};
  std::uint64_t sent_ = 0;
  std::array<Channel<T>*, MaxLinks> links_{};
  std::size_t count_ = 0;
};

}  // namespace earl
