// earl runtime: input and output buffers (Orocos-style ports) and the channels of links.
// Part of earl-m2t's C++ target; header-only, C++17.
#pragma once

#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "earl/wake.hpp"

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

  /// Stores ``value`` and wakes the reader (signal()).
  void write(const T& value) noexcept {
    store(value);
    signal();
  }
  /// Stores ``value`` without waking the reader yet (a gated link signals past its gate).
  void store(const T& value) noexcept {
    slots_[back_] = value;
    const unsigned previous = middle_.exchange(back_ | kFresh, std::memory_order_acq_rel);
    back_ = previous & kIndex;
  }
  /// Tells the reader's wake word that a value came (a system call only if it sleeps on it).
  void signal() noexcept {
    if (reader_ != nullptr) reader_->data(input_);
  }
  /// Wiring: the wake word of the component reading this channel (nullptr: none).
  void setReader(Wake* reader, std::uint64_t input = Wake::kAnyInput) noexcept {
    reader_ = reader;
    input_ = input;
  }

  /// A value written since the last read() waits (the consumer's side; does not take it).
  bool fresh() const noexcept { return (middle_.load(std::memory_order_acquire) & kFresh) != 0u; }
  /// A latest-value channel never overflows: a newer value replaces an unread one.
  std::uint64_t overflows() const noexcept { return 0; }

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
  Wake* reader_ = nullptr;
  std::uint64_t input_ = Wake::kAnyInput;  // the reader's input this channel delivers into (its bit)
};

/// One link into a queued Input Buffer: a single-producer single-consumer ring of Capacity
/// values in arrival order. write() and read() are wait-free and never allocate. A value
/// written when the ring is full is not stored and counted in overflows(): a loss is
/// reported, never silent (the Orocos RTT buffer connection with its drop count).
template <class T, std::size_t Capacity>
class QueueChannel {
  static_assert(Capacity > 0, "a queue holds at least one value");

 public:
  QueueChannel() noexcept = default;
  QueueChannel(const QueueChannel&) = delete;
  QueueChannel& operator=(const QueueChannel&) = delete;

  void write(const T& value) noexcept {
    store(value);
    signal();
  }
  void store(const T& value) noexcept {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail - head_.load(std::memory_order_acquire) == kSlots) {
      overflows_.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    slots_[tail % kSlots] = value;
    tail_.store(tail + 1, std::memory_order_release);
  }
  void signal() noexcept {
    if (reader_ != nullptr) reader_->data(input_);
  }
  void setReader(Wake* reader, std::uint64_t input = Wake::kAnyInput) noexcept {
    reader_ = reader;
    input_ = input;
  }

  /// The oldest value not read yet; false when the queue is empty.
  bool read(T& out) noexcept {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head == tail_.load(std::memory_order_acquire)) return false;
    out = slots_[head % kSlots];
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  bool fresh() const noexcept {
    return head_.load(std::memory_order_acquire) != tail_.load(std::memory_order_acquire);
  }
  std::uint64_t overflows() const noexcept { return overflows_.load(std::memory_order_relaxed); }

 private:
  static constexpr std::size_t kSlots = Capacity;
  std::array<T, Capacity> slots_{};
  std::atomic<std::size_t> head_{0};  // the consumer's index
  std::atomic<std::size_t> tail_{0};  // the producer's index
  std::atomic<std::uint64_t> overflows_{0};
  Wake* reader_ = nullptr;
  std::uint64_t input_ = Wake::kAnyInput;  // the reader's input this channel delivers into (its bit)
};

/// An Input Buffer (ib): ``msg`` holds the last value received. Queue == 0 (EARL's latest
/// value): receive() takes the newest value of every linked channel (in link order). Queue
/// == N: every link is a queue of N and receive() takes one value, the oldest of the first
/// link (in link order) that has one, so that each value is delivered once, in order.
template <class T, std::size_t MaxLinks = 1, std::size_t Queue = 0>
class InputPort {
 public:
  using value_type = T;
  using channel_type = std::conditional_t<Queue == 0, Channel<T>, QueueChannel<T, (Queue == 0 ? 1 : Queue)>>;

  /// Wiring, at initialisation only; false when more than MaxLinks links are connected. The
  /// channel learns the wake word of the component reading this port.
  bool connect(channel_type& channel) noexcept {
    if (count_ == MaxLinks) return false;
    links_[count_++] = &channel;
    channel.setReader(wake_, input_);
    return true;
  }

  /// Wiring, at initialisation only: the wake word of the component owning this port and the
  /// port's bit among its inputs (Wake::inputBit()), told to every channel connected before or
  /// after.
  void setWake(Wake& wake, std::uint64_t input = Wake::kAnyInput) noexcept {
    wake_ = &wake;
    input_ = input;
    for (std::size_t i = 0; i < count_; ++i) links_[i]->setReader(wake_, input_);
  }

  /// EARL receive(): newData() is true until the next receive() when this one delivered
  /// a value; otherwise msg() keeps the previous value and newData() is false.
  bool receive() noexcept {
    bool fresh = false;
    for (std::size_t i = 0; i < count_; ++i) {
      if (links_[i]->read(msg_)) {
        fresh = true;
        if constexpr (Queue != 0) break;  // one value per receive()
      }
    }
    newData_ = fresh;
    if (fresh) ++received_;
    return fresh;
  }

  /// A value waits on some link (what an obligatory input of a buffer group waits for).
  bool ready() const noexcept {
    for (std::size_t i = 0; i < count_; ++i) {
      if (links_[i]->fresh()) return true;
    }
    return false;
  }

  /// Values lost because a queue was full (always 0 for the latest value).
  std::uint64_t overflows() const noexcept {
    std::uint64_t lost = 0;
    for (std::size_t i = 0; i < count_; ++i) lost += links_[i]->overflows();
    return lost;
  }

  /// Values lost since the last call (the consumer's side reports them).
  std::uint64_t newOverflows() noexcept {
    const std::uint64_t total = overflows();
    const std::uint64_t lost = total - reported_;
    reported_ = total;
    return lost;
  }

  const T& msg() const noexcept { return msg_; }
  bool newData() const noexcept { return newData_; }
  std::uint64_t received() const noexcept { return received_; }
  std::size_t links() const noexcept { return count_; }

 private:
  T msg_{};
  bool newData_ = false;
  std::uint64_t received_ = 0;
  std::uint64_t reported_ = 0;
  std::array<channel_type*, MaxLinks> links_{};
  std::size_t count_ = 0;
  Wake* wake_ = nullptr;
  std::uint64_t input_ = Wake::kAnyInput;
};

/// An Output Buffer (ob): pf write msg(); send() copies it to every linked channel.
template <class T, std::size_t MaxLinks = 1>
class OutputPort {
 public:
  using value_type = T;

  /// Wiring to a Channel (latest value) or a QueueChannel (a queued Input Buffer).
  template <class LinkChannel>
  bool connect(LinkChannel& channel) noexcept {
    if (count_ == MaxLinks) return false;
    links_[count_++] = Sink{&channel, [](void* link, const T& value) noexcept {
                              static_cast<LinkChannel*>(link)->write(value);
                            }};
    return true;
  }

  /// EARL send(): the current msg() goes to every linked Input Buffer.
  void send() noexcept {
    for (std::size_t i = 0; i < count_; ++i) links_[i].write(links_[i].channel, msg_);
    ++sent_;
  }

  T& msg() noexcept { return msg_; }
  const T& msg() const noexcept { return msg_; }
  std::uint64_t sent() const noexcept { return sent_; }
  std::size_t links() const noexcept { return count_; }

 private:
  struct Sink {
    void* channel;
    void (*write)(void*, const T&) noexcept;
  };
  T msg_{};
  std::uint64_t sent_ = 0;
  std::array<Sink, MaxLinks> links_{};
  std::size_t count_ = 0;
};

}  // namespace earl
