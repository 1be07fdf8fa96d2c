// Unit test of the earl C++ runtime (transforms/cpp/runtime): buffers and newData, queued
// inputs (order, one value per receive, overflow counted), priority selection with ties in
// model order, the stage order of a transition function, the basic-behaviour loop and
// activation (obligatory inputs, minimal period, first and next timeouts on a given clock).
// Built and run by tests/test_gen_cpp.py; prints "ok" and exits 0.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "earl/earl.hpp"

namespace {

int failures = 0;

void expect(bool ok, const char* what, int line) {
  if (!ok) {
    std::printf("FAIL line %d: %s\n", line, what);
    ++failures;
  }
}
#define EXPECT(x) expect((x), #x, __LINE__)

void buffers_and_new_data() {
  earl::Channel<int> link;
  earl::OutputPort<int, 1> out;
  earl::InputPort<int, 1> in;
  EXPECT(out.connect(link));
  EXPECT(!out.connect(link));  // capacity 1
  EXPECT(in.connect(link));
  EXPECT(!in.receive());  // nothing sent yet
  EXPECT(!in.newData());
  out.msg() = 7;
  out.send();
  EXPECT(!in.newData());  // only receive() delivers
  EXPECT(in.receive());
  EXPECT(in.newData() && in.msg() == 7);
  EXPECT(!in.receive());  // consumed: no new value, the old one stays
  EXPECT(!in.newData() && in.msg() == 7);
  out.msg() = 8;
  out.send();
  out.msg() = 9;
  out.send();
  EXPECT(in.receive() && in.msg() == 9);  // latest value wins
  EXPECT(in.received() == 2 && out.sent() == 3);

  // fan-out to two inputs, fan-in from two outputs (link order: the last fresh value wins)
  earl::Channel<int> a, b;
  earl::OutputPort<int, 2> wide;
  earl::InputPort<int, 1> left, right;
  EXPECT(wide.connect(a) && wide.connect(b) && left.connect(a) && right.connect(b));
  wide.msg() = 3;
  wide.send();
  EXPECT(left.receive() && right.receive() && left.msg() == 3 && right.msg() == 3);
  earl::Channel<int> c, d;
  earl::OutputPort<int, 1> first, second;
  earl::InputPort<int, 2> merged;
  EXPECT(first.connect(c) && second.connect(d) && merged.connect(c) && merged.connect(d));
  first.msg() = 1;
  first.send();
  EXPECT(merged.receive() && merged.msg() == 1);
  second.msg() = 2;
  second.send();
  first.msg() = 4;
  first.send();
  EXPECT(merged.receive() && merged.msg() == 2);
}

void queued_inputs() {
  earl::QueueChannel<int, 3> link;
  earl::Channel<int> latest;
  earl::OutputPort<int, 2> out;
  earl::InputPort<int, 1, 3> in;
  earl::InputPort<int, 1> other;
  EXPECT(out.connect(link) && out.connect(latest));  // one output, a queued and a latest-value input
  EXPECT(in.connect(link) && other.connect(latest));
  EXPECT(!in.ready() && !in.receive());
  for (int v : {1, 2, 3, 4, 5}) {
    out.msg() = v;
    out.send();
  }
  EXPECT(in.ready() && other.ready());
  EXPECT(in.overflows() == 2 && in.newOverflows() == 2 && in.newOverflows() == 0);  // 4 and 5 lost, reported once
  EXPECT(in.receive() && in.msg() == 1);  // in order, one per receive()
  EXPECT(in.receive() && in.msg() == 2);
  EXPECT(in.receive() && in.msg() == 3 && !in.ready());
  EXPECT(!in.receive() && !in.newData() && in.msg() == 3);
  EXPECT(other.receive() && other.msg() == 5);  // the latest-value input got the newest
  // two queued links: the first link's values first
  earl::QueueChannel<int, 2> a, b;
  earl::OutputPort<int, 1> first, second;
  earl::InputPort<int, 2, 2> merged;
  EXPECT(first.connect(a) && second.connect(b) && merged.connect(a) && merged.connect(b));
  second.msg() = 20;
  second.send();
  first.msg() = 10;
  first.send();
  EXPECT(merged.receive() && merged.msg() == 10);
  EXPECT(merged.receive() && merged.msg() == 20);
  EXPECT(!merged.receive());
}

void value_types() {
  earl::String<4> s = "hello";
  EXPECT(s.size() == 4 && std::strcmp(s.c_str(), "hell") == 0);
  earl::BoundedArray<int, 2> v;
  EXPECT(v.empty() && v.push_back(1) && v.push_back(2) && !v.push_back(3) && v.size() == 2);
}

// A hand-written subsystem in the shape the generator emits: states A, B, C; transitions in
// model order A->B (priority 0), A->C (priority 1), A->A (priority 1), B->A; behaviour of A has
// two stages [f1, f2] [f3].
class Demo final : public earl::Subsystem<Demo> {
 public:
  Demo() noexcept : earl::Subsystem<Demo>("demo", tables()) {}
  std::string log;
  bool toB = false, toC = false, toA = false, done = false;

  void f1() noexcept { log += "1"; }
  void f2() noexcept { log += "2"; }
  void f3() noexcept { log += "3"; }
  void send() noexcept { log += "s"; }
  void receive() noexcept { log += "r"; }
  bool tc() const noexcept { return done; }
  bool never() const noexcept { return false; }
  bool always() const noexcept { return true; }
  bool gB() const noexcept { return toB; }
  bool gC() const noexcept { return toC; }
  bool gA() const noexcept { return toA; }

  static const earl::FsmTables<Demo>& tables() noexcept {
    static const earl::Action<Demo> stage1[] = {&Demo::f1, &Demo::f2};
    static const earl::Action<Demo> stage2[] = {&Demo::f3};
    static const earl::StageDef<Demo> stagesA[] = {{stage1, 2}, {stage2, 1}};
    static const earl::BehaviourDef<Demo> behaviours[] = {
        {"a/bb", stagesA, 2, &Demo::send, &Demo::receive, &Demo::tc, &Demo::never},
        {"b/bb", nullptr, 0, &Demo::send, &Demo::receive, &Demo::always, &Demo::never},
    };
    static const earl::StateDef states[] = {{"A", 0}, {"B", 1}, {"C", 1}};
    static const earl::TransitionDef<Demo> transitions[] = {
        {"A,B/t", 0, 1, 0, &Demo::gB},
        {"A,C/t", 0, 2, 1, &Demo::gC},
        {"A,A/t", 0, 0, 1, &Demo::gA},
        {"B,A/t", 1, 0, 0, &Demo::always},
    };
    static const earl::FsmTables<Demo> t{states, 3, behaviours, 2, transitions, 4, 0, nullptr};
    return t;
  }
};

struct Recorder final : earl::Observer {
  std::string seen;
  void stateChanged(const earl::Component&, const char* from, const char* to, const char*,
                    std::uint64_t) noexcept override {
    seen += std::string(from ? from : "-") + ">" + to + " ";
  }
};

void stages_and_priorities() {
  Demo d;
  Recorder r;
  d.setObserver(&r);
  d.updateHook();
  EXPECT(d.log == "123sr");  // stages in order, then send, then receive
  EXPECT(d.iteration() == 1 && d.currentState() == 0);
  d.done = true;  // tc holds, no transition enabled: stays in A, behaviour restarts
  d.updateHook();
  EXPECT(d.currentState() == 0 && d.iteration() == 0);
  d.toB = true;
  d.toC = true;
  d.toA = true;  // A->C and A->A tie at priority 1: the first in model order (A->C) wins
  d.updateHook();
  EXPECT(d.currentState() == 2);
  EXPECT(std::strcmp(d.currentStateName(), "C") == 0);
  EXPECT(r.seen == "->A A>C ");
  const earl::TransitionDef<Demo>* t =
      earl::selectTransition(d, Demo::tables().transitions, 4, earl::StateId{0});
  EXPECT(t != nullptr && std::strcmp(t->name, "A,C/t") == 0);
  d.toC = false;
  t = earl::selectTransition(d, Demo::tables().transitions, 4, earl::StateId{0});
  EXPECT(t != nullptr && std::strcmp(t->name, "A,A/t") == 0);
  d.toA = false;
  t = earl::selectTransition(d, Demo::tables().transitions, 4, earl::StateId{0});
  EXPECT(t != nullptr && std::strcmp(t->name, "A,B/t") == 0);
  d.toB = false;
  EXPECT(earl::selectTransition(d, Demo::tables().transitions, 4, earl::StateId{0}) == nullptr);
}

// One state, activated by the obligatory input ``ready`` (minimal period 2 ms, first timeout
// 10 ms, next timeout 5 ms), and a second state without a group at the component's period.
class Driven final : public earl::Subsystem<Driven> {
 public:
  Driven() noexcept : earl::Subsystem<Driven>("driven", tables()) {}
  bool input = false, leave = false;
  void send() noexcept {}
  void receive() noexcept { input = false; }
  bool obligatory() const noexcept { return input; }
  bool tc() const noexcept { return leave; }
  bool never() const noexcept { return false; }
  bool always() const noexcept { return true; }

  static const earl::FsmTables<Driven>& tables() noexcept {
    static const earl::BehaviourDef<Driven> behaviours[] = {
        {"a/bb", nullptr, 0, &Driven::send, &Driven::receive, &Driven::tc, &Driven::never},
    };
    static const earl::StateDef states[] = {{"A", 0}, {"B", 0}};
    static const earl::TransitionDef<Driven> transitions[] = {{"A,B/t", 0, 1, 0, &Driven::always}};
    static const earl::ActivationDef<Driven> activations[] = {
        {&Driven::obligatory, 2'000'000, 10'000'000, 5'000'000},
        {nullptr, -1, -1, -1},
    };
    static const earl::FsmTables<Driven> t{states, 2, behaviours, 1, transitions, 1, 0, activations};
    return t;
  }
};

void activation() {
  using ms = std::chrono::milliseconds;
  const earl::Component::Clock::time_point t0{};
  Driven d;
  d.setPeriod(ms(4));
  EXPECT(d.eventDriven());
  EXPECT(d.ready(t0));  // the first iteration runs at once
  d.updateHook();
  EXPECT(!d.ready(t0 + ms(1)));  // nothing came: the wait begins at 1 ms
  d.input = true;
  EXPECT(!d.ready(t0 + ms(1)));  // the input came, but the minimal period (2 ms) has not passed
  EXPECT(d.ready(t0 + ms(2)));
  d.updateHook();  // receive() takes the input
  EXPECT(!d.ready(t0 + ms(3)));
  EXPECT(!d.ready(t0 + ms(7)));  // next timeout: 5 ms after the wait began at 3 ms
  EXPECT(d.ready(t0 + ms(8)) && d.timeouts() == 1);
  d.updateHook();
  d.leave = true;
  d.input = true;
  EXPECT(d.ready(t0 + ms(10)));
  d.updateHook();  // A -> B
  EXPECT(d.currentState() == 1);
  EXPECT(!d.ready(t0 + ms(13)));  // B: no group, the component's period (4 ms)
  EXPECT(d.ready(t0 + ms(14)));
  earl::Component& periodic = d;
  Demo plain;
  EXPECT(periodic.eventDriven() && !static_cast<earl::Component&>(plain).eventDriven());
}

}  // namespace

int main() {
  buffers_and_new_data();
  queued_inputs();
  value_types();
  stages_and_priorities();
  activation();
  if (failures != 0) return EXIT_FAILURE;
  std::printf("ok\n");
  return EXIT_SUCCESS;
}
