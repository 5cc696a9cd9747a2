// The machine's floor for catching a fault, and keel's guard beside it, interleaved trial by
// trial on one thread so that the machine's drift blurs neither: the thread sleeps 1 ms (as an
// executor between cycles), wakes and faults — alternately under a bare SA_SIGINFO handler on
// an alternate stack (which takes the time and siglongjmps back) and under keel's
// runtime::guarded (detection time taken in keel's handler). Same for a C++ throw.
// Then the bare handler and catch by cadence, on a 1 ms cycle: a fault on every cycle (the
// path stays warm) and one every third cycle (as `keel bench detection` strikes): what a few
// quiet milliseconds cost the kernel's delivery and the unwinder.
//   build/bin/keel_bench_signal_floor [--n 1000]
#include <charconv>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <system_error>
#include <thread>
#include <vector>

#include "floor.hpp"
#include "harness/stats.hpp"
#include "runtime/guard.hpp"
#include "runtime/injection.hpp"

namespace {

using keel::bench::bareSegfault;
using keel::bench::bareThrow;
using keel::runtime::steadyNs;

void report(const char* what, std::vector<std::int64_t> v) {
  auto s = keel::bench::summarise(std::move(v));
  std::printf("| %s | %zu | %.1f | %.1f | %.1f |\n", what, s.n, s.p50_us, s.p99_us, s.max_us);
}

}  // namespace

int main(int argc, char** argv) {
  int n = 1000;
  if (argc > 2 && std::string(argv[1]) == "--n") {
    const std::string_view arg(argv[2]);
    if (std::from_chars(arg.data(), arg.data() + arg.size(), n).ec != std::errc() || n <= 0) {
      std::fprintf(stderr, "usage: %s [--n FAULTS]\n", argv[0]);
      return 2;
    }
  }
  std::printf(
      "| fault right after a 1 ms sleep, interleaved | n | p50 µs | p99 µs | max µs |\n|---|---|---|---|---|\n");
  std::thread t([n] {
    keel::runtime::installSignalHandlers();
    keel::runtime::installAltStack();
    std::vector<std::int64_t> seg, thr, kseg, kthr;
    auto nap = [] { std::this_thread::sleep_for(std::chrono::milliseconds(1)); };
    auto bareSeg = [&] {
      const keel::bench::BareSegvHandler bare;  // keel's handler is back when it goes
      nap();
      seg.push_back(bareSegfault());
    };
    auto keelSeg = [&] {
      nap();
      std::int64_t tk = 0;
      auto out = keel::runtime::guarded([&tk] {
        tk = steadyNs();
        keel::bench::storeToPageZero();
        return keel::ReturnCode::Ok;
      });
      kseg.push_back(out.t_ns - tk);
    };
    auto bareThr = [&] {
      nap();
      thr.push_back(bareThrow());
    };
    auto keelThr = [&] {
      nap();
      const std::int64_t tt = steadyNs();
      auto out = keel::runtime::guarded([]() -> keel::ReturnCode {
        keel::bench::throwRuntimeError();
        return keel::ReturnCode::Ok;
      });
      kthr.push_back(out.t_ns - tt);  // the time keel's catch took, as for a signal
    };
    for (int i = 0; i < n; ++i) {  // alternate the order: neither side always runs warmer
      if (i % 2) {
        bareSeg(), keelSeg(), bareThr(), keelThr();
      } else {
        keelSeg(), bareSeg(), keelThr(), bareThr();
      }
    }
    report("bare SIGSEGV to handler", seg);
    report("keel: SIGSEGV in a guarded call to detection", kseg);
    report("bare throw to catch", thr);
    report("keel: throw in a guarded call to its catch", kthr);
  });
  t.join();
  std::printf("\n| bare, by cadence (1 ms cycle) | n | p50 µs | p99 µs | max µs |\n|---|---|---|---|---|\n");
  report("SIGSEGV on every cycle", keel::bench::measureSignalFloor(n, false, 1).latencies_ns);
  report("SIGSEGV every third cycle", keel::bench::measureSignalFloor(n, false, 3).latencies_ns);
  report("throw on every cycle", keel::bench::measureThrowFloor(n, false, 1).latencies_ns);
  report("throw every third cycle", keel::bench::measureThrowFloor(n, false, 3).latencies_ns);
  return 0;
}
