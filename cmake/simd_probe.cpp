// Prints the widest SIMD path of cmake/simd.cmake that the machine running it supports.
#include <cstdio>

int main() {
  __builtin_cpu_init();
  std::puts(__builtin_cpu_supports("x86-64-v3") ? "avx2" : "baseline");
  return 0;
}
