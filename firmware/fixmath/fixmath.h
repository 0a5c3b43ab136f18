/*
 * fixmath.h - portable fixed-point core for the DTC firmware (C99, freestanding).
 *
 * Formats
 *   q15_t    int16_t, value = raw / 2^15, range [-1, 1 - 2^-15].
 *   q31_t    int32_t, value = raw / 2^31, range [-1, 1 - 2^-31].
 *   iq_t     int32_t, value = raw / 2^FIX_IQ_Q with FIX_IQ_Q = 24, range [-128, 128 - 2^-24].
 *   angle_t  uint16_t per-unit angle, 65536 = one turn (2*pi). It wraps modulo one turn BY DESIGN:
 *            unsigned arithmetic on angles is well defined and is the only wrap-around allowed.
 *
 * Why Q24 for the IQ type. All firmware quantities are per-unit. In this drive the largest
 * values seen are over-currents and intermediate sums of a few per-unit (the trip level is below
 * 8 pu), so 7 integer bits (+-128) leave ample headroom. The fraction must resolve the smallest
 * per-sample change the estimators make: the voltage-model low-pass leak psi*wc*Ts at wc = 5 rad/s,
 * Ts = 50 us is about 2.5e-4 pu of flux per sample, i.e. 8 LSB in Q15 (a 12 % quantisation of the
 * leak, which turns the low-pass into a dead band) but 4200 LSB in Q24. Q24 is also TI IQmath's
 * default GLOBAL_Q, so the TI build can map these functions onto IQmath unchanged.
 *
 * Rules (see docs/DESIGN-NOTES.md): every multiply widens first; every sum that can overflow
 * saturates; right shifts of negative numbers happen only in this module (arithmetic shift on
 * every compiler the project targets: gcc, arm-none-eabi-gcc, avr-gcc and TI cl2000 document it).
 * No function here divides. Literals go through Q15()/Q31()/IQ()/ANGLE() so the format is stated.
 */
#ifndef FIXMATH_H
#define FIXMATH_H

#include <stdbool.h>
#include <stdint.h>

typedef int16_t q15_t;
typedef int32_t q31_t;
typedef int32_t iq_t;
typedef uint16_t angle_t;

#define FIX_IQ_Q 24

#define Q15_MAX ((q15_t)INT16_MAX)
#define Q15_MIN ((q15_t)INT16_MIN)
#define Q31_MAX ((q31_t)INT32_MAX)
#define Q31_MIN ((q31_t)INT32_MIN)
#define IQ_MAX ((iq_t)INT32_MAX)
#define IQ_MIN ((iq_t)INT32_MIN)

/* Compile-time literal conversions, rounded to nearest, saturated to the format's range.
 * Arguments must be constant expressions (they are folded by the compiler; a run-time argument
 * would pull in floating point, which the firmware-rules check rejects). */
#define FIX_RND_(x) ((x) >= 0 ? 0.5 : -0.5)
#define Q15(x)                                                                                 \
    ((q15_t)((x) >= (32767.5 / 32768.0) ? INT16_MAX                                            \
             : (x) <= -1.0              ? INT16_MIN                                            \
                                        : (int32_t)((x) * 32768.0 + FIX_RND_(x))))
#define Q31(x)                                                                                 \
    ((q31_t)((x) >= (2147483647.5 / 2147483648.0) ? INT32_MAX                                  \
             : (x) <= -1.0                        ? INT32_MIN                                  \
                                                  : (int32_t)((x) * 2147483648.0 + FIX_RND_(x))))
#define IQ(x)                                                                                  \
    ((iq_t)((x) >= (2147483647.5 / 16777216.0) ? INT32_MAX                                     \
            : (x) <= -128.0                     ? INT32_MIN                                    \
                                                : (int32_t)((x) * 16777216.0 + FIX_RND_(x))))
/* Irrational factors at full Q31 precision, as integers: Q31() is evaluated in the compiler's
 * double, which is 32 bits on the C28x COFF ABI and on avr-gcc, and would round these to 24
 * significant bits there (1/sqrt(3): 1239850240 instead of 1239850262), so the same firmware
 * would compute 1-LSB different results on the DSP and in SIL. Each value is round(x * 2^31)
 * in 64-bit arithmetic; tests/unit checks them against the double reference. */
#define FIX_Q31_THIRD ((q31_t)715827883L)       /* 1/3 */
#define FIX_Q31_INV_SQRT3 ((q31_t)1239850262L)  /* 1/sqrt(3) */
#define FIX_Q31_SQRT3_2 ((q31_t)1859775393L)    /* sqrt(3)/2 */
/* A ratio of whole numbers n/d (0 <= n/d < 128 for IQ, < 1 for Q31), rounded to nearest in
 * integer arithmetic at compile time: the same on every target, where IQ(n.0 / d) is not
 * (above). n, d: integer constants, d > 0. tests/rules/check_fix_literals.py finds the literals
 * that need it. */
#define IQ_FRAC(n, d) ((iq_t)((((int64_t)(n) << FIX_IQ_Q) + (int64_t)(d) / 2) / (int64_t)(d)))
#define Q31_FRAC(n, d) ((q31_t)((((int64_t)(n) << 31) + (int64_t)(d) / 2) / (int64_t)(d)))
/* Angle in turns (1.0 = 2*pi), rounded to the nearest 1/65536 turn (halves up) and reduced
 * modulo one turn: ANGLE(0.25) = 90 degrees, ANGLE(-0.25) = ANGLE(0.75) = 270 degrees.
 * Valid for |turns| < 32768. The cast truncates towards zero, so FIX_FLOOR_ subtracts 1 where
 * that rounded a negative value up (a plain cast made ANGLE(-0.25) 49153). No large bias is
 * added: on compilers whose double is 32 bits (TI C28x COFF ABI, avr-gcc) a bias would eat the
 * fraction bits. */
#define FIX_FLOOR_(v) ((int32_t)(v) - ((v) < (int32_t)(v) ? 1 : 0))
#define ANGLE(turns) ((angle_t)((uint32_t)FIX_FLOOR_((turns) * 65536.0 + 0.5) & 0xFFFFU))

/* ------------------------------------------------------------------------------------------ */
/* Saturation                                                                                  */

/* Scaling and overflow: clamps a 32-bit value to [Q15_MIN, Q15_MAX]. Exact, no rounding. */
static inline q15_t q15_sat(int32_t x)
{
    if (x > INT16_MAX) {
        return Q15_MAX;
    }
    if (x < INT16_MIN) {
        return Q15_MIN;
    }
    return (q15_t)x;
}

/* On a 64-bit host built with GCC or Clang, fix_sat32 takes the clamp's direction out of line
 * (fix_sat32_clamp, cold): the path every call takes is then the sign extension, the compare
 * and a branch not taken, where the compiler otherwise forms the clamp value on every call and
 * selects it (host instructions per step, dtc_budget). The same values; the 32- and 16-bit
 * targets keep the inline form. */
#if UINTPTR_MAX > 0xFFFFFFFFU && defined(__GNUC__)
__attribute__((cold, noinline, unused)) static int32_t fix_sat32_clamp(int64_t x)
{
    return x < 0 ? INT32_MIN : INT32_MAX;
}
#define FIX_SAT32_OUT(x) __builtin_expect((x) != 0, 0)
#define FIX_SAT32_CLAMP(x) fix_sat32_clamp(x)
#else
#define FIX_SAT32_OUT(x) (x)
#define FIX_SAT32_CLAMP(x) ((x) < 0 ? INT32_MIN : INT32_MAX)
#endif

/* Scaling and overflow: clamps a 64-bit value to the int32 range (q31_t and iq_t alike).
 * x is in range exactly when its low 32 bits, read as an int32, equal it: one sign extension and
 * one compare on the path every call takes (on a 32-bit target: the high word against the low
 * word's sign), the direction of the clamp only on the saturating path (FIX_SAT32_CLAMP). The
 * low word is converted without an implementation-defined conversion; compilers turn that into a
 * plain move. */
static inline int32_t fix_sat32(int64_t x)
{
    const uint32_t u = (uint32_t)x; /* the low 32 bits (modulo 2^32, C99 6.3.1.3) */
    const int32_t lo = u <= (uint32_t)INT32_MAX ? (int32_t)u : -(int32_t)(~u) - 1;
    if (FIX_SAT32_OUT((int64_t)lo != x)) {
        return FIX_SAT32_CLAMP(x);
    }
    return lo;
}

/* Scaling and overflow: clamps x to [lo, hi] (any 32-bit format; requires lo <= hi). */
static inline int32_t fix_clamp32(int32_t x, int32_t lo, int32_t hi)
{
    if (x > hi) {
        return hi;
    }
    if (x < lo) {
        return lo;
    }
    return x;
}

/* ------------------------------------------------------------------------------------------ */
/* Shifts (the only place negative values are shifted right)                                   */

/* FIX_WORD64: 1 where a 64-bit sum is one register (a 64-bit host), 0 on the 32- and 16-bit
 * targets (Cortex-M0, AVR, C28x), where it is a pair or four of them. fix_rshift_rnd32, fix_add32
 * and fix_sub32 take the form that is short there: the 64-bit one on a 64-bit host (for the sums
 * with GCC or Clang, the 32-bit sum and its overflow flag), the 32-bit one elsewhere. On a
 * 64-bit host the 32-bit form is also there, as fix_..._w32, and
 * tests/unit/test_fixmath_basic.c finds both equal for every input it tries. */
#if UINTPTR_MAX > 0xFFFFFFFFU
#define FIX_WORD64 1
#define FIX_W32_(name) name##_w32
#else
#define FIX_WORD64 0
#define FIX_W32_(name) name
#endif

/* Arithmetic right shift with round-half-up: (x + 2^(n-1)) >> n, 1 <= n <= 31.
 * Scaling and overflow: the 64-bit form does the rounding add in 64 bits, so it cannot overflow.
 * The 32-bit form does without it: with x = q 2^n + r, 0 <= r < 2^n, (x + 2^(n-1)) >> n is q
 * plus 1 when r >= 2^(n-1), which is bit n-1 of x; so (x >> n) + ((x >> (n-1)) & 1), which
 * cannot overflow (|x >> n| <= 2^30). */
static inline int32_t FIX_W32_(fix_rshift_rnd32)(int32_t x, uint16_t n) { return (x >> n) + ((x >> (n - 1U)) & 1); }
#if FIX_WORD64
static inline int32_t fix_rshift_rnd32(int32_t x, uint16_t n)
{
    return (int32_t)(((int64_t)x + ((int64_t)1 << (n - 1U))) >> n);
}
#endif

/* Arithmetic right shift with round-half-up on a 64-bit value, 1 <= n <= 62, saturated to int32.
 * Scaling and overflow: the rounding add cannot overflow for |x| <= 2^62 (every 32x32 product,
 * including INT32_MIN * INT32_MIN = 2^62, is inside); the result saturates. */
static inline int32_t fix_rshift_rnd64_sat32(int64_t x, uint16_t n)
{
    return fix_sat32((x + ((int64_t)1 << (n - 1U))) >> n);
}

/* ------------------------------------------------------------------------------------------ */
/* Q15 arithmetic                                                                               */

/* Scaling and overflow: sum formed in 32 bits, saturated to Q15. */
static inline q15_t q15_add(q15_t a, q15_t b) { return q15_sat((int32_t)a + (int32_t)b); }
/* Scaling and overflow: difference formed in 32 bits, saturated to Q15. */
static inline q15_t q15_sub(q15_t a, q15_t b) { return q15_sat((int32_t)a - (int32_t)b); }
/* Scaling and overflow: -(-1.0) saturates to Q15_MAX. */
static inline q15_t q15_neg(q15_t a) { return q15_sat(-(int32_t)a); }
/* Scaling and overflow: |-1.0| saturates to Q15_MAX. */
static inline q15_t q15_abs(q15_t a) { return q15_sat(a < 0 ? -(int32_t)a : (int32_t)a); }

/* Q15 x Q15 -> Q15, rounded to nearest. Scaling and overflow: the product is exact in 32 bits
 * (Q30); only (-1.0) * (-1.0) exceeds Q15 and saturates to Q15_MAX. Error <= 0.5 LSB. */
static inline q15_t q15_mul(q15_t a, q15_t b)
{
    return q15_sat(fix_rshift_rnd32((int32_t)a * (int32_t)b, 15U));
}

/* Q15 x Q15 -> Q30 (exact 32-bit product, for accumulating before one rounding step).
 * Scaling and overflow: |result| <= 2^30, cannot overflow. */
static inline int32_t q15_mul_q30(q15_t a, q15_t b) { return (int32_t)a * (int32_t)b; }

/* ------------------------------------------------------------------------------------------ */
/* Q31 / IQ arithmetic (both are int32; the functions are format-agnostic where noted)         */

/* The int32 of the low 32 bits u (modulo 2^32), without an implementation-defined conversion
 * (as fix_sat32). */
static inline int32_t fix_from_u32(uint32_t u)
{
    return u <= (uint32_t)INT32_MAX ? (int32_t)u : -(int32_t)(~u) - 1;
}

/* Scaling and overflow: the sum saturated to int32. Same format in and out (Q31 or IQ). The
 * 64-bit form saturates the 64-bit sum. The 32-bit form: the sum modulo 2^32 is the true one
 * unless a and b have one sign and it has the other (then the true sum lies beyond the range on
 * a's side), which is exactly where the 64-bit sum saturates. */
static inline int32_t FIX_W32_(fix_add32)(int32_t a, int32_t b)
{
    const uint32_t ua = (uint32_t)a, ub = (uint32_t)b, s = ua + ub;
    if ((((ua ^ s) & (ub ^ s)) >> 31) != 0U) {
        return a < 0 ? INT32_MIN : INT32_MAX;
    }
    return fix_from_u32(s);
}
/* Scaling and overflow: the difference saturated to int32. Same format in and out. The 32-bit
 * form: the difference modulo 2^32 is the true one unless a and b have different signs and it
 * has b's sign (then the true difference lies beyond the range on a's side). */
static inline int32_t FIX_W32_(fix_sub32)(int32_t a, int32_t b)
{
    const uint32_t ua = (uint32_t)a, ub = (uint32_t)b, d = ua - ub;
    if ((((ua ^ ub) & (ua ^ d)) >> 31) != 0U) {
        return a < 0 ? INT32_MIN : INT32_MAX;
    }
    return fix_from_u32(d);
}
#if FIX_WORD64 && defined(__GNUC__)
/* The 64-bit host's form with GCC or Clang: the sum in 32 bits and the processor's overflow flag
 * (__builtin_add_overflow, __builtin_sub_overflow), which is set exactly where the 64-bit sum
 * leaves the int32 range; the true sum then lies beyond it on a's side (as the 32-bit form). */
static inline int32_t fix_add32(int32_t a, int32_t b)
{
    int32_t s;
    if (__builtin_add_overflow(a, b, &s)) {
        return FIX_SAT32_CLAMP((int64_t)a);
    }
    return s;
}
static inline int32_t fix_sub32(int32_t a, int32_t b)
{
    int32_t d;
    if (__builtin_sub_overflow(a, b, &d)) {
        return FIX_SAT32_CLAMP((int64_t)a);
    }
    return d;
}
#elif FIX_WORD64
static inline int32_t fix_add32(int32_t a, int32_t b) { return fix_sat32((int64_t)a + (int64_t)b); }
static inline int32_t fix_sub32(int32_t a, int32_t b) { return fix_sat32((int64_t)a - (int64_t)b); }
#endif
/* Scaling and overflow: -INT32_MIN saturates to INT32_MAX. The 32-bit form: -a is defined for
 * every other int32 (|a| <= 2^31 - 1), so INT32_MIN is the only input to test. On the 32-bit
 * targets the 64-bit form's negation and saturation test took an out-of-line call of 14
 * Cortex-M0 instructions and two blocks (cross-cm0 -Os); this one is inlined. (A branch-free
 * form, -a minus the sign bit a and -a share only at INT32_MIN, measured 10 C28x-estimate cycles
 * worse on the PM image's worst ISR.) */
static inline int32_t FIX_W32_(fix_neg32)(int32_t a) { return a == INT32_MIN ? INT32_MAX : -a; }
#if FIX_WORD64
static inline int32_t fix_neg32(int32_t a) { return fix_sat32(-(int64_t)a); }
#endif
/* Scaling and overflow: |INT32_MIN| saturates to INT32_MAX. (Kept in the 64-bit form on every
 * target: a 32-bit form, with a test or without, is one cross-cm0 -Os keeps out of line, a call
 * per use that runs from flash on the F2812 IM image, whose linker list does not name it: IM worst
 * ISR 5720 -> 5871 C28x-estimate cycles, measured.) */
static inline int32_t fix_abs32(int32_t a) { return fix_sat32(a < 0 ? -(int64_t)a : (int64_t)a); }

static inline q31_t q31_add(q31_t a, q31_t b) { return fix_add32(a, b); }
static inline q31_t q31_sub(q31_t a, q31_t b) { return fix_sub32(a, b); }
static inline iq_t iq_add(iq_t a, iq_t b) { return fix_add32(a, b); }
static inline iq_t iq_sub(iq_t a, iq_t b) { return fix_sub32(a, b); }

/* Q31 x Q31 -> Q31, high part of the 64-bit product, rounded (as IQmath's _IQ31rsmpy).
 * Scaling and overflow: product exact in 64 bits (Q62); (-1)*(-1) saturates to Q31_MAX.
 * Error <= 0.5 LSB. */
static inline q31_t q31_mul(q31_t a, q31_t b)
{
    return fix_rshift_rnd64_sat32((int64_t)a * (int64_t)b, 31U);
}

/* Q31 x Q31 -> Q31 as q31_mul, for a factor k > Q31_MIN (a constant such as 1/3 or 1/sqrt(3)):
 * the same rounded result, without the saturation test, which only (-1)*(-1) needs.
 * Scaling and overflow: |a k| <= 2^31 (2^31 - 1), so (a k + 2^30) >> 31 lies in
 * [-2^31 + 1, 2^31 - 1]: it cannot overflow. Error <= 0.5 LSB. */
static inline q31_t q31_mul_k(q31_t a, q31_t k)
{
    return (q31_t)(((int64_t)a * (int64_t)k + ((int64_t)1 << 30)) >> 31);
}

/* IQ x IQ -> IQ (Q24), rounded and saturated (as IQmath's _IQrsmpy).
 * Scaling and overflow: product exact in 64 bits (Q48); |a*b| >= 128 saturates. Error <= 0.5 LSB. */
static inline iq_t iq_mpy(iq_t a, iq_t b)
{
    return fix_rshift_rnd64_sat32((int64_t)a * (int64_t)b, (uint16_t)FIX_IQ_Q);
}

/* IQ x Q15 -> IQ: scales an IQ value by a Q15 gain in [-1, 1).
 * Scaling and overflow: product exact in 64 bits (Q39); only INT32_MIN * -1.0 saturates.
 * Error <= 0.5 LSB. */
static inline iq_t iq_mpy_q15(iq_t a, q15_t b)
{
    return fix_rshift_rnd64_sat32((int64_t)a * (int64_t)b, 15U);
}

/* IQ x unsigned Q16 gain -> IQ: scales an IQ value by g/65536, g in [0, 1). Used for small
 * positive gains (e.g. wc*Ts) where Q15 would waste a bit.
 * Scaling and overflow: product exact in 64 bits; |result| <= |a|, cannot overflow. */
static inline iq_t iq_mpy_uq16(iq_t a, uint16_t g)
{
    return fix_rshift_rnd64_sat32((int64_t)a * (int64_t)g, 16U);
}

/* a*b + c*d, IQ, rounded once (a two-term dot product; a difference by negating c or d).
 * Scaling and overflow: each product is exact in 64 bits (|a*b| <= 2^62); their sum is below 2^63
 * except when all four operands are IQ_MIN (2^62 + 2^62), which the callers' operands (bounded
 * per-unit quantities) never are; the result saturates to the IQ range. Error <= 0.5 LSB. */
static inline iq_t iq_mac2(iq_t a, iq_t b, iq_t c, iq_t d)
{
    return fix_rshift_rnd64_sat32((int64_t)a * (int64_t)b + (int64_t)c * (int64_t)d, (uint16_t)FIX_IQ_Q);
}

/* Clamp an IQ value to [lo, hi] (as IQmath's _IQsat, argument order lo, hi). */
static inline iq_t iq_sat(iq_t x, iq_t lo, iq_t hi) { return fix_clamp32(x, lo, hi); }

/* ------------------------------------------------------------------------------------------ */
/* Conversions                                                                                  */

/* Q15 -> IQ (Q24): exact (value preserved, shift left by 9). */
static inline iq_t iq_from_q15(q15_t a) { return (iq_t)((int32_t)a * (int32_t)512); }
/* IQ -> Q15: rounded, saturated to [-1, 1 - 2^-15]. Error <= 0.5 LSB of Q15 inside the range. */
static inline q15_t q15_from_iq(iq_t a) { return q15_sat(fix_rshift_rnd32(a, (uint16_t)(FIX_IQ_Q - 15))); }
/* Q15 -> Q31: exact. */
static inline q31_t q31_from_q15(q15_t a) { return (q31_t)((int32_t)a * (int32_t)65536); }
/* Q31 -> Q15: rounded, saturated (rounding 0x7FFF8000 and above would exceed Q15_MAX). */
static inline q15_t q15_from_q31(q31_t a) { return q15_sat(fix_rshift_rnd32(a, 16U)); }
/* IQ -> Q31: IQ values outside [-1, 1) saturate. Exact inside. */
static inline q31_t q31_from_iq(iq_t a) { return fix_sat32((int64_t)a * (int64_t)128); }
/* Q31 -> IQ: rounded (drops 7 fraction bits). Cannot overflow. */
static inline iq_t iq_from_q31(q31_t a) { return fix_rshift_rnd32(a, (uint16_t)(31 - FIX_IQ_Q)); }
/* Integer -> IQ, saturated to +-128. */
static inline iq_t iq_from_int(int16_t n) { return fix_sat32((int64_t)n * ((int64_t)1 << FIX_IQ_Q)); }

/* ------------------------------------------------------------------------------------------ */
/* Square root and vector magnitude (fixmath.c; a seeded multiply-only reciprocal-root Newton    */
/* estimate made exact by integer comparison, no division: the digit-by-digit root's results)  */

/* floor(sqrt(x)) for a 64-bit unsigned x. Result fits in 32 bits.
 * Scaling and overflow: integer in, integer out; exact floor (0 <= sqrt(x) - result < 1). */
uint32_t fix_isqrt64(uint64_t x);

/* round(sqrt(x)) for a 64-bit unsigned x, and floor(sqrt(x)) in *floor_out (both from one
 * digit-by-digit root; at most 32 iterations). Scaling and overflow: integer in, integer out; the
 * rounded root is <= 2^32 (returned in 64 bits), error < 0.5 (no ties: (r + 1/2)^2 is never an
 * integer); the floor fits in 32 bits. */
uint64_t fix_isqrt_rnd(uint64_t x, uint32_t *floor_out);

/* sqrt of an IQ value (Q24 -> Q24), rounded to nearest (error < 0.5 LSB). Negative input
 * returns 0. Scaling and overflow: sqrt(x * 2^24) of an argument < 2^55; the
 * result is below 2^27.5 (sqrt(128) pu), cannot overflow. */
iq_t iq_sqrt(iq_t x);

/* sqrt(a^2 + b^2) in IQ (Q24), rounded to nearest (error < 0.5 LSB). Scaling and overflow: sum of
 * squares formed in 64 bits (Q48, <= 2^63, cannot overflow); the result saturates
 * to IQ_MAX when it would reach 128 (possible only when |a| or |b| exceeds 90.5 pu). */
iq_t iq_mag(iq_t a, iq_t b);

/* sqrt(a^2 + b^2) in Q15, rounded to nearest (error < 0.5 LSB). Scaling and overflow: sum of
 * squares in Q30 (<= 2^31); saturates to Q15_MAX when the result rounds to 1.0. */
q15_t q15_mag(q15_t a, q15_t b);

/* Sum of squares a^2 + b^2 as unsigned Q48 (IQ inputs). Exact; for comparing a magnitude with a
 * threshold without the square root. */
static inline uint64_t iq_sumsq_q48(iq_t a, iq_t b)
{
    return (uint64_t)((int64_t)a * (int64_t)a) + (uint64_t)((int64_t)b * (int64_t)b);
}

/* ------------------------------------------------------------------------------------------ */
/* Sine and cosine of a per-unit angle (fixmath.c; quarter-wave table of 256 segments, linear  */
/* interpolation)                                                                              */

/* sin(2*pi*angle/65536) in Q15. Error against the true sine <= 1.16 LSB by construction (table
 * rounding 0.5 + interpolation 0.15 + final rounding 0.5); 1.0007 LSB measured over all 65536
 * angles (the worst case is at the peaks, where 1.0 saturates to Q15_MAX), 0.37 LSB rms.
 * Exactly odd (sin(-x) = -sin(x)); never returns Q15_MIN.
 * Scaling and overflow: the angle is folded into the first quadrant by symmetry; table values
 * within [0, 32767]; interpolation stays between two neighbouring entries; the sign is applied
 * last, so no overflow. */
q15_t fix_sin(angle_t angle);
/* cos(2*pi*angle/65536) in Q15, = fix_sin(angle + quarter turn). Same bounds. */
q15_t fix_cos(angle_t angle);
/* Both, *sin_out = fix_sin(angle) and *cos_out = fix_cos(angle) bit for bit, from one quadrant
 * decode (fixmath.c): for a caller that needs the pair. */
void fix_sincos(angle_t angle, q15_t *sin_out, q15_t *cos_out);

/* ------------------------------------------------------------------------------------------ */
/* Flux-vector position without an arctangent                                                  */

/* 60-degree sector of the vector (alpha, beta), sectors centred on 0, 60, ..., 300 degrees:
 * returns 1 for [-30, 30), 2 for [30, 90), 3 for [90, 150), 4 for [150, 210), 5 for [210, 270),
 * 6 for [270, 330). (alpha, beta) = (0, 0) returns 1. Decided from the signs of
 * p = sqrt(3)*beta - alpha, q = sqrt(3)*beta + alpha and alpha, with sqrt(3) in Q30 and the
 * products formed exactly in 64 bits (< 2^63, no overflow for any inputs); the 30 + 60k degree
 * rays it implements lie within 9e-11 rad of the true ones. Boundary rays belong to the sector that starts there, except the
 * +-90 degree rays, which go to sectors 3 and 5 (a measure-zero choice; both are adjacent). */
uint16_t fix_sector6(iq_t alpha, iq_t beta);

/* Quadrant of (alpha, beta): 1 for [0, 90), 2 for [90, 180), 3 for [180, 270), 4 for [270, 360)
 * degrees. (0, 0) returns 1. Sign tests only; inline (the FSTP sector of the PM law's 50 us path,
 * where a call costs as much as the tests). */
static inline uint16_t fix_quadrant(iq_t alpha, iq_t beta)
{
    if (alpha > 0 && beta >= 0) {
        return 1U;
    }
    if (alpha <= 0 && beta > 0) {
        return 2U;
    }
    if (alpha < 0 && beta <= 0) {
        return 3U;
    }
    if (alpha >= 0 && beta < 0) {
        return 4U;
    }
    return 1U; /* origin */
}

/* ------------------------------------------------------------------------------------------ */
/* Angle and magnitude of a vector (fixmath.c; CORDIC vectoring, shifts and adds, no division) */

/* Polar form of (x, y): *angle = atan2(y, x) as angle_t (65536 = one turn) and *mag =
 * sqrt(x^2 + y^2) in the format of x and y (IQ). (0, 0) gives angle 0, magnitude 0.
 * Method: a half-turn pre-rotation puts the vector in the right half plane, then 16 CORDIC
 * micro-rotations by atan(2^-i) drive y to zero (16: the residual rotation atan(2^-15) is 0.32
 * angle_t LSB, below the resolution of the result); the rotation angles are summed in a 32-bit turn
 * accumulator (table of atan(2^-i) in Q32 turns, each rounded to 0.5 of 2^-32 turn) and rounded to
 * angle_t once. The iteration runs in 32 bits on x, y scaled by a power of two (up to 2^28
 * for the smallest, down to 2^-3 for the largest) that puts the top bit of max(|x|, |y|) at bit
 * 28, so that every vector keeps 28 to 29 significant bits through the truncated shifts.
 * Error: angle 0.82 angle LSB (residual rotation 0.32 LSB, table and final rounding 0.5) plus
 * 16 truncated shifts of at most 2^-28 rad each relative to |v|, so <= 0.82 LSB for every
 * nonzero vector; magnitude <= 1 LSB + 6e-8 relative (CORDIC gain 1/K in Q24 and the truncated
 * shifts, about 2^-28 of |v| each, measured in tests/unit/test_im_est.c; for |x| or |y| >= 2^29
 * the pre-shift drops the low 1 to 3 bits; the residual rotation's cosine error is 5e-10). Scaled by 2^6 (max(|x|, |y|) in
 * [2^22, 2^23), 0.25 to 0.5 pu) the result is that of the same iteration on 64-bit values
 * scaled by 2^6, bit for bit (tests/unit/test_im_est.c).
 * Scaling and overflow: |xs|, |ys| < 2^29 after the scaling, |v| < 2^29.5, grown by the CORDIC
 * gain K = 1.65 to < 2^30.3 (int32); the gain product K |v| 2^s * (1/K in Q24) < 2^54 is
 * formed in 64 bits and shifted back by 24 + s with rounding. The magnitude saturates to IQ_MAX
 * (only when sqrt(x^2 + y^2) >= 128 pu). */
void fix_polar(iq_t x, iq_t y, angle_t *angle, iq_t *mag);
/* fix_polar in two halves, for a caller that spreads its cost over two periods (the IM law's
 * rotor-flux angle, im_est.h): fix_polar_begin scales (x, y) and runs micro-rotations 0..7 into
 * *s, fix_polar_end runs 8..15 on it and forms the angle and the magnitude; begin then end is
 * fix_polar bit for bit (fix_polar is that pair). The state: the rotated vector (xs, ys), the
 * turn accumulator and the magnitude's shift back 24 + up - down (0: the vector was (0, 0)). */
typedef struct {
    int32_t xs, ys;
    uint32_t turn;
    uint16_t shift;
} fix_polar_t;
void fix_polar_begin(iq_t x, iq_t y, fix_polar_t *s);
void fix_polar_end(fix_polar_t *s, angle_t *angle, iq_t *mag);

/* ------------------------------------------------------------------------------------------ */
/* Reciprocal, small complex factors (fixmath.c), a high-resolution integrator (inline)       */

/* Two Newton steps y <- y (2 - x y) towards 1/x (x > 0, IQ): quadratic convergence for
 * 0 < y < 2/x (the error e = 1 - x y becomes e^4); the caller keeps y from call to call. IQ
 * throughout, products rounded; |y| <= 128 pu (saturating). */
iq_t iq_recip_newton(iq_t y, iq_t x);

/* (a + j b) <- (a + j b)(1 + j x): a - x b, b + x a. IQ, products rounded, sums saturated.
 * iq_cmul_1jx_inline is the same for a caller that keeps it in its own frame (one call less on
 * its stack chain); iq_cmul_1jx, out of line, is it. */
static inline void iq_cmul_1jx_inline(iq_t x, iq_t *a, iq_t *b)
{
    const iq_t a0 = *a;
    *a = iq_sub(a0, iq_mpy(x, *b));
    *b = iq_add(*b, iq_mpy(x, a0));
}
void iq_cmul_1jx(iq_t x, iq_t *a, iq_t *b);

/* Integrator with 8 fractional bits below IQ: *acc (Q32 pu, +-0.5 pu, saturating) += k x
 * (IQ x IQ rounded to Q32); returns *acc rounded to IQ. For increments below one IQ LSB per
 * step (an IQ state would stop short by 0.5 LSB / k of input). Inline: its caller runs it every
 * period (dtc_dcsupp), where a call costs as much as its body. */
static inline iq_t q32_integrate(int32_t *acc, iq_t k, iq_t x)
{
    *acc = fix_add32(*acc, fix_rshift_rnd64_sat32((int64_t)k * (int64_t)x, 16U));
    return fix_rshift_rnd32(*acc, 8U);
}

#endif /* FIXMATH_H */
