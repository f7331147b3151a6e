#pragma once
// Counts heap allocations in the test binary: every global operator new, and (where the
// build wraps them, GRIP_TEST_WRAP_MALLOC) malloc, calloc and realloc. NoHeapScope also
// tells Eigen (EIGEN_RUNTIME_NO_MALLOC) to assert on any allocation inside the scope.
#include <Eigen/Core>

namespace grip_test {

/// Heap allocations made by this process since start.
long allocation_count();

/// Within its lifetime Eigen may not allocate (asserts in builds without NDEBUG);
/// allocations() tells how many allocations of any kind happened inside it.
class NoHeapScope {
 public:
  NoHeapScope() : start_(allocation_count()) { Eigen::internal::set_is_malloc_allowed(false); }
  ~NoHeapScope() { Eigen::internal::set_is_malloc_allowed(true); }
  NoHeapScope(const NoHeapScope&) = delete;
  NoHeapScope& operator=(const NoHeapScope&) = delete;
  long allocations() const { return allocation_count() - start_; }

 private:
  long start_;
};

}  // namespace grip_test
