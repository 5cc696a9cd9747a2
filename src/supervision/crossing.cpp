#include "supervision/crossing.hpp"

#include <fmt/format.h>

#include <bit>
#include <cstdlib>
#include <optional>

#include "runtime/component_core.hpp"
#include "runtime/executor.hpp"
#include "runtime/futex.hpp"

namespace keel::supervision {
namespace {

namespace ipc = runtime::ipc;

std::string what(const plan::PlannedConnection& c) {
  return fmt::format("port_connection {}.{} -> {}.{}", c.source.component, c.source.port, c.target.component,
                     c.target.port);
}

struct FreeAligned {
  void operator()(std::byte* p) const { std::free(p); }
};

}  // namespace

std::vector<std::size_t> crossingConnections(const plan::Plan& plan) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < plan.connections.size(); ++i) {
    const auto& c = plan.connections[i];
    if (c.type == PortKind::Service) continue;  // the plan rejects those that cross
    if (plan.processOf(c.source.component) != plan.processOf(c.target.component)) out.push_back(i);
  }
  return out;
}

std::size_t ringSlots(const plan::Plan& plan, const plan::PlannedConnection& c) {
  std::size_t queue = 1;
  if (const plan::PlannedInstance* target = plan.find(c.target.component)) {
    for (const auto& d : target->profile->data_ports)
      if (d.name == c.target.port) queue = d.queue_size;
    for (const auto& e : target->profile->event_ports)
      if (e.name == c.target.port) queue = e.queue_size;
  }
  return std::bit_ceil(std::max<std::size_t>({queue, 64}));
}

std::optional<std::string> crossingProblem(const plan::Plan& plan, const plan::PlannedConnection& c,
                                           const detail::PortBase& port) {
  if (port.byteSize() != 0) return std::nullopt;
  return fmt::format(
      "{}: {}: a value of type '{}' cannot cross processes ('{}' runs in {}, '{}' in {}): values are copied "
      "between processes as bytes, so the type must be trivially copyable (no pointers, std::string or "
      "std::vector inside)",
      c.where.str(), what(c), port.typeName(), c.source.component,
      plan::describeProcess(plan.processOf(c.source.component)), c.target.component,
      plan::describeProcess(plan.processOf(c.target.component)));
}

struct Crossings::Writer final : detail::ByteSink {
  std::optional<ipc::RingBuffer> ring;
  std::atomic<std::uint32_t> epoch{0};  // 0: not (yet) the writer
  std::unique_ptr<detail::ByteEnd> outlet;
  detail::PortBase* port = nullptr;
  Fenced fenced;
  runtime::Warn warn;
  std::string name;
  std::atomic<bool> warned{false};

  void deliverBytes(const void* value) override {
    const std::uint32_t e = epoch.load(std::memory_order_acquire);
    if (e == 0) return;  // a standby's component does not run; nothing to write yet
    auto pushed = ring->push(e, value);
    if (!pushed) {
      if (!warned.exchange(true)) warn(fmt::format("{}: {} (values on it are lost)", name, pushed.error().message));
      return;
    }
    if (*pushed == ipc::PushStatus::Fenced) fenced();
  }
};

struct Crossings::Reader final : runtime::ExternalInput {
  std::optional<ipc::RingBuffer> ring;
  std::optional<ipc::RingReader> cursor;
  std::unique_ptr<detail::ByteInlet> inlet;
  detail::PortBase* port = nullptr;
  std::unique_ptr<std::byte, FreeAligned> buffer;
  std::atomic<std::uint64_t>* consumed = nullptr;  // in the session: where a successor resumes
  runtime::Executor* executor = nullptr;           // drains it (null: the pump thread does)
  std::atomic<bool> stop{false};
  std::atomic<std::uint64_t> dropped{0};
  std::thread thread;

  std::optional<runtime::FutexWaiter> announceSleep() override { return cursor->announceSleep(); }
  void endSleep() override { cursor->endSleep(); }
  bool drain() override {
    bool any = false;
    while (cursor->pop(buffer.get())) {
      inlet->deliverBytes(buffer.get());
      consumed->store(cursor->next(), std::memory_order_relaxed);
      any = true;
    }
    dropped.store(cursor->dropped(), std::memory_order_relaxed);
    return any;
  }

  void pump() {
    while (!stop.load(std::memory_order_acquire))
      if (cursor->wait(std::chrono::seconds(1))) drain();
  }
};

Crossings::Crossings() = default;
Crossings::~Crossings() { stop(); }

Result<void> Crossings::connect(const plan::Plan& plan, const std::string& process, ipc::Session& session,
                                std::map<std::size_t, int> fds, const Find& find, std::chrono::milliseconds wait,
                                const Fenced& fenced, const runtime::Warn& warn) {
  std::string errors;
  const std::vector<std::size_t> crossing = crossingConnections(plan);
  const auto deadline = std::chrono::steady_clock::now() + wait;
  // Writers first: they never wait, so every reader's writer gets to its ring (in any process).
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t k = 0; k < crossing.size(); ++k) {
      const plan::PlannedConnection& c = plan.connections[crossing[k]];
      const std::string from = plan.processOf(c.source.component), to = plan.processOf(c.target.component);
      const bool writes = from == process, reads = to == process;
      if (writes != (pass == 0)) continue;
      auto fd = fds.find(k);
      if (!writes && !reads) continue;
      if (fd == fds.end()) {
        errors += fmt::format("{}: {}: no ring was handed to this process\n", c.where.str(), what(c));
        continue;
      }
      ipc::SharedMemory region = ipc::SharedMemory::adoptUnmapped(fd->second, fmt::format("keel-ring-{}", k));
      fds.erase(fd);
      const profile::Endpoint& mine = writes ? c.source : c.target;
      Component* comp = find(mine.component);
      detail::PortBase* port = comp ? runtime::coreOf(*comp).findPort(mine.port) : nullptr;
      if (!port) {
        errors += fmt::format("{}: {}: no port '{}' on '{}'\n", c.where.str(), what(c), mine.port, mine.component);
        continue;
      }
      if (auto problem = crossingProblem(plan, c, *port)) {
        errors += *problem + "\n";
        continue;
      }
      const std::size_t size = port->byteSize();
      std::atomic<std::uint32_t>& ready = session.ringReady(k);
      if (writes) {
        auto w = std::make_unique<Writer>();
        Result<ipc::RingBuffer> ring = fail("");
        constexpr const char* kAbandoned = "the run stopped before the ring was set up";
        const std::uint32_t state = ready.load(std::memory_order_acquire);
        if (state == ipc::kRingAbandoned) {
          ring = fail(kAbandoned);
        } else if (state == ipc::kRingPending) {
          // Laid out by the writer: a writer that died halfway (sized, not ready) is done again.
          const std::size_t slots = ringSlots(plan, c);
          auto sized = region.sizeTo(ipc::RingBuffer::bytesFor(size, slots));
          if (!sized) sized = region.map();
          ring = sized ? ipc::RingBuffer::create(std::move(region), size, slots)
                       : Result<ipc::RingBuffer>(sized.error());
          // Unless keel run abandoned it meanwhile (the run stops): then its readers have gone.
          std::uint32_t pending = ipc::kRingPending;
          if (ring && !ready.compare_exchange_strong(pending, ipc::kRingReady, std::memory_order_acq_rel))
            ring = fail(kAbandoned);
          if (ring) runtime::futexWakeAll(ready, runtime::FutexScope::Shared);
        } else if (auto mapped = region.map(); mapped) {
          ring = ipc::RingBuffer::attach(std::move(region), size);
        } else {
          ring = mapped.error();
        }
        if (!ring) {
          errors += fmt::format("{}: {}: {}\n", c.where.str(), what(c), ring.error().message);
          continue;
        }
        w->ring.emplace(std::move(*ring));
        w->port = port;
        w->fenced = fenced;
        w->warn = warn;
        w->name = what(c);
        w->outlet = static_cast<detail::OutputPortBase*>(port)->attachBytes(*w);
        writers_.push_back(std::move(w));
      } else {
        while (ready.load(std::memory_order_acquire) == ipc::kRingPending &&
               std::chrono::steady_clock::now() < deadline)
          runtime::futexWait(ready, ipc::kRingPending, &deadline, runtime::FutexScope::Shared);
        if (ready.load(std::memory_order_acquire) == ipc::kRingAbandoned) {
          errors += fmt::format("{}: {}: the run stopped before its writer '{}' ({}) set up the ring\n", c.where.str(),
                                what(c), c.source.component, plan::describeProcess(from));
          continue;
        }
        if (ready.load(std::memory_order_acquire) == ipc::kRingPending) {
          errors += fmt::format("{}: {}: its writer '{}' ({}) did not set up the ring within {} ms\n", c.where.str(),
                                what(c), c.source.component, plan::describeProcess(from), wait.count());
          continue;
        }
        Result<ipc::RingBuffer> ring = fail("");
        if (auto mapped = region.map(); mapped) ring = ipc::RingBuffer::attach(std::move(region), size);
        else ring = mapped.error();
        if (!ring) {
          errors += fmt::format("{}: {}: {}\n", c.where.str(), what(c), ring.error().message);
          continue;
        }
        auto r = std::make_unique<Reader>();
        r->ring.emplace(std::move(*ring));
        r->cursor.emplace(*r->ring);
        r->port = port;
        r->consumed = &session.ringConsumed(k);
        r->inlet = static_cast<detail::InputPortBase*>(port)->makeByteInlet();
        const std::size_t align = 64;
        r->buffer.reset(static_cast<std::byte*>(std::aligned_alloc(align, (size + align - 1) / align * align)));
        readers_.push_back(std::move(r));
      }
    }
  for (const auto& [k, fd] : fds) ipc::SharedMemory::adoptUnmapped(fd);  // rings of no connection: closed
  if (!errors.empty()) {
    errors.pop_back();
    return fail(errors);
  }
  return {};
}

Result<void> Crossings::takeOver() {
  for (auto& w : writers_) {
    auto t = w->ring->takeOver();
    if (!t) return fail(fmt::format("{}: {}", w->name, t.error().message));
    w->epoch.store(t->epoch, std::memory_order_release);
  }
  return {};
}

void Crossings::attach() {
  std::map<runtime::Executor*, std::size_t> per_executor;
  for (auto& r : readers_) {
    if (!runtime::futexWaitAnySupported()) continue;
    runtime::Executor* ex = runtime::coreOf(r->port->owner()).executor.load(std::memory_order_acquire);
    if (ex == nullptr || per_executor[ex] == runtime::Executor::kMaxExternalInputs) continue;
    ++per_executor[ex];
    ex->addInput(*r);
    r->executor = ex;
  }
}

void Crossings::resume() {
  for (auto& r : readers_) r->cursor->seek(r->consumed->load(std::memory_order_relaxed));
}

void Crossings::start() {
  for (auto& r : readers_) {
    if (r->executor || r->thread.joinable()) continue;
    r->thread = std::thread([p = r.get()] { p->pump(); });
  }
}

void Crossings::stop() {
  for (auto& r : readers_) {
    if (!r->thread.joinable()) continue;  // read by its executor, which stops with it
    r->stop.store(true, std::memory_order_release);
    r->ring->wakeReaders();
  }
  for (auto& r : readers_)
    if (r->thread.joinable()) r->thread.join();
}

std::vector<runtime::Wire> Crossings::wires() const {
  std::vector<runtime::Wire> out;
  for (const auto& w : writers_) out.push_back({&w->outlet->connection(), w->port, nullptr});
  for (const auto& r : readers_) out.push_back({&r->inlet->connection(), nullptr, r->port});
  return out;
}

std::uint64_t Crossings::dropped() const {
  std::uint64_t n = 0;
  for (const auto& r : readers_) n += r->dropped.load(std::memory_order_relaxed);
  return n;
}

}  // namespace keel::supervision
