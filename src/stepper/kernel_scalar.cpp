// The scalar path: the same kernel on one lane, the oracle for every SIMD path.
#include "stepper/kernel.hpp"

namespace slidespec::stepper::scalar {
using Batch = double;
constexpr int width = 1;
inline Batch load(const double* p) { return *p; }
inline void store(double* p, Batch x) { *p = x; }
inline Batch broadcast(double x) { return x; }
inline bool any_passed(Batch x, Batch mark) { return x >= mark; }
#include "stepper/kernel.inc"
}  // namespace slidespec::stepper::scalar

namespace slidespec::stepper {
GroupKernel scalar_kernel(int dimension, int inputs) { return scalar::select_kernel(dimension, inputs); }
}  // namespace slidespec::stepper
