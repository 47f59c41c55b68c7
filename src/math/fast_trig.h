// Sine and cosine as straight-line code that compilers vectorize: a loop calling sincos_poly
// becomes AVX-512 / AVX2 code under target_clones, where std::sin stays a scalar library call
// (glibc's vector variants need -ffast-math). Camera kernels use it in their one-at-a-time and
// batched paths alike, so both give the same bits on every ISA.
#pragma once

#include <cmath>

namespace anamorph {

// |error| within a few ulp of the true value for |x| < 1e5 (the camera's angles stay below 4 pi).
inline void sincos_poly(double x, double* s, double* c) {
  // x = k pi/2 + r with |r| <= pi/4; pi/2 in three parts (Cody-Waite) so k * part is exact.
  constexpr double kTwoOverPi = 0.6366197723675814;
  constexpr double kPio2Hi = 1.5707963267341256, kPio2Mid = 6.077100506303966e-11,
                   kPio2Lo = 2.0222662487959506e-21;
  // Round to nearest by adding and removing 1.5 * 2^52 (exact below 2^51; std::nearbyint and
  // std::floor would keep GCC from vectorizing the loop).
  constexpr double kRound = 6755399441055744.0;
  const double k = (x * kTwoOverPi + kRound) - kRound;
  const double r = ((x - k * kPio2Hi) - k * kPio2Mid) - k * kPio2Lo;
  const double r2 = r * r;
  // Taylor series to degree 17 (sine) and 18 (cosine): truncation below 3e-18 on |r| <= pi/4.
  double ps = 2.8114572543455206e-15;  // 1/17!
  ps = ps * r2 - 7.647163731819816e-13;
  ps = ps * r2 + 1.6059043836821613e-10;
  ps = ps * r2 - 2.505210838544172e-08;
  ps = ps * r2 + 2.7557319223985893e-06;
  ps = ps * r2 - 1.984126984126984e-04;
  ps = ps * r2 + 8.333333333333333e-03;
  ps = ps * r2 - 1.6666666666666666e-01;
  const double sr = r + r * r2 * ps;
  double pc = -1.5619206968586225e-16;  // -1/18!
  pc = pc * r2 + 4.779477332387385e-14;
  pc = pc * r2 - 1.1470745597729725e-11;
  pc = pc * r2 + 2.08767569878681e-09;
  pc = pc * r2 - 2.755731922398589e-07;
  pc = pc * r2 + 2.48015873015873e-05;
  pc = pc * r2 - 1.388888888888889e-03;
  pc = pc * r2 + 4.1666666666666664e-02;
  const double cr = (1 - 0.5 * r2) + r2 * r2 * pc;
  // Quadrant q = k mod 4: sin(r + q pi/2) = sr, cr, -sr, -cr; cos = cr, -sr, -cr, sr.
  const int q = int(k) & 3;  // two's complement: also right for negative k
  const bool odd = q == 1 || q == 3;
  const double s0 = odd ? cr : sr, c0 = odd ? sr : cr;
  *s = q >= 2 ? -s0 : s0;
  *c = (q == 1 || q == 2) ? -c0 : c0;
}

}  // namespace anamorph
