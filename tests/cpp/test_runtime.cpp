// Unit test of the earl C++ runtime (transforms/cpp/runtime): buffers and newData, priority
// selection with ties in model order, the stage order of a transition function and the
// basic-behaviour loop. Built and run by tests/test_gen_cpp.py; prints "ok" and exits 0.
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
    static const earl::FsmTables<Demo> t{states, 3, behaviours, 2, transitions, 4, 0};
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

}  // namespace

int main() {
  buffers_and_new_data();
  value_types();
  stages_and_priorities();
  if (failures != 0) return EXIT_FAILURE;
  std::printf("ok\n");
  return EXIT_SUCCESS;
}
