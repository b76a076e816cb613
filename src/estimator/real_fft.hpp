// A real-to-complex FFT of one length with this object's own aligned buffers. The FFTW
// plan behind it is made once per length (FFTW_ESTIMATE, so the algorithm never depends
// on timing) and shared by every instance; creating plans is serialised by a mutex,
// executing them with new arrays is thread-safe.
#pragma once

#include <complex>
#include <memory>

namespace slidespec::estimator_detail {

class RealFft {
 public:
  explicit RealFft(int length);
  ~RealFft();
  RealFft(const RealFft&) = delete;
  RealFft& operator=(const RealFft&) = delete;

  double* input() { return input_; }
  /// Bins 0 .. length/2 of the last transform.
  const std::complex<double>* output() const { return output_; }
  void execute();

 private:
  void* plan_;
  double* input_;
  std::complex<double>* output_;
};

}  // namespace slidespec::estimator_detail
