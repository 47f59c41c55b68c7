// Our own instruction-set dispatch for the vectorized kernels (camera batches). A kernel is written
// once, as an always-inline body; simd::Kernel<body> compiles it three times, for x86-64-v4
// (AVX-512 with BW/DQ/VL), x86-64-v3 (AVX2, FMA) and the baseline (SSE2), and calls the clone of
// the instruction set chosen once per process: the best this CPU has, or the one the environment
// variable ANAMORPH_ISA names (avx512, avx2, baseline; never one the CPU lacks), so that AVX2
// machines can be measured on an AVX-512 one. The same choice configures Embree's device
// (accel/accel.cpp) when ANAMORPH_ISA is set.
//
// -ffp-contract=off (src/CMakeLists.txt) keeps the clones bit-identical to each other.
// A plain "avx512f" target is not enough: without AVX-512BW/VL GCC finds no vector type for loops
// that mix double lanes with bool masks and leaves them scalar. A lambda inside a kernel needs
// __attribute__((always_inline)): compiled for the default target, it is otherwise not inlined
// into the clone before the vectorizer runs, and leaves the loop scalar.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <type_traits>

#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define ANAMORPH_TARGET_AVX512 __attribute__((target("arch=x86-64-v4")))
#define ANAMORPH_TARGET_AVX2 __attribute__((target("arch=x86-64-v3")))
#else
#define ANAMORPH_TARGET_AVX512
#define ANAMORPH_TARGET_AVX2
#endif

// The loader-time clones these kernels used before (GCC's target_clones: ifunc resolvers, which
// ANAMORPH_ISA cannot steer). Only the denoiser (src/denoise) still uses them; a kernel there
// follows ANAMORPH_ISA once it becomes a simd::Kernel body. (Not under ThreadSanitizer: the
// ifunc resolvers run while the dynamic loader relocates the program, before TSan's runtime is
// up, and crash there.)
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && \
    !defined(__SANITIZE_THREAD__) && !defined(ANAMORPH_ONE_CLONE)
#define ANAMORPH_SIMD_CLONES \
  __attribute__((target_clones("arch=x86-64-v4", "arch=x86-64-v3", "default")))
#else
#define ANAMORPH_SIMD_CLONES
#endif

// A kernel's body: `ANAMORPH_KERNEL_BODY void f_body(...) { ... }`, then
// `constexpr simd::Kernel<f_body> f;` and calls `f(...)` as before.
#define ANAMORPH_KERNEL_BODY [[gnu::always_inline]] inline

namespace anamorph::simd {

enum class Isa { Baseline, Avx2, Avx512 };

// "baseline", "avx2", "avx512".
const char* name(Isa isa);
// The names above, and "sse2" for the baseline; nullopt for anything else.
std::optional<Isa> parse(std::string_view text);
// The best instruction set of this CPU that the kernels have a clone for.
Isa cpu_best();
// The instruction set the kernels run (decided on first use, then fixed for the process).
Isa active();
// What is wrong with ANAMORPH_ISA (an unknown name, or more than the CPU has; the kernels then run
// cpu_best()), for the program to report; empty when it is unset or fine.
std::string override_problem();
// Embree's device configuration: "isa=avx2" (sse2, avx512) when ANAMORPH_ISA chose the set, so
// that traversal runs the same instruction set as our kernels; nullptr otherwise (Embree picks).
const char* embree_config();

// The clones of one kernel body and the pointer to the active one.
template <auto Body>
struct Kernel;
template <class R, class... A, R (*Body)(A...)>
struct Kernel<Body> {
  using Fn = R (*)(A...);
#ifdef ANAMORPH_ONE_CLONE  // sanitized builds (CMakeLists.txt): every set runs the baseline code
  static R avx512(A... a) { return baseline(a...); }
  static R avx2(A... a) { return baseline(a...); }
#else
  ANAMORPH_TARGET_AVX512 static R avx512(A... a) { return Body(a...); }
  ANAMORPH_TARGET_AVX2 static R avx2(A... a) { return Body(a...); }
#endif
  static R baseline(A... a) { return Body(a...); }
  static Fn of(Isa isa) { return isa == Isa::Avx512 ? avx512 : isa == Isa::Avx2 ? avx2 : baseline; }
  static Fn get() {
    static const Fn fn = of(active());
    return fn;
  }
  R operator()(A... a) const { return get()(a...); }
};

// Calls kernel(m) with m = std::integral_constant<int, kFull> when n == kFull, the constant 1
// when n == 1, else n. Inlined into a clone, a kernel looping to a constant vectorizes without a
// remainder loop (full packets) or becomes straight-line code (one-at-a-time rays).
template <int kFull, class Body>
[[gnu::always_inline]] inline void with_trip_count(int n, Body&& kernel) {
  if (n == kFull)
    kernel(std::integral_constant<int, kFull>{});
  else if (n == 1)
    kernel(std::integral_constant<int, 1>{});
  else
    kernel(n);
}

}  // namespace anamorph::simd

namespace anamorph {
using simd::with_trip_count;
}  // namespace anamorph
