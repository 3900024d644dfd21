// glibc's libmvec has vector cos and sin (x86-64 vector ABI, <= 4 ulp); <math.h> declares them
// only under -ffast-math, which we do not use. Declaring them here lets the engine's orientation
// loops vectorise: scalar libm calls were a quarter of a triangle collision's time.
#pragma once

extern "C" {
#pragma omp declare simd notinbranch
double cos(double) noexcept;
#pragma omp declare simd notinbranch
double sin(double) noexcept;
}
