#include "math/simd.h"

#include <cstdlib>

namespace anamorph::simd {

const char* name(Isa isa) {
  switch (isa) {
    case Isa::Avx512:
      return "avx512";
    case Isa::Avx2:
      return "avx2";
    case Isa::Baseline:
      break;
  }
  return "baseline";
}

std::optional<Isa> parse(std::string_view text) {
  if (text == "avx512") return Isa::Avx512;
  if (text == "avx2") return Isa::Avx2;
  if (text == "baseline" || text == "sse2") return Isa::Baseline;
  return std::nullopt;
}

Isa cpu_best() {
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
  __builtin_cpu_init();
  if (__builtin_cpu_supports("x86-64-v4")) return Isa::Avx512;
  if (__builtin_cpu_supports("x86-64-v3")) return Isa::Avx2;
#endif
  return Isa::Baseline;
}

namespace {

struct Choice {
  Isa isa;
  bool overridden = false;  // ANAMORPH_ISA named a usable set
  std::string problem;
};

Choice decide() {
  const Isa best = cpu_best();
  const char* env = std::getenv("ANAMORPH_ISA");
  if (!env || !*env) return {best, false, {}};
  const auto wanted = parse(env);
  if (!wanted)
    return {best, false,
            "ANAMORPH_ISA=" + std::string(env) +
                " is not an instruction set (valid: avx512, avx2, baseline)"};
  if (int(*wanted) > int(best))
    return {best, false,
            "ANAMORPH_ISA=" + std::string(env) + ": this CPU has no " + name(*wanted) +
                " (the best it has is " + name(best) + ")"};
  return {*wanted, true, {}};
}

const Choice& choice() {
  static const Choice c = decide();
  return c;
}

}  // namespace

Isa active() { return choice().isa; }

std::string override_problem() { return choice().problem; }

const char* embree_config() {
  if (!choice().overridden) return nullptr;
  switch (choice().isa) {
    case Isa::Avx512:
      return "isa=avx512";
    case Isa::Avx2:
      return "isa=avx2";
    case Isa::Baseline:
      break;
  }
  return "isa=sse2";
}

}  // namespace anamorph::simd
