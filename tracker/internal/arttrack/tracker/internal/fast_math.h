// Branch-free exp and erfc for the likelihood's hot loop, where libm's exact
// functions cost most of a pixel. Inline, allocation-free, no lookup tables.
//
// fast_exp: Cody-Waite reduction x = n ln 2 + r, |r| <= ln 2 / 2, a degree-10
// Taylor polynomial for exp(r) (truncation below 1e-13 relative) and 2^n
// built in the exponent bits. Relative error below 1e-13 for x in [-708, 709];
// exactly 0 below -708 (where exp is subnormal or 0).
//
// fast_erfc: the Chebyshev fit of erfc(z) exp(z^2) in t = 1 / (1 + z / 2)
// (Press et al., Numerical Recipes, 2nd ed., Sec. 6.2, "erfcc"), fractional
// error below 1.2e-7 for every z >= 0, with erfc(-z) = 2 - erfc(z). Checked
// against std::erfc in tests/tracker/fast_math_test.cc.
//
// Each comes as a scalar function and as a lane-wise one on Double4 or
// Double8 (GCC vector extensions: AVX2 / AVX-512 registers where the target
// has them, SSE2 pairs otherwise); all compute the same operations, lane by
// lane, so they give the same bits.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <type_traits>

namespace arttrack {

// The lane-wise functions (and the polynomials they share with the scalar
// ones) are always inlined, so no vector crosses a call; GCC's note that such
// calls change the ABI without AVX does not apply.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

namespace fast_math_detail {

constexpr double kLog2e = 1.4426950408889634;
constexpr double kLn2Hi = 0.693147180369123816490;  // ln 2 in 32 bits: n kLn2Hi is exact
constexpr double kLn2Lo = 1.90821492927058770002e-10;
constexpr double kShifter = 0x1.8p52;  // adding it rounds to an integer in the low bits

// The polynomials, written once for a double and for a GCC vector of them
// (T times a double, plus a double, works lane-wise), so the scalar and
// lane-wise functions compute the same operations.

// exp(r), |r| <= 0.347: Taylor to degree 10 (next term 0.347^11 / 11! < 1e-13).
template <class T>
[[gnu::always_inline]] inline T exp_taylor(T r) {
  T p = r * (1.0 / 3628800) + 1.0 / 362880;
  p = p * r + 1.0 / 40320;
  p = p * r + 1.0 / 5040;
  p = p * r + 1.0 / 720;
  p = p * r + 1.0 / 120;
  p = p * r + 1.0 / 24;
  p = p * r + 1.0 / 6;
  p = p * r + 0.5;
  p = p * r + 1.0;
  return p * r + 1.0;
}

// The exponent of erfc(z) = t exp(-z^2 + poly(t)), t = 1 / (1 + z / 2).
template <class T>
[[gnu::always_inline]] inline T erfc_exponent_poly(T t) {
  T p = t * 0.17087277 - 0.82215223;
  p = p * t + 1.48851587;
  p = p * t - 1.13520398;
  p = p * t + 0.27886807;
  p = p * t - 0.18628806;
  p = p * t + 0.09678418;
  p = p * t + 0.37409196;
  p = p * t + 1.00002368;
  return p * t - 1.26551223;
}

}  // namespace fast_math_detail

// exp(x) to 1e-13 relative for x in [-708, 709]; 0 for x < -708 (and NaN in, NaN out).
inline double fast_exp(double x) {
  using namespace fast_math_detail;
  // Quiet comparisons and unconditional arithmetic: the compiler may turn
  // the selects into blends and vectorise loops that call this.
  const bool underflow = std::isless(x, -708.0);
  const double xc = underflow ? -708.0 : (std::isgreater(x, 709.0) ? 709.0 : x);
  const double shifted = xc * kLog2e + kShifter;
  const double n = shifted - kShifter;  // round(x / ln 2)
  const double r = (xc - n * kLn2Hi) - n * kLn2Lo;
  const double p = exp_taylor(r);
  // 2^n from the integer in the shifter's low bits (n in [-1022, 1023]).
  const std::int64_t ni =
      std::bit_cast<std::int64_t>(shifted) - std::bit_cast<std::int64_t>(kShifter);
  const double two_n = std::bit_cast<double>((ni + 1023) << 52);
  const double result = p * two_n;
  return underflow ? 0.0 : result;
}

// erfc(y) to 1.2e-7 relative for every finite y (0 where erfc(y) < ~1e-307).
inline double fast_erfc(double y) {
  const bool negative = std::isless(y, 0.0);
  const double z = std::fabs(y);
  const double t = 1.0 / (1.0 + 0.5 * z);
  const double p = fast_math_detail::erfc_exponent_poly(t);
  const double e = t * fast_exp(p - z * z);
  const double reflected = 2.0 - e;
  return negative ? reflected : e;
}

// Two, four and eight doubles, lane-wise (two: SSE2, what every x86-64 has).
using Double2 = double __attribute__((vector_size(16)));
using Double4 = double __attribute__((vector_size(32)));
using Double8 = double __attribute__((vector_size(64)));

// A GCC vector of doubles (comparisons give the same-sized integer vector).
template <class V>
concept DoubleLanes =
    std::is_same_v<V, Double2> || std::is_same_v<V, Double4> || std::is_same_v<V, Double8>;

template <DoubleLanes V>
[[gnu::always_inline]] inline V broadcast(double x) {
  return V{} + x;
}

// fast_exp() lane-wise (same bits).
template <DoubleLanes V>
[[gnu::always_inline]] inline V fast_exp(V x) {
  using I = decltype(x < x);
  const V lo = broadcast<V>(-708.0), hi = broadcast<V>(709.0);
  const V shifter = broadcast<V>(fast_math_detail::kShifter);
  const I underflow = x < lo;
  const V xc = underflow ? lo : (x > hi ? hi : x);
  const V shifted = xc * fast_math_detail::kLog2e + shifter;
  const V n = shifted - shifter;
  const V r = (xc - n * fast_math_detail::kLn2Hi) - n * fast_math_detail::kLn2Lo;
  const V p = fast_math_detail::exp_taylor(r);
  const I ni = (I)shifted - (I)shifter;
  const V two_n = (V)((ni + 1023) << 52);
  return underflow ? broadcast<V>(0.0) : p * two_n;
}

// fast_erfc() lane-wise (same bits).
template <DoubleLanes V>
[[gnu::always_inline]] inline V fast_erfc(V y) {
  const auto negative = y < 0.0;
  const V z = negative ? -y : y;
  const V t = 1.0 / (1.0 + 0.5 * z);
  const V p = fast_math_detail::erfc_exponent_poly(t);
  const V e = t * fast_exp(p - z * z);
  return negative ? 2.0 - e : e;
}

#pragma GCC diagnostic pop

}  // namespace arttrack
