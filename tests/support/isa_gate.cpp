// Runs a test binary built for an x86-64 micro-architecture level only where this CPU has
// that level; elsewhere it reports the test skipped (exit code 77, CTest's SKIP_RETURN_CODE)
// instead of letting the binary die of an illegal instruction. It is itself compiled for the
// baseline, so it runs on every x86-64 CPU.
//   isa_gate <level> <test binary> [arguments...]      level: x86-64, x86-64-v3 or x86-64-v4
#include <unistd.h>

#include <cstdio>
#include <cstring>

namespace {

// The features of a level that a CPU can lack while it has the level below. Feature names
// both g++ and clang accept; every CPU with AVX2, FMA and BMI2 also has the level's MOVBE,
// LZCNT and F16C.
bool has_level(const char* level) {
  __builtin_cpu_init();
  if (std::strcmp(level, "x86-64") == 0) return true;
  const bool v3 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi") &&
                  __builtin_cpu_supports("bmi2");
  if (std::strcmp(level, "x86-64-v3") == 0) return v3;
  const bool v4 = v3 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
                  __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") &&
                  __builtin_cpu_supports("avx512cd");
  if (std::strcmp(level, "x86-64-v4") == 0) return v4;
  std::fprintf(stderr, "isa_gate: unknown level %s\n", level);
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: isa_gate <level> <test binary> [arguments...]\n");
    return 2;
  }
  if (!has_level(argv[1])) {
    std::printf("skipped: this CPU lacks %s (the binary was built, not run)\n", argv[1]);
    return 77;
  }
  execv(argv[2], argv + 2);
  std::perror("isa_gate: execv");
  return 2;
}
