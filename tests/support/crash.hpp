// Test support: real faults, made so that neither the compiler nor UBSan turns them into
// something else (a store to a low unmapped page; a hardware integer divide by zero).
#pragma once

#include <csignal>
#include <cstdint>

namespace keel::test {

[[gnu::noinline]] inline void segfault() {
  volatile std::uintptr_t addr = 0x10;         // page 0 is never mapped
  *reinterpret_cast<volatile int*>(addr) = 1;  // NOLINT(performance-no-int-to-ptr): the crash wanted
}

[[gnu::noinline]] inline void divideByZero() {
#if defined(__x86_64__)
  asm volatile("xor %%ecx, %%ecx\n\tmov $1, %%eax\n\tcltd\n\tidivl %%ecx" ::: "eax", "ecx", "edx");
#else
  std::raise(SIGFPE);
#endif
}

}  // namespace keel::test
