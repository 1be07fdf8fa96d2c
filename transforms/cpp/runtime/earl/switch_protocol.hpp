// earl runtime: the switch of earl/switch.hpp between processes or components that share no
// memory (ROS nodes, Orocos components). Same protocol and guarantees, in rounds: the
// coordinator sends a SwitchCommand to every node (one subsystem instance each) and waits until
// every node has acknowledged it with a SwitchAck before it sends the next round.
//
//   close     senders close their variable links that the new configuration lacks and
//             report how many values they sent on each (cumulative counts); a link from a
//             leaving agent to one that stays stays open until the park;
//   drain     with the counts of the close: a receiver of a closed link acknowledges once that
//             many values have arrived on it (the transport keeps each link's order) and, when
//             its agent leaves, once it has read them all. A leaving agent sees leaving() true
//             once they have arrived, not before: values still in flight at the close would
//             otherwise come after its FSM reached a quiescent state that reads them no more,
//             and the drain would wait for the timeout (in one process, earl::Switch closes the
//             senders' gates before the agents see leaving(), so nothing is in flight then);
//   stop      the control subsystem of a leaving agent stops at its first iteration boundary
//             in a quiescent state (at once when forced: the switch timeout passed);
//   park      every subsystem of a leaving agent stops and closes its links to the agents
//             that stay, reporting how many values it sent on each; when forced, the values
//             still queued for it, or still to arrive, are cleared and reported as
//             undelivered, per link;
//   open      senders open the variable links of the new configuration (as earl::Switch
//             does, before the joining agents run: what they send from their first iteration
//             on goes out on them); a receiver of a link from a stopped agent acknowledges
//             once everything sent on it has arrived, so that it reads those values before
//             any of a joining agent (unless the switch was forced: then they come when they
//             arrive, none lost);
//   activate  the joining agents are restarted or resumed; the coordinator then enters its
//             new state.
//
// Every node acknowledges every round (at once for a round that does not concern it), so the
// coordinator only counts acknowledgements. A transport delivers commands to SwitchMember::
// command() and acknowledgements to SwitchCoordinator::ack(), in the thread that runs the
// node's iterations; the node calls SwitchMember::boundary() between two iterations and sends
// the acknowledgement it fills. Nothing allocates and nothing blocks: a round waits across
// iterations. Part of earl-m2t's C++ target; header-only, C++17.
#pragma once

#include <algorithm>
#include <array>
#include <chrono>
#include <cstddef>
#include <cstdint>

#include "earl/component.hpp"
#include "earl/switch.hpp"

namespace earl {

enum class SwitchRound : std::uint8_t { none = 0, close, drain, stop, park, open, activate };

/// Coordinator -> every node.
template <std::size_t Links>
struct SwitchCommand {
  std::uint32_t seq = 0;  // the switch, numbered from 1
  SwitchRound round = SwitchRound::none;
  std::uint16_t from = 0;  // configurations
  std::uint16_t to = 0;
  bool forced = false;  // the switch timeout passed
  /// From the drain on: per variable link, the values sent on it before it closed.
  std::array<std::uint64_t, Links> counts{};
};

/// Node -> coordinator.
template <std::size_t Links>
struct SwitchAck {
  std::uint32_t seq = 0;
  SwitchRound round = SwitchRound::none;
  std::uint16_t node = 0;
  /// close: the values this node sent on each variable link it sends (0 for the others);
  /// park: the values of each link into it that were undelivered, and the values it sent on
  /// each link of its agent to an agent that stays (the links lingers()).
  std::array<std::uint64_t, Links> counts{};
};

/// The switch as one node sees it: the gates of the variable links it sends, the counts of
/// those it receives, and the slot of its agent when that agent is variable.
template <std::size_t Links>
class SwitchMember final : public SwitchControl {
 public:
  /// ``agent``: the index of the node's agent among the variable agents, -1 for an agent of
  /// every configuration; ``control``: the node is that agent's control subsystem.
  SwitchMember(const SwitchTables& tables, std::uint16_t node, int agent, bool control, const char* agentName,
               Reactivation reactivation) noexcept
      : tables_(tables), node_(node), agent_(agent), control_(control), slot_(agentName, reactivation) {
    slot_.switch_ = this;
  }
  SwitchMember(const SwitchMember&) = delete;
  SwitchMember& operator=(const SwitchMember&) = delete;

  /// The slot the node's subsystem joins (joinAgent(*slot(), control)), nullptr when its
  /// agent is in every configuration.
  AgentSlot* slot() noexcept { return agent_ >= 0 ? &slot_ : nullptr; }
  bool control() const noexcept { return control_; }
  std::uint16_t node() const noexcept { return node_; }

  /// At initialisation: who is told each value a forced switch clears here (its seq, on the
  /// link of that number in ``linkNames``); the coordinator counts them per link.
  void setObserver(SwitchObserver* observer, const char* const* linkNames) noexcept {
    observer_ = observer;
    linkNames_ = linkNames;
  }

  /// At initialisation: the node sends the variable link ``link``.
  void sends(std::size_t link) noexcept {
    if (link < Links) sends_[link] = true;
  }
  /// At initialisation: the node receives the variable link ``link`` into ``channel``.
  template <class Ch>
  void receives(std::size_t link, VariableLink<Ch>& channel) noexcept {
    if (link >= Links) return;
    receivers_[link] = Receiver{&channel.gate(), &channel,
                                [](const void* c) noexcept { return static_cast<const VariableLink<Ch>*>(c)->fresh(); },
                                [](const void* c) noexcept { return static_cast<const VariableLink<Ch>*>(c)->held(); },
                                [](void* c, LostValue each, void* context) noexcept {
                                  return static_cast<VariableLink<Ch>*>(c)->discard(each, context);
                                }};
  }

  /// At initialisation: the links and the agent as ``configuration`` has them.
  void start(std::size_t configuration) noexcept {
    current_ = configuration;
    for (std::size_t l = 0; l < Links; ++l) {
      const bool present = tables_.hasLink(configuration, l);
      open_[l] = present;
      if (receivers_[l].gate != nullptr) present ? receivers_[l].gate->open() : receivers_[l].gate->close();
    }
    if (agent_ >= 0) {
      slot_.set(tables_.hasAgent(configuration, static_cast<std::size_t>(agent_)) ? AgentSlot::Phase::active
                                                                                          : AgentSlot::Phase::stopped);
    }
  }

  /// Whether a value sent now goes out on the variable link ``link`` (sent() counts it); a value
  /// it refuses is counted (reportWrittenClosed()).
  bool admit(std::size_t link) noexcept {
    if (link >= Links) return false;
    if (!open_[link]) ++refused_[link];
    return open_[link];
  }
  void sent(std::size_t link) noexcept {
    if (link < Links) ++sent_[link];
  }
  /// At the end of a run: the values written on each variable link this node sends while it
  /// was closed, told to the observer.
  void reportWrittenClosed() const noexcept {
    if (observer_ == nullptr) return;
    for (std::size_t l = 0; l < Links; ++l) {
      if (refused_[l] > 0) observer_->writtenClosed(linkNames_ != nullptr ? linkNames_[l] : "?", refused_[l]);
    }
  }

  /// A value of the variable link ``link`` arrived: writes it to ``channel`` (past its gate,
  /// which orders reading), or drops it when a forced switch already reported it undelivered.
  template <class Ch>
  bool deliver(std::size_t link, VariableLink<Ch>& channel, const typename VariableLink<Ch>::value_type& value) noexcept {
    if (link >= Links) return false;
    if (++arrived_[link] <= dropUpTo_[link]) {  // counted at the park of a forced switch
      lost(link, seqOf(value));
      return false;
    }
    channel.Ch::write(value);
    return true;
  }

  /// A command of the coordinator; handled at the next boundary().
  void command(const SwitchCommand<Links>& command) noexcept {
    if (command.seq < command_.seq) return;
    // of the current switch, a later round, or the round the coordinator forced (its timeout)
    if (command.seq == command_.seq && command.round <= command_.round &&
        !(command.round == command_.round && command.forced && !command_.forced)) {
      return;
    }
    command_ = command;
  }

  /// Between two iterations: carries out the pending command; true when ``ack`` is filled and
  /// is to be sent.
  bool boundary(SwitchAck<Links>& ack) noexcept {
    const SwitchCommand<Links>& c = command_;
    // a forced command repeats its round (the coordinator's timeout): it is acknowledged again,
    // since the coordinator forgot the acknowledgements of the round it forced
    if (c.round == SwitchRound::none || (c.seq == ackedSeq_ && c.round == ackedRound_ && c.forced == ackedForced_)) {
      return false;
    }
    if (c.seq != seq_) begin(c);
    if (c.round >= SwitchRound::drain) expected_ = c.counts;
    bool done = true;
    switch (c.round) {
      case SwitchRound::drain:
        if (leaves() && slot_.phase() == AgentSlot::Phase::active && arrivedAll(false)) {
          slot_.set(AgentSlot::Phase::leaving);
        }
        done = arrivedAll(leaves());
        break;
      case SwitchRound::stop:
        done = stopped(c.forced);
        break;
      case SwitchRound::park:
        park(c.forced);
        break;
      case SwitchRound::activate:
        activate();
        break;
      case SwitchRound::open:
        openLinks();
        done = c.forced || arrivedLingering();
        break;
      default:
        break;
    }
    if (!done) return false;
    ackedSeq_ = c.seq;
    ackedRound_ = c.round;
    ackedForced_ = c.forced;
    ack.seq = c.seq;
    ack.round = c.round;
    ack.node = node_;
    ack.counts.fill(0);
    if (c.round == SwitchRound::close) {
      for (std::size_t l = 0; l < Links; ++l) {
        if (sends_[l]) ack.counts[l] = sent_[l];
      }
    } else if (c.round == SwitchRound::park) {
      ack.counts = undelivered_;
      for (std::size_t l = 0; l < Links; ++l) {
        if (sends_[l] && lingers(l)) ack.counts[l] = sent_[l];
      }
    }
    return true;
  }

  /// The leaving agent may stop: the coordinator has seen every closed link into it drained
  /// (its stop round), and this node's own closed links are read.
  bool drained(const AgentSlot& agent) const noexcept override {
    (void)agent;
    return command_.seq == seq_ && command_.round >= SwitchRound::stop && arrivedAll(true);
  }
  /// No value of this node's closed links waits in an Input Buffer for the next iteration's pfs.
  bool settled(const AgentSlot& agent) const noexcept override {
    (void)agent;
    for (std::size_t l = 0; l < Links; ++l) {
      const Receiver& r = receivers_[l];
      if (r.channel != nullptr && closes(l) && r.held(r.channel)) return false;
    }
    return true;
  }
  bool begin(std::size_t) noexcept override { return false; }
  bool poll() noexcept override { return true; }

  std::uint64_t sentOn(std::size_t link) const noexcept { return link < Links ? sent_[link] : 0; }
  std::uint64_t arrivedOn(std::size_t link) const noexcept { return link < Links ? arrived_[link] : 0; }

 private:
  struct Receiver {
    Gate* gate = nullptr;
    void* channel = nullptr;
    bool (*fresh)(const void*) noexcept = nullptr;
    bool (*held)(const void*) noexcept = nullptr;
    std::uint64_t (*discard)(void*, LostValue, void*) noexcept = nullptr;
  };

  /// A value of the link ``link`` a forced switch cleared: told to the observer.
  void lost(std::size_t link, std::int64_t seq) const noexcept {
    if (observer_ != nullptr) observer_->undeliveredValue(linkNames_ != nullptr ? linkNames_[link] : "?", seq);
  }
  struct Lost {
    const SwitchMember* member;
    std::size_t link;
    static void each(void* context, std::int64_t seq) noexcept {
      const Lost& lost = *static_cast<const Lost*>(context);
      lost.member->lost(lost.link, seq);
    }
  };

  bool closes(std::size_t l) const noexcept {
    return tables_.hasLink(from_, l) && !tables_.hasLink(to_, l);
  }
  bool lingers(std::size_t l) const noexcept { return tables_.lingers(from_, to_, l); }
  bool opens(std::size_t l) const noexcept { return !tables_.hasLink(from_, l) && tables_.hasLink(to_, l); }
  bool leaves() const noexcept {
    if (agent_ < 0) return false;
    const auto a = static_cast<std::size_t>(agent_);
    return tables_.hasAgent(from_, a) && !tables_.hasAgent(to_, a);
  }
  bool joins() const noexcept {
    if (agent_ < 0) return false;
    const auto a = static_cast<std::size_t>(agent_);
    return !tables_.hasAgent(from_, a) && tables_.hasAgent(to_, a);
  }

  /// The close, which every later round of a switch implies.
  void begin(const SwitchCommand<Links>& c) noexcept {
    seq_ = c.seq;
    from_ = c.from;
    to_ = c.to;
    undelivered_.fill(0);
    for (std::size_t l = 0; l < Links; ++l) {
      if (!closes(l)) continue;
      if (!lingers(l)) open_[l] = false;  // a lingering one at the park, once its sender stopped
      if (receivers_[l].gate != nullptr) receivers_[l].gate->close();  // read before the others
    }
  }

  /// Every value sent on the links into this node from the agents that stopped (lingers()) has
  /// arrived: the counts of the park are in the open round's command.
  bool arrivedLingering() const noexcept {
    for (std::size_t l = 0; l < Links; ++l) {
      if (receivers_[l].channel != nullptr && lingers(l) && arrived_[l] < expected_[l]) return false;
    }
    return true;
  }

  /// Every closed link into this node has brought what was sent on it, and (``read``) the
  /// subsystem has read it.
  bool arrivedAll(bool read) const noexcept {
    for (std::size_t l = 0; l < Links; ++l) {
      const Receiver& r = receivers_[l];
      if (r.channel == nullptr || !closes(l)) continue;
      if (arrived_[l] < expected_[l]) return false;
      if (read && r.fresh(r.channel)) return false;
    }
    return true;
  }

  bool stopped(bool forced) noexcept {
    if (!leaves() || !control_) return true;
    if (forced) slot_.set(AgentSlot::Phase::stopped);
    return slot_.phase() == AgentSlot::Phase::stopped;
  }

  void park(bool forced) noexcept {
    if (!leaves()) return;
    slot_.set(AgentSlot::Phase::stopped);
    for (std::size_t l = 0; l < Links; ++l) {
      if (sends_[l] && lingers(l)) open_[l] = false;
    }
    if (!forced) return;
    for (std::size_t l = 0; l < Links; ++l) {
      const Receiver& r = receivers_[l];
      if (r.channel == nullptr || !closes(l)) continue;
      const std::uint64_t late = expected_[l] > arrived_[l] ? expected_[l] - arrived_[l] : 0;
      Lost context{this, l};
      undelivered_[l] = r.discard(r.channel, &Lost::each, &context) + late;
      if (expected_[l] > dropUpTo_[l]) dropUpTo_[l] = expected_[l];
    }
  }

  void activate() noexcept {
    if (joins()) slot_.activate();
  }

  void openLinks() noexcept {
    for (std::size_t l = 0; l < Links; ++l) {
      if (!opens(l)) continue;
      open_[l] = true;
      if (receivers_[l].gate != nullptr) receivers_[l].gate->open();
    }
    current_ = to_;
  }

  const SwitchTables& tables_;
  std::uint16_t node_;
  int agent_;
  bool control_;
  AgentSlot slot_;
  std::size_t current_ = 0;
  std::size_t from_ = 0;
  std::size_t to_ = 0;
  std::uint32_t seq_ = 0;
  std::uint32_t ackedSeq_ = 0;
  SwitchRound ackedRound_ = SwitchRound::none;
  bool ackedForced_ = false;
  SwitchCommand<Links> command_{};
  std::array<bool, Links> sends_{};
  std::array<bool, Links> open_{};
  std::array<std::uint64_t, Links> sent_{};
  std::array<std::uint64_t, Links> refused_{};
  std::array<Receiver, Links> receivers_{};
  std::array<std::uint64_t, Links> arrived_{};
  std::array<std::uint64_t, Links> expected_{};
  std::array<std::uint64_t, Links> dropUpTo_{};
  std::array<std::uint64_t, Links> undelivered_{};
  SwitchObserver* observer_ = nullptr;
  const char* const* linkNames_ = nullptr;
};

/// The switch as the coordinator's node drives it: SwitchedSubsystem::coordinate() takes it
/// in place of a Switch. ``Nodes``: every subsystem instance of the system, each a
/// SwitchMember numbered 0 … Nodes-1 (the coordinator's own node included).
template <std::size_t Links, std::size_t Nodes>
class SwitchCoordinator final : public SwitchControl {
 public:
  using Clock = std::chrono::steady_clock;
  using Send = void (*)(void* context, const SwitchCommand<Links>& command) noexcept;

  SwitchCoordinator(const SwitchTables& tables, const char* const* linkNames) noexcept
      : tables_(tables), linkNames_(linkNames) {}
  SwitchCoordinator(const SwitchCoordinator&) = delete;
  SwitchCoordinator& operator=(const SwitchCoordinator&) = delete;

  /// At initialisation: how a command reaches every node (this one's included).
  void setTransport(Send send, void* context) noexcept {
    send_ = send;
    context_ = context;
  }
  void setObserver(SwitchObserver* observer) noexcept { observer_ = observer; }
  void setCoordinator(const Component* coordinator) noexcept override { coordinator_ = coordinator; }
  /// A deterministic (stepped) run: the timeout is counted in polls of the coordinator, one
  /// per period, and latencies are reported in them. Otherwise on the steady clock.
  void countCycles(bool cycles) noexcept { cycles_ = cycles; }
  void start(std::size_t configuration) noexcept { current_ = configuration; }

  std::size_t current() const noexcept { return current_; }
  bool switching() const noexcept { return target_ != kNone; }
  std::uint64_t switches() const noexcept { return switches_; }
  std::uint64_t timeouts() const noexcept { return timeouts_; }
  std::uint64_t undelivered() const noexcept { return undelivered_; }
  const SwitchLatency& lastLatency() const noexcept { return last_; }

  /// An acknowledgement of a node; one of an earlier round is ignored.
  void ack(const SwitchAck<Links>& ack) noexcept {
    if (!switching() || ack.seq != command_.seq || ack.round != command_.round || ack.node >= Nodes) return;
    if (acked_[ack.node]) return;
    acked_[ack.node] = true;
    ++acks_;
    if (ack.round == SwitchRound::close) {
      for (std::size_t l = 0; l < Links; ++l) command_.counts[l] += ack.counts[l];
    } else if (ack.round == SwitchRound::park) {
      for (std::size_t l = 0; l < Links; ++l) {
        if (tables_.lingers(current_, target_, l)) {
          lingered_[l] += ack.counts[l];  // sent by the stopped agent: what the open waits for
        } else {
          undeliveredNow_[l] += ack.counts[l];
        }
      }
    }
  }

  bool begin(std::size_t configuration) noexcept override {
    if (configuration == current_ || configuration >= tables_.configurations) return false;
    target_ = configuration;
    started_ = Clock::now();
    polls_ = 0;
    command_ = SwitchCommand<Links>{};
    command_.seq = ++seq_;
    command_.from = static_cast<std::uint16_t>(current_);
    command_.to = static_cast<std::uint16_t>(target_);
    undeliveredNow_.fill(0);
    lingered_.fill(0);
    send(SwitchRound::close);
    return true;
  }

  bool poll() noexcept override {
    if (!switching()) return true;
    ++polls_;
    const SwitchRound round = command_.round;
    if (acks_ < Nodes) {
      // the drain and the quiescence of the leaving agents are what the timeout bounds
      if ((round == SwitchRound::drain || round == SwitchRound::stop) && !command_.forced && timedOut()) force();
      // and the arrival of a stopped agent's last values, once the switch timeout itself passed
      // (a transport that dropped one): none is lost, they are taken when they arrive
      if (round == SwitchRound::open && !command_.forced && pastTimeout()) {
        ++timeouts_;
        command_.forced = true;
        send(SwitchRound::open);
      }
      return false;
    }
    measure(round);
    switch (round) {
      case SwitchRound::close:
#if EARL_SWITCH_DRAIN
        if (timedOut()) {
          force();
        } else {
          send(SwitchRound::drain);
        }
#else
        force();
#endif
        return false;
      case SwitchRound::drain:
        send(SwitchRound::stop);
        return false;
      case SwitchRound::stop:
        send(SwitchRound::park);
        return false;
      case SwitchRound::park:
        report();
        for (std::size_t l = 0; l < Links; ++l) {
          if (tables_.lingers(current_, target_, l)) command_.counts[l] = lingered_[l];
        }
        send(SwitchRound::open);
        return false;
      case SwitchRound::open:
        send(SwitchRound::activate);
        return false;
      default:
        finish();
        return true;
    }
  }

  /// The coordinator's node is a member too, but drains nothing here: its agent is never
  /// variable (rule X003).
  bool drained(const AgentSlot& agent) const noexcept override {
    (void)agent;
    return true;
  }
  bool settled(const AgentSlot& agent) const noexcept override {
    (void)agent;
    return true;
  }

 private:
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

  void send(SwitchRound round) noexcept {
    command_.round = round;
    acked_.fill(false);
    acks_ = 0;
    roundPolls_ = polls_;
    if (!cycles_) roundStarted_ = Clock::now();
    if (send_ != nullptr) send_(context_, command_);
  }

  /// A round every node acknowledged: how long it took, when only the transport and the nodes'
  /// iteration boundaries made it wait (not the drain and the stop, which wait for the agents).
  /// The slowest recent one is what each round after a forced stop is expected to take: a
  /// slower round counts at once, and its weight fades by an eighth per round since.
  void measure(SwitchRound round) noexcept {
    if (round == SwitchRound::drain || round == SwitchRound::stop) return;
    const std::int64_t took =
        cycles_ ? static_cast<std::int64_t>(polls_ - roundPolls_)
                : std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - roundStarted_).count();
    slowestRound_ = std::max(took, slowestRound_ - slowestRound_ / 8);
  }

  void force() noexcept {
    ++timeouts_;
    command_.forced = true;
    send(SwitchRound::stop);
  }

  std::chrono::nanoseconds period() const noexcept {
    return coordinator_ != nullptr ? coordinator_->period() : std::chrono::nanoseconds(std::chrono::milliseconds(1));
  }

  /// A forced switch still takes its stop, park, open and activate rounds, each at least a poll
  /// and as long as the slowest recent round (measure()): it is forced that long before the
  /// timeout, so that it ends by the timeout when those rounds are no slower. Never more than
  /// a quarter of the timeout before it, though: one starved round must not cut the drain of
  /// the next switches short (values a forced switch clears are lost to the receiver).
  static constexpr std::int64_t kRoundsAfterForce = 4;
  static constexpr std::int64_t kMostReservedPart = 4;  // of the timeout

  bool timedOut() const noexcept {
    const std::int64_t timeout = tables_.timeoutNs[target_];
    if (timeout < 0) return false;
    const std::int64_t p = period().count() > 0 ? period().count() : 1;
    if (cycles_) {
      const std::int64_t polls = (timeout + p - 1) / p;
      const std::int64_t reserve = kRoundsAfterForce * std::max<std::int64_t>(1, slowestRound_);
      const std::int64_t reserved = std::max(kRoundsAfterForce, std::min(reserve, polls / kMostReservedPart));
      return static_cast<std::int64_t>(polls_) + reserved >= polls;
    }
    const auto elapsed = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - started_).count();
    // on the clock, rounds vary with the load: half the slowest one again for that
    const std::int64_t reserve = p + kRoundsAfterForce * std::max(p, slowestRound_ + slowestRound_ / 2);
    const std::int64_t reserved = std::max((kRoundsAfterForce + 1) * p, std::min(reserve, timeout / kMostReservedPart));
    return elapsed + reserved >= timeout;
  }

  /// The switch timeout has passed (no reserve for rounds to come: the open round is the last
  /// that waits).
  bool pastTimeout() const noexcept {
    const std::int64_t timeout = tables_.timeoutNs[target_];
    if (timeout < 0) return false;
    if (cycles_) {
      const std::int64_t p = period().count() > 0 ? period().count() : 1;
      return static_cast<std::int64_t>(polls_) >= (timeout + p - 1) / p;
    }
    return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - started_).count() >= timeout;
  }

  void report() noexcept {
    for (std::size_t l = 0; l < Links; ++l) {
      if (undeliveredNow_[l] == 0) continue;
      undelivered_ += undeliveredNow_[l];
      if (observer_ != nullptr) observer_->undelivered(linkNames_ != nullptr ? linkNames_[l] : "?", undeliveredNow_[l]);
    }
  }

  void finish() noexcept {
    last_ = SwitchLatency{polls_, 0, !cycles_, command_.forced};
    if (!cycles_) last_.nanoseconds = std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - started_).count();
    const std::size_t from = current_;
    current_ = target_;
    target_ = kNone;
    ++switches_;
    if (observer_ != nullptr) observer_->switched(tables_.names[from], tables_.names[current_], last_);
  }

  const SwitchTables& tables_;
  const char* const* linkNames_;
  Send send_ = nullptr;
  void* context_ = nullptr;
  const Component* coordinator_ = nullptr;
  SwitchObserver* observer_ = nullptr;
  bool cycles_ = false;
  SwitchCommand<Links> command_{};
  std::array<bool, Nodes> acked_{};
  std::size_t acks_ = 0;
  std::array<std::uint64_t, Links> undeliveredNow_{};
  std::array<std::uint64_t, Links> lingered_{};
  std::size_t current_ = 0;
  std::size_t target_ = kNone;
  std::uint32_t seq_ = 0;
  std::uint64_t polls_ = 0;
  Clock::time_point started_{};
  std::uint64_t roundPolls_ = 0;  // polls_ when the current round was sent
  Clock::time_point roundStarted_{};
  std::int64_t slowestRound_ = 0;  // in polls when counting cycles, else in ns
  std::uint64_t switches_ = 0;
  std::uint64_t timeouts_ = 0;
  std::uint64_t undelivered_ = 0;
  SwitchLatency last_{0, 0, true, false};
};

}  // namespace earl
