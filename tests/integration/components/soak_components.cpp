// Components for keel soak's tests (tests/integration/soak_test.cpp).
//   Leaky: periodic; pushes a level in [0, 100] on `level` each cycle. Its onInitialize opens
//   `leak_fds` descriptors and allocates `leak_kb` KiB it never gives back (kept reachable, so
//   that LeakSanitizer does not call it a leak at exit): what a soak must see grow run after run.
//   The blocks live in a static of this library, which it keeps loaded for good (RTLD_NODELETE):
//   unloaded at the end of a run, the static's destructor would give them back. GCC keeps such a
//   library loaded anyway (its function-local statics are unique symbols); clang does not.
#include <dlfcn.h>
#include <fcntl.h>
#include <unistd.h>

#include <cstring>
#include <mutex>
#include <vector>

#include <keel/component.hpp>

namespace itest {

class Leaky : public keel::Component {
 public:
  keel::OutputDataPort<double> level{this, "level"};
  keel::ReturnCode onInitialize() override {
    for (int i = property<int>("leak_fds", 0); i > 0; --i) (void)::open("/dev/null", O_RDONLY);  // never closed
    const auto kb = static_cast<std::size_t>(property<int>("leak_kb", 0));
    if (kb > 0) {
      pinLibrary();
      std::vector<char> block(kb * 1024);
      std::memset(block.data(), 1, block.size());  // resident, not just reserved
      std::lock_guard lock(mutex());
      hoard().push_back(std::move(block));
    }
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    level.push(50.0);
    return keel::ReturnCode::Ok;
  }

 private:
  // Marks this library, already loaded, never to be unloaded.
  static void pinLibrary() {
    Dl_info info{};
    if (::dladdr(reinterpret_cast<void*>(&pinLibrary), &info) != 0 && info.dli_fname != nullptr)
      (void)::dlopen(info.dli_fname, RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);  // a reference never closed
  }
  static std::vector<std::vector<char>>& hoard() {
    static std::vector<std::vector<char>> blocks;
    return blocks;
  }
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
};

}  // namespace itest

KEEL_REGISTER_COMPONENT_AS(itest::Leaky, "Leaky")
