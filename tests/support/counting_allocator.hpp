// Counts heap allocations in a test program, so a test can show that a piece of code (a World
// step, a distance lookup) allocates nothing. Linking the acdr_counting_allocator target into a
// test executable replaces the global operator new and operator new[] with counting versions
// (the C++ standard allows a program to replace them); nothing else changes.
#pragma once

namespace acdr::test_support {

/// Heap allocations (operator new and new[], any overload) since the program started.
long heap_allocations();

/// Allocations made while `f()` runs.
template <class F>
long allocations_during(F&& f) {
  const long before = heap_allocations();
  f();
  return heap_allocations() - before;
}

}  // namespace acdr::test_support
