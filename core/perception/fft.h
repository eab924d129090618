// A radix-2 fast Fourier transform sized once, then run without allocating.
#pragma once

#include <complex>
#include <cstddef>
#include <span>
#include <vector>

namespace marvin::perception {

class Fft {
 public:
  // `size` must be a power of two >= 2; throws std::invalid_argument otherwise.
  explicit Fft(std::size_t size);

  std::size_t size() const { return size_; }

  // In-place forward transform of `data` (size() values): X[k] = sum x[n] e^{-2 pi i k n / N}.
  // Allocates nothing. Not thread-safe per object only in the sense that the object is const
  // here: several threads may transform different buffers with one Fft at once.
  void forward(std::span<std::complex<float>> data) const;

 private:
  std::size_t size_;
  std::vector<std::size_t> bit_reverse_;
  std::vector<std::complex<float>> twiddles_;  // e^{-2 pi i k / N}, k < N/2
};

}  // namespace marvin::perception
