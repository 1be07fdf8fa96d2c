// earl runtime: variable structure. The structure of a system (which agents run, which links
// carry data) switches at run time between named configurations, break-before-make:
//
//   0. decide   the coordinator's iteration ends (its sends done under the old structure)
//               and its next state names another configuration; it does not enter it yet;
//   1. close    every link of the old configuration that the new one lacks is closed at its
//               sender (later writes skip it, counted), except a link from an agent that
//               leaves to one that stays: it stays open until its sender has stopped, so what
//               a leaving agent sends until then (its last iterations) is delivered; the
//               agents that leave see leaving() true;
//   2. drain    a leaving agent stops at an iteration boundary once its control subsystem is
//               in a quiescent state and every link into it is empty; a receiver that stays
//               reads a closed link before the others, so nothing is reordered;
//   3. timeout  past the switch timeout the leaving agents are stopped anyway, and the values
//               still queued for them are cleared and reported as undelivered, per link;
//   4. open     the links from the stopped agents close, the joining agents are restarted
//               or resumed, the new links open, and the coordinator enters the new state and
//               runs its behaviour.
//
// Everything exists from initialisation: every agent of the general model is an object, every
// link a channel with a gate. A switch allocates nothing and takes no lock (atomics only); it
// runs inside the coordinator's updateHook(), polled once per iteration, and never blocks a
// subsystem. The deterministic executor counts the timeout in cycles of the coordinator's
// period, the threaded one on the steady clock.
// Part of earl-m2t's C++ target; header-only, C++17. Copied only for models with configurations.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cinttypes>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <type_traits>
#include <utility>

#include "earl/component.hpp"
#include "earl/port.hpp"
#include "earl/subsystem.hpp"
#include "earl/trace.hpp"

// Test-only: 0 builds a switch that stops a leaving agent at once, without waiting for its
// quiescence and its links to drain (what deactivating or disconnecting does). The tests use
// it to show that they detect the values such a switch loses.
#ifndef EARL_SWITCH_DRAIN
#define EARL_SWITCH_DRAIN 1
#endif
// Test-only: 0 builds a switch that closes a leaving agent's links to the agents that stay at the
// decision, as every other link (its last sends are then skipped): the tests use it to show that
// they detect those values.
#ifndef EARL_SWITCH_LINGER
#define EARL_SWITCH_LINGER 1
#endif
// Test-only: 0 builds a switch that forgets the value an Input Buffer took in a leaving agent's
// last iteration (the agent may stop before its pfs run on it, and a forced switch does not count
// it): the tests use it to show that they detect a value lost uncounted.
#ifndef EARL_SWITCH_SETTLE
#define EARL_SWITCH_SETTLE 1
#endif

namespace earl {

// ------------------------------------------------------------------ links

/// The sender-side gate of a variable link. A write enters the gate (counted in flight) and
/// goes to the channel only while the gate is open; once close() returned and quiet() holds,
/// no write of before the close can still reach the channel. A write the closed gate refuses
/// is counted (refused()): a value written on a closed link is never lost silently.
class Gate {
 public:
  bool enter() noexcept {
    writers_.fetch_add(1, std::memory_order_seq_cst);
    if (open_.load(std::memory_order_seq_cst)) return true;
    writers_.fetch_sub(1, std::memory_order_release);
    refused_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  /// Values written while the gate was closed.
  std::uint64_t refused() const noexcept { return refused_.load(std::memory_order_relaxed); }
  void leave() noexcept { writers_.fetch_sub(1, std::memory_order_release); }
  void open() noexcept { open_.store(true, std::memory_order_seq_cst); }
  void close() noexcept { open_.store(false, std::memory_order_seq_cst); }
  bool isOpen() const noexcept { return open_.load(std::memory_order_seq_cst); }
  /// No write is in flight.
  bool quiet() const noexcept { return writers_.load(std::memory_order_seq_cst) == 0; }

 private:
  std::atomic<bool> open_{true};
  std::atomic<std::uint32_t> writers_{0};
  std::atomic<std::uint64_t> refused_{0};
};

template <class Ch>
struct ChannelValue;
template <class T>
struct ChannelValue<Channel<T>> {
  using type = T;
};
template <class T, std::size_t N>
struct ChannelValue<QueueChannel<T, N>> {
  using type = T;
};

/// Whether a value type has an integral field ``seq`` (its number, by the convention of the
/// samples' commands): a value a switch loses is then named by it.
template <class T, class = void>
struct HasSeq : std::false_type {};
template <class T>
struct HasSeq<T, std::void_t<decltype(std::declval<const T&>().seq)>>
    : std::is_integral<std::decay_t<decltype(std::declval<const T&>().seq)>> {};
template <class T>
std::int64_t seqOf(const T& value) noexcept {
  if constexpr (HasSeq<T>::value) {
    return static_cast<std::int64_t>(value.seq);
  } else {
    (void)value;
    return -1;
  }
}

/// Told each value a switch lost (its seq, -1 for a type without one); ``context`` is the caller's.
using LostValue = void (*)(void* context, std::int64_t seq) noexcept;

/// A link that a configuration can close: the channel (a Channel or a QueueChannel, so that
/// an InputPort connects to it as to any link) behind a Gate. OutputPort::connect() takes it
/// as its sink, so every send() passes the gate.
template <class Ch>
class VariableLink : public Ch {
 public:
  using value_type = typename ChannelValue<Ch>::type;
  using channel_type = Ch;

  void write(const value_type& value) noexcept {
    if (!gate_.enter()) return;
    Ch::store(value);
    gate_.leave();
    Ch::signal();  // after leave(): a leaving reader also waits for the gate to be quiet
  }

  Gate& gate() noexcept { return gate_; }
  const Gate& gate() const noexcept { return gate_; }

  /// The receiver took a value of this link that its pfs have not run on yet: it is in the
  /// Input Buffer, read at the end of the receiver's last iteration, for its next one. Set by
  /// the receiving port's receive(), cleared by its settle() (after the pfs of the next
  /// iteration) or reset(), all in the receiver's thread, and by discard().
  bool held() const noexcept { return held_.load(std::memory_order_relaxed); }
  void hold(bool value, std::int64_t seq = -1) noexcept {
    heldSeq_ = seq;
    held_.store(value, std::memory_order_relaxed);
  }

  /// The consumer's side, only while the receiver does not run: empties the link and returns
  /// the values it lost: the one its receiver had taken but not processed, and those the link
  /// held (a latest-value link holds at most one); ``each`` (when given) is told each of them.
  std::uint64_t discard(LostValue each = nullptr, void* context = nullptr) noexcept {
    std::uint64_t n = 0;
    if (held()) {
      ++n;
      if (each != nullptr) each(context, heldSeq_);
    }
    hold(false);
    value_type dropped{};
    while (Ch::read(dropped)) {
      ++n;
      if (each != nullptr) each(context, seqOf(dropped));
    }
    return n;
  }

 private:
  Gate gate_;
  std::atomic<bool> held_{false};
  std::int64_t heldSeq_ = -1;  // written before held_, by the receiver; read once it is parked
};

/// An Input Buffer of a model with configurations: InputPort's semantics, except that links
/// closed by a switch are read before the open ones (so a receiver that stays empties a closed
/// link before reading a link opened at the same switch), and reset() (reactivation).
template <class T, std::size_t MaxLinks = 1, std::size_t Queue = 0>
class SwitchedInputPort {
 public:
  using value_type = T;
  using channel_type = std::conditional_t<Queue == 0, Channel<T>, QueueChannel<T, (Queue == 0 ? 1 : Queue)>>;

  /// A link present in every configuration; at initialisation only.
  bool connect(channel_type& channel) noexcept { return add(channel, nullptr, nullptr); }
  /// A variable link; at initialisation only.
  bool connect(VariableLink<channel_type>& link) noexcept { return add(link, &link.gate(), &link); }
  /// The wake word of the component owning this port (InputPort::setWake()).
  void setWake(Wake& wake, std::uint64_t input = Wake::kAnyInput) noexcept {
    wake_ = &wake;
    input_ = input;
    for (std::size_t i = 0; i < count_; ++i) links_[i]->setReader(wake_, input_);
  }

  bool receive() noexcept {
    bool fresh = false;
    std::size_t from = 0;
    for (int pass = 0; pass < 2; ++pass) {
      const bool closed = pass == 0;
      for (std::size_t i = 0; i < count_; ++i) {
        if ((gates_[i] != nullptr && !gates_[i]->isOpen()) != closed) continue;
        if (links_[i]->read(msg_)) {
          fresh = true;
          from = i;
          if constexpr (Queue != 0) {
            pass = 2;
            break;
          }
        }
      }
    }
    newData_ = fresh;
    if (fresh) {
      ++received_;
#if EARL_SWITCH_SETTLE
      if (variable_[from] != nullptr) variable_[from]->hold(true, seqOf(msg_));  // msg() holds its value
#else
      (void)from;
#endif
    }
    return fresh;
  }

  bool ready() const noexcept {
    for (std::size_t i = 0; i < count_; ++i) {
      if (links_[i]->fresh()) return true;
    }
    return false;
  }

  std::uint64_t overflows() const noexcept {
    std::uint64_t lost = 0;
    for (std::size_t i = 0; i < count_; ++i) lost += links_[i]->overflows();
    return lost;
  }

  std::uint64_t newOverflows() noexcept {
    const std::uint64_t total = overflows();
    const std::uint64_t lost = total - reported_;
    reported_ = total;
    return lost;
  }

  /// The pfs of an iteration ran on what the last receive() took (SwitchedSubsystem::iterate()).
  void settle() noexcept {
    for (std::size_t i = 0; i < count_; ++i) {
      if (variable_[i] != nullptr) variable_[i]->hold(false);
    }
  }

  /// Reactivation: msg() back to its initial value (restart) or kept (resume); no new data.
  void reset(bool restart) noexcept {
    if (restart) msg_ = T{};
    newData_ = false;
    for (std::size_t i = 0; i < count_; ++i) {
      if (variable_[i] != nullptr) variable_[i]->hold(false);
    }
  }

  const T& msg() const noexcept { return msg_; }
  bool newData() const noexcept { return newData_; }
  std::uint64_t received() const noexcept { return received_; }
  std::size_t links() const noexcept { return count_; }

 private:
  bool add(channel_type& channel, const Gate* gate, VariableLink<channel_type>* variable) noexcept {
    if (count_ == MaxLinks) return false;
    gates_[count_] = gate;
    variable_[count_] = variable;
    links_[count_++] = &channel;
    channel.setReader(wake_, input_);
    return true;
  }

  T msg_{};
  bool newData_ = false;
  std::uint64_t received_ = 0;
  std::uint64_t reported_ = 0;
  std::array<channel_type*, MaxLinks> links_{};
  std::array<const Gate*, MaxLinks> gates_{};
  std::array<VariableLink<channel_type>*, MaxLinks> variable_{};
  std::size_t count_ = 0;
  Wake* wake_ = nullptr;
  std::uint64_t input_ = Wake::kAnyInput;
};

/// Calls ``object.reset()`` when the class has one (the optional hook of user pf classes).
template <class T, class = void>
struct HasReset : std::false_type {};
template <class T>
struct HasReset<T, std::void_t<decltype(std::declval<T&>().reset())>> : std::true_type {};
template <class T>
void resetIfAble(T& object) noexcept {
  if constexpr (HasReset<T>::value) object.reset();
}

// ------------------------------------------------------------------ observer

struct SwitchLatency {
  std::uint64_t cycles;      // coordinator iterations from the decision to the open
  std::int64_t nanoseconds;  // on the steady clock (threaded executor); 0 when counted in cycles
  bool clock;                // measured on the clock (true) or in cycles
  bool forced;               // the switch timeout passed: the leaving agents were stopped where they were
};

/// An Observer that is also told about switches and the values a switch could not deliver.
class SwitchObserver : public Observer {
 public:
  virtual void switched(const char* from, const char* to, const SwitchLatency& latency) noexcept {
    (void)from, (void)to, (void)latency;
  }
  /// ``count`` values of ``link`` were cleared at a switch (its timeout passed): those queued,
  /// and the one its receiver had taken and not yet processed.
  virtual void undelivered(const char* link, std::uint64_t count) noexcept { (void)link, (void)count; }
  /// One of them, before the count: its seq (-1 when its type has no field seq).
  virtual void undeliveredValue(const char* link, std::int64_t seq) noexcept { (void)link, (void)seq; }
  /// At the end of a run: ``count`` values were written on ``link`` while it was closed (its
  /// configuration lacked it), and went nowhere.
  virtual void writtenClosed(const char* link, std::uint64_t count) noexcept { (void)link, (void)count; }
};

/// PrintObserver's lines, and one line per switch (`` (forced)`` after it when its timeout
/// stopped the leaving agents) and per link with undelivered values.
class SwitchPrintObserver final : public SwitchObserver {
 public:
  void stateChanged(const Component& component, const char* from, const char* to, const char* via,
                    std::uint64_t step) noexcept override {
    lines_.stateChanged(component, from, to, via, step);
  }
  void overflowed(const Component& component, const char* buffer, std::uint64_t lost,
                  std::uint64_t step) noexcept override {
    lines_.overflowed(component, buffer, lost, step);
  }
  void pfFailed(const Component& component, const char* pf, const char* reason,
                std::uint64_t step) noexcept override {
    lines_.pfFailed(component, pf, reason, step);
  }
  void nonFinite(const Component& component, const char* pf, const char* buffer,
                 std::uint64_t step) noexcept override {
    lines_.nonFinite(component, pf, buffer, step);
  }
  void switched(const char* from, const char* to, const SwitchLatency& latency) noexcept override {
    const char* forced = latency.forced ? " (forced)" : "";
    if (latency.clock) {
      std::printf("switch %s -> %s in %.3f ms%s\n", from, to, static_cast<double>(latency.nanoseconds) / 1e6, forced);
    } else {
      std::printf("switch %s -> %s in %" PRIu64 " cycles%s\n", from, to, latency.cycles, forced);
    }
  }
  void undelivered(const char* link, std::uint64_t count) noexcept override {
    std::printf("link %s: %" PRIu64 " value(s) undelivered at switch\n", link, count);
  }
  void undeliveredValue(const char* link, std::int64_t seq) noexcept override {
    if (seq >= 0) std::printf("link %s: seq %" PRId64 " undelivered at switch\n", link, seq);
  }
  void writtenClosed(const char* link, std::uint64_t count) noexcept override {
    std::printf("link %s: %" PRIu64 " value(s) written while closed\n", link, count);
  }

 private:
  PrintObserver lines_;
};

// ------------------------------------------------------------------ agents

class Switch;
class AgentSlot;

/// What a switched subsystem asks of the switch: the coordinator begins a switch and polls it
/// once per iteration; a leaving agent asks whether every closed link into it is drained.
/// Switch (below) does it in one process; earl/switch_protocol.hpp over a transport (ROS
/// topics, RTT ports) between processes or components.
class SwitchControl {
 public:
  /// 0 + 1 (decide, close): false when ``configuration`` is the current one (no switch).
  virtual bool begin(std::size_t configuration) noexcept = 0;
  /// true once the new configuration is open (the coordinator then enters its new state).
  virtual bool poll() noexcept = 0;
  /// Every closed link into ``agent`` is empty and no write to it is in flight.
  virtual bool drained(const AgentSlot& agent) const noexcept = 0;
  /// No value of a closed link into ``agent`` waits in an Input Buffer for the pfs of the
  /// agent's next iteration (taken by the last one): the agent may stop without losing it.
  virtual bool settled(const AgentSlot& agent) const noexcept = 0;
  /// The coordinator (its period sets the polling interval); set by SwitchedSubsystem.
  virtual void setCoordinator(const Component* coordinator) noexcept { (void)coordinator; }

 protected:
  SwitchControl() = default;
  ~SwitchControl() = default;
};

/// One subsystem of a variable agent, as its agent and the switch see it. ``busy`` is set
/// while the subsystem is inside an iteration (or deciding whether to run one).
class AgentMember {
 public:
  bool busy() const noexcept { return busy_.load(std::memory_order_seq_cst); }

 private:
  friend class AgentSlot;
  template <class>
  friend class SwitchedSubsystem;
  std::atomic<bool> busy_{false};
  Wake* wake_ = nullptr;  // the subsystem's: woken when its agent's phase changes
  AgentMember* next_ = nullptr;
  std::uint32_t epoch_ = 0;
};

enum class Reactivation : std::uint8_t { restart, resume };

/// The run-time presence of one variable agent: active, leaving (a switch removes it; its
/// subsystems see leaving() true) or stopped. Its subsystems are linked in at initialisation.
class AgentSlot {
 public:
  enum class Phase : std::uint8_t { active, leaving, stopped };

  explicit AgentSlot(const char* name, Reactivation reactivation = Reactivation::restart) noexcept
      : name_(name), reactivation_(reactivation) {}
  AgentSlot(const AgentSlot&) = delete;
  AgentSlot& operator=(const AgentSlot&) = delete;

  const char* name() const noexcept { return name_; }
  Reactivation reactivation() const noexcept { return reactivation_; }
  Phase phase() const noexcept { return phase_.load(std::memory_order_seq_cst); }
  std::uint32_t epoch() const noexcept { return epoch_.load(std::memory_order_acquire); }
  /// Activations so far (the initial one not counted).
  std::uint64_t activations() const noexcept { return epoch(); }

  /// At initialisation: what to do with the agent's own links (between its subsystems) when
  /// it is activated again; ``clear(agent, sw)`` empties them, reporting queued values with
  /// Switch::report().
  void setClear(void* agent, void (*clear)(void*, Switch&) noexcept) noexcept {
    agent_ = agent;
    clear_ = clear;
  }

  /// Every subsystem of the agent is between two iterations and will not start one.
  bool parked() const noexcept {
    if (phase() != Phase::stopped) return false;
    for (const AgentMember* m = members_; m != nullptr; m = m->next_) {
      if (m->busy()) return false;
    }
    return true;
  }

 private:
  friend class Switch;
  template <std::size_t>
  friend class SwitchMember;
  template <class>
  friend class SwitchedSubsystem;

  void add(AgentMember& member) noexcept {
    member.next_ = members_;
    members_ = &member;
  }
  void set(Phase phase) noexcept {
    phase_.store(phase, std::memory_order_seq_cst);
    wakeMembers();
  }
  void activate() noexcept {
    epoch_.fetch_add(1, std::memory_order_release);
    set(Phase::active);
  }
  /// A sleeping subsystem of the agent looks at the new phase (leaving, stopped, active).
  void wakeMembers() noexcept {
    for (AgentMember* m = members_; m != nullptr; m = m->next_) {
      if (m->wake_ != nullptr) m->wake_->notify();
    }
  }

  const char* name_;
  Reactivation reactivation_;
  std::atomic<Phase> phase_{Phase::active};
  std::atomic<std::uint32_t> epoch_{0};
  AgentMember* members_ = nullptr;
  SwitchControl* switch_ = nullptr;
  void* agent_ = nullptr;
  void (*clear_)(void*, Switch&) noexcept = nullptr;
};

// ------------------------------------------------------------------ the switch

/// One variable link as the switch sees it: its gate, the agent receiving it (nullptr: an
/// agent present in every configuration) and type-erased access to its channel.
struct SwitchLink {
  const char* name;
  Gate* gate;
  AgentSlot* receiver;
  void* channel;
  bool (*fresh)(const void* channel) noexcept;
  bool (*held)(const void* channel) noexcept;
  std::uint64_t (*discard)(void* channel, LostValue each, void* context) noexcept;
};

template <class Ch>
SwitchLink switchLink(const char* name, VariableLink<Ch>& link, AgentSlot* receiver) noexcept {
  return SwitchLink{name, &link.gate(), receiver, &link,
                    [](const void* c) noexcept { return static_cast<const VariableLink<Ch>*>(c)->fresh(); },
                    [](const void* c) noexcept { return static_cast<const VariableLink<Ch>*>(c)->held(); },
                    [](void* c, LostValue each, void* context) noexcept {
                      return static_cast<VariableLink<Ch>*>(c)->discard(each, context);
                    }};
}

/// The configurations, as constant tables (generated): which variable agents and which
/// variable links each holds, row-major, its switch timeout (ns, for switching into it), and
/// the variable agents at the two ends of each variable link.
struct SwitchTables {
  const char* const* names;
  std::size_t configurations;
  const bool* agents;  // [configuration * agentCount + agent]
  std::size_t agentCount;
  const bool* links;  // [configuration * linkCount + link]
  std::size_t linkCount;
  const std::int64_t* timeoutNs;  // [configuration]
  const std::int16_t* linkSender;    // [link]: the variable agent sending it, -1 for an agent of every configuration
  const std::int16_t* linkReceiver;  // [link]: the variable agent receiving it, likewise

  bool hasAgent(std::size_t c, std::size_t a) const noexcept { return agents[c * agentCount + a]; }
  bool hasLink(std::size_t c, std::size_t l) const noexcept { return links[c * linkCount + l]; }
  /// Configuration ``c`` holds the agent ``a`` (-1: an agent of every configuration).
  bool holds(std::size_t c, std::int16_t a) const noexcept { return a < 0 || hasAgent(c, static_cast<std::size_t>(a)); }
  /// A switch from ``from`` to ``to`` keeps the link ``l`` open until its sender has stopped:
  /// ``to`` lacks it, its sender leaves and its receiver stays (earl_m2t.model.variability.lingers).
  bool lingers(std::size_t from, std::size_t to, std::size_t l) const noexcept {
#if EARL_SWITCH_LINGER
    if (!hasLink(from, l) || hasLink(to, l)) return false;
    const std::int16_t sender = linkSender[l], receiver = linkReceiver[l];
    return sender >= 0 && holds(from, sender) && !holds(to, sender) && holds(from, receiver) && holds(to, receiver);
#else
    (void)from, (void)to, (void)l;
    return false;
#endif
  }
};

/// The switch protocol (see the top of this file), driven by the coordinator subsystem.
class Switch final : public SwitchControl {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

  Switch(const SwitchTables& tables, AgentSlot* const* agents, SwitchLink* links) noexcept
      : tables_(tables), agents_(agents), links_(links) {
    for (std::size_t a = 0; a < tables_.agentCount; ++a) agents_[a]->switch_ = this;
  }
  Switch(const Switch&) = delete;
  Switch& operator=(const Switch&) = delete;

  /// At initialisation: the links and agents of ``configuration`` open and active, the
  /// others closed and stopped.
  void start(std::size_t configuration) noexcept {
    current_ = configuration;
    for (std::size_t l = 0; l < tables_.linkCount; ++l) {
      if (hasLink(configuration, l)) {
        links_[l].gate->open();
      } else {
        links_[l].gate->close();
      }
    }
    for (std::size_t a = 0; a < tables_.agentCount; ++a) {
      agents_[a]->set(hasAgent(configuration, a) ? AgentSlot::Phase::active : AgentSlot::Phase::stopped);
    }
  }

  /// The deterministic executor: the timeout is counted in iterations of the coordinator,
  /// ``period`` each. Otherwise (the default) it is measured on the steady clock.
  void countCycles(bool cycles) noexcept { cycles_ = cycles; }
  void setObserver(SwitchObserver* observer) noexcept { observer_ = observer; }
  void setCoordinator(const Component* coordinator) noexcept override { coordinator_ = coordinator; }

  std::size_t current() const noexcept { return current_; }
  const char* name(std::size_t configuration) const noexcept { return tables_.names[configuration]; }
  bool switching() const noexcept { return target_ != kNone; }
  std::uint64_t switches() const noexcept { return switches_; }
  std::uint64_t timeouts() const noexcept { return timeouts_; }
  std::uint64_t undelivered() const noexcept { return undelivered_; }
  const SwitchLatency& lastLatency() const noexcept { return last_; }

  /// 0 + 1 (decide, close), by the coordinator at the end of its iteration: false when
  /// ``configuration`` is the current one (no switch).
  bool begin(std::size_t configuration) noexcept override {
    if (configuration == current_ || configuration >= tables_.configurations) return false;
    target_ = configuration;
    polls_ = 0;
    forced_ = false;
    if (!cycles_) started_ = Clock::now();
    for (std::size_t l = 0; l < tables_.linkCount; ++l) {
      if (hasLink(current_, l) && !hasLink(target_, l) && !tables_.lingers(current_, target_, l)) links_[l].gate->close();
    }
    for (std::size_t a = 0; a < tables_.agentCount; ++a) {
      if (leaves(a)) agents_[a]->set(AgentSlot::Phase::leaving);
    }
    return true;
  }

  /// 2 + 3 + 4, by the coordinator once per iteration while switching: true once the new
  /// configuration is open (the coordinator then enters its new state).
  bool poll() noexcept override {
    if (!switching()) return true;
    ++polls_;
    if (!leftAll()) {
      if (!forced_ && !timedOut()) return false;
      if (!forced_) {
        forced_ = true;
        ++timeouts_;
        for (std::size_t a = 0; a < tables_.agentCount; ++a) {
          if (leaves(a)) agents_[a]->set(AgentSlot::Phase::stopped);
        }
      }
      if (!leftAll()) return false;  // a subsystem is still inside its last iteration
    }
    for (std::size_t l = 0; l < tables_.linkCount; ++l) {
      const SwitchLink& link = links_[l];
      const std::size_t receiver = link.receiver != nullptr ? index(*link.receiver) : kNone;
      if (receiver == kNone || !leaves(receiver)) continue;
      Lost lost{observer_, link.name};
      report(link.name, link.discard(link.channel, &Lost::each, &lost));
    }
    open();
    return true;
  }

  /// Drained: every closed link into ``agent`` is empty and no write to it is in flight.
  bool drained(const AgentSlot& agent) const noexcept override {
    for (std::size_t l = 0; l < tables_.linkCount; ++l) {
      const SwitchLink& link = links_[l];
      if (link.receiver != &agent || link.gate->isOpen()) continue;
      if (!link.gate->quiet() || link.fresh(link.channel)) return false;
    }
    return true;
  }

  bool settled(const AgentSlot& agent) const noexcept override {
    for (std::size_t l = 0; l < tables_.linkCount; ++l) {
      const SwitchLink& link = links_[l];
      if (link.receiver == &agent && !link.gate->isOpen() && link.held(link.channel)) return false;
    }
    return true;
  }

  /// At the end of a run: the values written on each variable link while it was closed, told
  /// to the observer.
  void reportWrittenClosed() const noexcept {
    if (observer_ == nullptr) return;
    for (std::size_t l = 0; l < tables_.linkCount; ++l) {
      const std::uint64_t refused = links_[l].gate->refused();
      if (refused > 0) observer_->writtenClosed(links_[l].name, refused);
    }
  }

  /// Values cleared on ``link`` at this switch: counted and told to the observer.
  void report(const char* link, std::uint64_t count) noexcept {
    if (count == 0) return;
    undelivered_ += count;
    if (observer_ != nullptr) observer_->undelivered(link, count);
  }

 private:
  /// Tells the observer each value a forced switch clears on one link.
  struct Lost {
    SwitchObserver* observer;
    const char* link;
    static void each(void* context, std::int64_t seq) noexcept {
      const Lost& lost = *static_cast<const Lost*>(context);
      if (lost.observer != nullptr) lost.observer->undeliveredValue(lost.link, seq);
    }
  };

  bool hasAgent(std::size_t c, std::size_t a) const noexcept { return tables_.hasAgent(c, a); }
  bool hasLink(std::size_t c, std::size_t l) const noexcept { return tables_.hasLink(c, l); }
  bool leaves(std::size_t a) const noexcept { return hasAgent(current_, a) && !hasAgent(target_, a); }
  bool joins(std::size_t a) const noexcept { return !hasAgent(current_, a) && hasAgent(target_, a); }
  std::size_t index(const AgentSlot& agent) const noexcept {
    for (std::size_t a = 0; a < tables_.agentCount; ++a) {
      if (agents_[a] == &agent) return a;
    }
    return kNone;
  }

  bool leftAll() const noexcept {
    for (std::size_t a = 0; a < tables_.agentCount; ++a) {
      if (leaves(a) && !agents_[a]->parked()) return false;
    }
    return true;
  }

  std::chrono::nanoseconds period() const noexcept {
    return coordinator_ != nullptr ? coordinator_->period() : std::chrono::nanoseconds(std::chrono::milliseconds(1));
  }

  /// The next poll would come after the timeout: stop the leaving agents now.
  bool timedOut() const noexcept {
    const std::int64_t timeout = tables_.timeoutNs[target_];
    if (timeout < 0) return false;
    const std::int64_t p = period().count() > 0 ? period().count() : 1;
    if (cycles_) return static_cast<std::int64_t>(polls_) >= (timeout + p - 1) / p;
    const auto elapsed = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - started_).count();
    return elapsed + p >= timeout;
  }

  void open() noexcept {
    for (std::size_t l = 0; l < tables_.linkCount; ++l) {
      if (tables_.lingers(current_, target_, l)) links_[l].gate->close();  // its sender has stopped
      if (!hasLink(current_, l) && hasLink(target_, l)) links_[l].gate->open();
    }
    for (std::size_t a = 0; a < tables_.agentCount; ++a) {
      if (!joins(a)) continue;
      AgentSlot& agent = *agents_[a];
      if (agent.clear_ != nullptr) agent.clear_(agent.agent_, *this);
      agent.activate();
    }
    last_ = SwitchLatency{polls_, 0, !cycles_, forced_};
    if (!cycles_) last_.nanoseconds = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - started_).count();
    const std::size_t from = current_;
    current_ = target_;
    target_ = kNone;
    ++switches_;
    if (observer_ != nullptr) observer_->switched(tables_.names[from], tables_.names[current_], last_);
  }

  const SwitchTables& tables_;
  AgentSlot* const* agents_;
  SwitchLink* links_;
  const Component* coordinator_ = nullptr;
  SwitchObserver* observer_ = nullptr;
  std::size_t current_ = 0;
  std::size_t target_ = kNone;
  bool cycles_ = false;
  bool forced_ = false;
  std::uint64_t polls_ = 0;
  Clock::time_point started_{};
  std::uint64_t switches_ = 0;
  std::uint64_t timeouts_ = 0;
  std::uint64_t undelivered_ = 0;
  SwitchLatency last_{0, 0, false, false};
};

// ------------------------------------------------------------------ subsystems

/// The base of every generated subsystem of a model with configurations (CRTP): Subsystem's
/// FSM and basic-behaviour loop (subsystem.hpp, same tables, same order of a step), plus
///   * membership of a variable agent: no iteration while the agent is stopped; the control
///     subsystem stops its agent at an iteration boundary once leaving, quiescent, drained and
///     settled (a value taken from a closed link in the last iteration has been through the
///     pfs of one more: Self::settleData() after the pfs of every iteration says so);
///     while leaving and drained, an event-driven subsystem waits for its minimal period only,
///     not for its obligatory inputs (the links the switch closed bring nothing more);
///     on its first iteration after a reactivation, a subsystem restarts (FSM at its initial
///     state, Self::resetData(true)) or resumes (Self::resetData(false));
///   * the coordinator: a transition to a state naming another configuration starts a switch
///     instead of entering the state; the state is entered once the switch has opened.
/// Self supplies the tables, the functions they point to, ``void resetData(bool restart)`` and
/// ``void settleData()`` (SwitchedInputPort::settle() of each of its inputs).
template <class Self>
class SwitchedSubsystem : public Component, public Health {
 public:
  SwitchedSubsystem(const char* name, const FsmTables<Self>& tables, const bool* quiescent = nullptr) noexcept
      : Component(name), tables_(tables), quiescent_(quiescent), current_(tables.initial) {}

  /// At initialisation: a subsystem of the variable agent ``agent``; ``control``: its
  /// control subsystem, whose states say when the agent may stop.
  void joinAgent(AgentSlot& agent, bool control) noexcept {
    agent_ = &agent;
    control_ = control;
    member_.wake_ = &wake();
    agent.add(member_);
  }

  /// At initialisation: the coordinator. ``configuration[state]`` is the index of the
  /// configuration the state names, -1 for none (the current one stays).
  void coordinate(SwitchControl& sw, const std::int16_t* configuration) noexcept {
    switch_ = &sw;
    configurations_ = configuration;
    sw.setCoordinator(this);
  }

  void startHook() noexcept override {
    if (started_) return;
    if (agent_ != nullptr && agent_->phase() == AgentSlot::Phase::stopped) return;  // at its activation
    started_ = true;
    if (agent_ != nullptr) member_.epoch_ = agent_->epoch();
    enter(tables_.initial, nullptr);
  }

  bool eventDriven() const noexcept override { return tables_.activations != nullptr; }

  bool ready(Clock::time_point now) noexcept override {
    if (!admit()) return false;
    const bool result = readyToRun(now);
    release();
    return result;
  }

  /// After ready() said no: sleep until activated while the agent is stopped; the next poll
  /// while a switch is pending; otherwise Subsystem::nextDeadline().
  Clock::time_point nextDeadline(Clock::time_point now, bool& onData) noexcept override {
    onData = false;
    if (agent_ != nullptr && agent_->phase() == AgentSlot::Phase::stopped) return Clock::time_point::max();
    if (pending_ != nullptr) return lastStart_ + period();
    if (tables_.activations == nullptr || !ran_) return now;
    const ActivationDef<Self>& a = tables_.activations[current_];
    const Clock::time_point earliest = lastStart_ + activationGap(a);
    if (now < earliest) return earliest;
    if (a.obligatory == nullptr) return now;
    onData = true;
    const std::int64_t timeout = entered_ ? a.firstTimeoutNs : a.nextTimeoutNs;
    return timeout >= 0 ? waitStart_ + std::chrono::nanoseconds(timeout) : Clock::time_point::max();
  }

  /// The obligatory inputs of the state; every input while the agent is leaving (its closed
  /// links' values decide when it may stop).
  std::uint64_t wakeInputs() const noexcept override {
    if (tables_.activations == nullptr || !ran_ || leaving()) return Wake::kAnyInput;
    return tables_.activations[current_].wakeInputs;
  }

  void updateHook() noexcept override {
    if (!admit()) return;
    Self& self = static_cast<Self&>(*this);
    iterate([&self](Action<Self> function) noexcept { (self.*function)(); });
    release();
  }

  /// One iteration, as Subsystem::step(); while a switch is pending it only polls the switch.
  template <class RunFunction>
  void step(RunFunction&& run) noexcept {
    if (!admit()) return;
    iterate(std::forward<RunFunction>(run));
    release();
  }

  /// The built-in predicate leaving(): a switch that removes this subsystem's agent is pending.
  bool leaving() const noexcept { return agent_ != nullptr && agent_->phase() == AgentSlot::Phase::leaving; }
  bool quiescent() const noexcept { return quiescent_ == nullptr || quiescent_[current_]; }
  bool switching() const noexcept { return pending_ != nullptr; }

  StateId currentState() const noexcept { return current_; }
  const char* currentStateName() const noexcept { return tables_.states[current_].name; }
  std::uint64_t iteration() const noexcept { return iteration_; }
  std::uint64_t steps() const noexcept { return steps_; }
  std::uint64_t timeouts() const noexcept { return timeouts_; }
  /// The times the subsystem restarted (its agent rejoined with reactivation restart; its first
  /// start not counted): a runtime whose pfs keep state outside Self (Orocos pf components)
  /// resets them when this changes.
  std::uint64_t restarts() const noexcept { return restarts_; }
  const FsmTables<Self>& tables() const noexcept { return tables_; }

 protected:
  void overflowed(const char* buffer, std::uint64_t lost) const noexcept {
    if (Observer* o = observer()) o->overflowed(*this, buffer, lost, steps_);
  }

 public:
  /// The pf number ``pf`` (``name``) failed for ``reason``: behaviourOk() is false until the
  /// subsystem enters a state; the observer hears of the pf's first failure in the state.
  void pfFailed(std::size_t pf, const char* name, const char* reason) noexcept {
    if (!markFailed(pf)) return;
    if (Observer* o = observer()) o->pfFailed(*this, name, reason, steps_);
  }
  /// After the pf number ``pf`` ran: whether the value it wrote into ``buffer`` may be sent.
  /// ``finite``: every number in it is; ``reason``: the failure a non-finite one is under
  /// NonFinite::error (the value is held back); under report it is reported and sent,
  /// ``reported`` remembering that until the value is finite again.
  bool written(std::size_t pf, const char* name, const char* buffer, const char* reason, bool finite,
               bool& reported) noexcept {
    if (finite) {
      reported = false;
      return true;
    }
    if (nonFinite() == NonFinite::error) {
      pfFailed(pf, name, reason);
      return false;
    }
    if (!reported) {
      reported = true;
      if (Observer* o = observer()) o->nonFinite(*this, name, buffer, steps_);
    }
    return true;
  }

 private:
  /// At an iteration boundary, in this subsystem's thread: whether it may run. A true
  /// answer leaves the member busy until release().
  bool admit() noexcept {
    if (agent_ == nullptr) return true;
    member_.busy_.store(true, std::memory_order_seq_cst);
    const AgentSlot::Phase phase = agent_->phase();
    if (phase == AgentSlot::Phase::stopped) {
      release();
      return false;
    }
    const std::uint32_t epoch = agent_->epoch();
    if (epoch != member_.epoch_) {
      member_.epoch_ = epoch;
      reactivate();
    }
    if (phase == AgentSlot::Phase::leaving && control_ && mayStop()) {
      agent_->set(AgentSlot::Phase::stopped);
      release();
      return false;
    }
    return true;
  }

  void release() noexcept {
    if (agent_ != nullptr) member_.busy_.store(false, std::memory_order_seq_cst);
  }

  bool mayStop() const noexcept {
#if EARL_SWITCH_DRAIN
    // a value taken in the last iteration is run through the pfs of one more before the stop
    return quiescent() && agent_->switch_ != nullptr && agent_->switch_->drained(*agent_) &&
           agent_->switch_->settled(*agent_);
#else
    return true;
#endif
  }

  void reactivate() noexcept {
    Self& self = static_cast<Self&>(*this);
    if (!started_) {
      started_ = true;
      self.resetData(true);
      enter(tables_.initial, nullptr);
      return;
    }
    if (agent_->reactivation() == Reactivation::resume) {
      self.resetData(false);
      return;
    }
    iteration_ = 0;
    entered_ = true;
    ran_ = false;
    waiting_ = false;
    ++restarts_;
    self.resetData(true);
    enter(tables_.initial, nullptr);
  }

  bool readyToRun(Clock::time_point now) noexcept {
    if (pending_ != nullptr) return now >= lastStart_ + period() ? take(now) : false;
    if (tables_.activations == nullptr || !ran_) return take(now);
    const ActivationDef<Self>& a = tables_.activations[current_];
    if (!waiting_) {
      waiting_ = true;
      waitStart_ = now;
    }
    if (now < lastStart_ + activationGap(a)) return false;
    if (a.obligatory == nullptr) return take(now);
    const Self& self = static_cast<const Self&>(*this);
    if ((self.*a.obligatory)()) return take(now);
    // leaving, with every closed link into the agent empty: no input the switch closed will
    // bring anything more, so the iterations that let the agent reach quiescence do not wait
    if (leaving() && agent_->switch_ != nullptr && agent_->switch_->drained(*agent_)) return take(now);
    const std::int64_t timeout = entered_ ? a.firstTimeoutNs : a.nextTimeoutNs;
    if (timeout >= 0 && now >= waitStart_ + std::chrono::nanoseconds(timeout)) {
      ++timeouts_;
      return take(now);
    }
    return false;
  }

  template <class RunFunction>
  void iterate(RunFunction&& run) noexcept {
    if (!started_) startHook();
    if (!started_) return;
    if (pending_ != nullptr) {
      if (!switch_->poll()) return;
      const TransitionDef<Self>* via = pending_;
      pending_ = nullptr;
      enter(via->target, via);
    }
    Self& self = static_cast<Self&>(*this);
    const BehaviourDef<Self>& behaviour = tables_.behaviours[tables_.states[current_].behaviour];
    for (std::size_t s = 0; s < behaviour.stageCount; ++s) {
      const StageDef<Self>& stage = behaviour.stages[s];
      for (std::size_t f = 0; f < stage.count; ++f) run(stage.functions[f]);
    }
    self.settleData();
    (self.*behaviour.send)();
    ++iteration_;
    entered_ = false;
    (self.*behaviour.receive)();
    ++steps_;
    const bool error = (self.*behaviour.error)();
    setInError(error);  // inError(): read by tc and the guards of this iteration, by ec in the next
    if (error || (self.*behaviour.terminal)()) {
      const TransitionDef<Self>* next =
          selectTransition(self, tables_.transitions, tables_.transitionCount, current_);
      if (next == nullptr) {
        iteration_ = 0;
      } else if (switch_ != nullptr && configurations_[next->target] >= 0 &&
                 switch_->begin(static_cast<std::size_t>(configurations_[next->target]))) {
        pending_ = next;
      } else {
        enter(next->target, next);
      }
    }
  }

  Clock::duration activationGap(const ActivationDef<Self>& a) const noexcept {
    return a.minPeriodNs >= 0 ? Clock::duration(std::chrono::nanoseconds(a.minPeriodNs))
           : a.obligatory != nullptr ? Clock::duration::zero()
                                     : Clock::duration(period());
  }

  bool take(Clock::time_point now) noexcept {
    ran_ = true;
    waiting_ = false;
    lastStart_ = now;
    return true;
  }

  void enter(StateId state, const TransitionDef<Self>* via) noexcept {
    const char* from = via != nullptr ? tables_.states[current_].name : nullptr;
    current_ = state;
    iteration_ = 0;
    entered_ = true;
    entered();  // every pf healthy again, inError() false
    if (Observer* o = observer()) {
      o->stateChanged(*this, from, tables_.states[state].name, via != nullptr ? via->name : nullptr, steps_);
    }
  }

  const FsmTables<Self>& tables_;
  const bool* quiescent_;
  StateId current_;
  std::uint64_t iteration_ = 0;
  std::uint64_t steps_ = 0;
  std::uint64_t timeouts_ = 0;
  std::uint64_t restarts_ = 0;
  bool started_ = false;
  bool entered_ = true;
  bool ran_ = false;
  bool waiting_ = false;
  Clock::time_point lastStart_{};
  Clock::time_point waitStart_{};
  AgentSlot* agent_ = nullptr;
  bool control_ = false;
  AgentMember member_;
  SwitchControl* switch_ = nullptr;
  const std::int16_t* configurations_ = nullptr;
  const TransitionDef<Self>* pending_ = nullptr;
};

}  // namespace earl
