// glibc's libmvec has vector cos and sin (x86-64 vector ABI, <= 4 ulp); <math.h> declares them
// only under -ffast-math, which we do not use. Declaring them here lets the engine's orientation
// loops vectorise: scalar libm calls were a quarter of a triangle collision's time.
#pragma once

#include <cstddef>

extern "C" {
#pragma omp declare simd notinbranch
double cos(double) noexcept;
#pragma omp declare simd notinbranch
double sin(double) noexcept;
}

namespace ricochet::detail {

/// c[i] = cos(th[i]) and s[i] = sin(th[i]) for i < n. One out-of-line loop for every path of the
/// engine (the generic step and the fused kernel), so that both call the same vector variant
/// and give the same bits on any build (RICOCHET_NATIVE or not): an inlined 8-lane loop is
/// unrolled before it is vectorised and falls back to scalar sincos. n a multiple of the vector
/// width (the engine's lanes come in chunks of 8) leaves no scalar remainder.
/// (th is not const: GCC 12 does not vectorise the loop over a const input; it then fuses the
/// two calls into scalar sincos.)
[[gnu::noinline]] inline void cos_sin_lanes(double* th_in, double* c_out, double* s_out,
                                            std::size_t n) {
  double* __restrict th = th_in;
  double* __restrict c = c_out;
  double* __restrict s = s_out;
#pragma omp simd
  for (std::size_t i = 0; i < n; ++i) {
    c[i] = ::cos(th[i]);
    s[i] = ::sin(th[i]);
  }
}

}  // namespace ricochet::detail
