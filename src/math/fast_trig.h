// Sine and cosine as straight-line code that compilers vectorize: a loop calling sincos_poly
// becomes AVX-512 / AVX2 code in the AVX-512 / AVX2 clones of math/simd.h, where std::sin stays a
// scalar library call (glibc's vector variants need -ffast-math). Camera kernels use it in their
// one-at-a-time and batched paths alike, so both give the same bits on every ISA.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

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
  // Estrin's scheme (pairs, then powers r^4 and r^8): a third of Horner's dependency chain, which
  // is what one-at-a-time rays wait on.
  const double r4 = r2 * r2, r8 = r4 * r4;
  const double s01 = -1.6666666666666666e-01 + 8.333333333333333e-03 * r2;  // -1/3!, 1/5!
  const double s23 = -1.984126984126984e-04 + 2.7557319223985893e-06 * r2;  // -1/7!, 1/9!
  const double s45 = -2.505210838544172e-08 + 1.6059043836821613e-10 * r2;  // -1/11!, 1/13!
  const double s67 = -7.647163731819816e-13 + 2.8114572543455206e-15 * r2;  // -1/15!, 1/17!
  const double ps = (s01 + s23 * r4) + (s45 + s67 * r4) * r8;
  const double sr = r + r * r2 * ps;
  const double c01 = 4.1666666666666664e-02 - 1.388888888888889e-03 * r2;  // 1/4!, -1/6!
  const double c23 = 2.48015873015873e-05 - 2.755731922398589e-07 * r2;    // 1/8!, -1/10!
  const double c45 = 2.08767569878681e-09 - 1.1470745597729725e-11 * r2;   // 1/12!, -1/14!
  const double c67 = 4.779477332387385e-14 - 1.5619206968586225e-16 * r2;  // 1/16!, -1/18!
  const double pc = (c01 + c23 * r4) + (c45 + c67 * r4) * r8;
  const double cr = (1 - 0.5 * r2) + r4 * pc;
  // Quadrant q = k mod 4: sin(r + q pi/2) = sr, cr, -sr, -cr; cos = cr, -sr, -cr, sr.
  const int q = int(k) & 3;  // two's complement: also right for negative k
  const bool odd = q == 1 || q == 3;
  const double s0 = odd ? cr : sr, c0 = odd ? sr : cr;
  *s = q >= 2 ? -s0 : s0;
  *c = (q == 1 || q == 2) ? -c0 : c0;
}

// e^x as straight-line code that vectorizes like sincos_poly, within a few ulp for |x| < 700.
// x = k ln2 + r with |r| <= ln2/2 (ln2 in two parts), e^r by Taylor to degree 13 (truncation
// below 1e-17), then the exponent k put into the bits.
inline double exp_poly(double x) {
  constexpr double kLog2e = 1.4426950408889634, kLn2Hi = 0.6931471803691238,
                   kLn2Lo = 1.9082149292705877e-10, kRound = 6755399441055744.0;
  const double k = (x * kLog2e + kRound) - kRound;
  const double r = (x - k * kLn2Hi) - k * kLn2Lo;
  const double r2 = r * r, r4 = r2 * r2, r8 = r4 * r4;
  // 1 + r + r^2/2! + ... + r^13/13!, Estrin's scheme.
  const double p01 = 1 + r, p23 = 0.5 + 1.6666666666666666e-01 * r;
  const double p45 = 4.1666666666666664e-02 + 8.333333333333333e-03 * r;
  const double p67 = 1.388888888888889e-03 + 1.984126984126984e-04 * r;
  const double p89 = 2.48015873015873e-05 + 2.7557319223985893e-06 * r;
  const double p1011 = 2.755731922398589e-07 + 2.505210838544172e-08 * r;
  const double p1213 = 2.08767569878681e-09 + 1.6059043836821613e-10 * r;
  const double lo = (p01 + p23 * r2) + (p45 + p67 * r2) * r4;
  const double hi = (p89 + p1011 * r2) + p1213 * r4;
  const double er = lo + hi * r8;
  const int64_t bits = (int64_t(int32_t(k)) + 1023) << 52;
  return er * std::bit_cast<double>(bits);
}

}  // namespace anamorph
