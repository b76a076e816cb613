#include "estimator/real_fft.hpp"

#include <fftw3.h>

#include <cstdlib>
#include <map>
#include <mutex>
#include <new>

namespace slidespec::estimator_detail {

namespace {

// 64-byte alignment for every buffer, so all arrays share the planning arrays' SIMD
// alignment and fftw_execute_dft_r2c picks the same codelets: bitwise-equal results.
constexpr std::size_t kAlignment = 64;

void* aligned_buffer(std::size_t bytes) {
  void* p = std::aligned_alloc(kAlignment, (bytes + kAlignment - 1) / kAlignment * kAlignment);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}

fftw_plan shared_plan(int length) {
  static std::mutex planner;
  static std::map<int, fftw_plan> plans;  // kept for the life of the process
  std::lock_guard<std::mutex> lock(planner);
  auto found = plans.find(length);
  if (found != plans.end()) return found->second;
  auto* in = static_cast<double*>(aligned_buffer(sizeof(double) * length));
  auto* out = static_cast<fftw_complex*>(aligned_buffer(sizeof(fftw_complex) * (length / 2 + 1)));
  fftw_plan plan = fftw_plan_dft_r2c_1d(length, in, out, FFTW_ESTIMATE);
  std::free(in);
  std::free(out);
  if (plan == nullptr) throw std::bad_alloc();
  plans.emplace(length, plan);
  return plan;
}

}  // namespace

RealFft::RealFft(int length)
    : plan_(shared_plan(length)),
      input_(static_cast<double*>(aligned_buffer(sizeof(double) * length))),
      output_(static_cast<std::complex<double>*>(
          aligned_buffer(sizeof(std::complex<double>) * (length / 2 + 1)))) {
  for (int n = 0; n < length; ++n) input_[n] = 0;
}

RealFft::~RealFft() {
  std::free(input_);
  std::free(output_);
}

void RealFft::execute() {
  fftw_execute_dft_r2c(static_cast<fftw_plan>(plan_), input_,
                       reinterpret_cast<fftw_complex*>(output_));
}

}  // namespace slidespec::estimator_detail
