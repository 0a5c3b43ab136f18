/*
 * fixtest.h - helpers shared by the C unit tests: conversions between fixed-point formats and
 * double, and the two accuracy measures every firmware module is held to against its
 * double-precision reference: a worst-case error in LSB over a sweep, and an SNR in dB over a
 * trajectory. Host-only (tests may use double and libm; the firmware may not).
 */
#ifndef FIXTEST_H
#define FIXTEST_H

#include <stddef.h>
#include <stdint.h>

#include "fixmath.h"

static inline double fixtest_q15_to_d(q15_t x) { return (double)x / 32768.0; }
static inline double fixtest_q31_to_d(q31_t x) { return (double)x / 2147483648.0; }
static inline double fixtest_iq_to_d(iq_t x) { return (double)x / (double)(1L << FIX_IQ_Q); }
/* Run-time double -> format, rounded and saturated (the Q15()/IQ() macros are compile-time only). */
q15_t fixtest_d_to_q15(double x);
q31_t fixtest_d_to_q31(double x);
iq_t fixtest_d_to_iq(double x);

/* Accumulates a fixed-point trajectory against its double reference. */
typedef struct {
    double sig_energy;   /* sum of ref^2 */
    double err_energy;   /* sum of (val - ref)^2 */
    double max_abs_err;  /* worst |val - ref|, in the reference's units */
    size_t n;
} fixtest_acc_t;

void fixtest_acc_init(fixtest_acc_t *acc);
void fixtest_acc_add(fixtest_acc_t *acc, double val, double ref);
/* 10*log10(signal energy / error energy); 200 dB when the error is exactly zero. */
double fixtest_acc_snr_db(const fixtest_acc_t *acc);
/* Mean power of the reference signal accumulated: sig_energy / n (0 with no samples). */
double fixtest_acc_ref_power(const fixtest_acc_t *acc);
/* The SNR in dB of ideal rounding to a step of lsb on a signal of mean power p: the rounding
 * error is uniform over one step (variance lsb^2/12), so 10*log10(p / (lsb^2/12)). */
double fixtest_ideal_rounding_snr_db(double p, double lsb);
/* The same for the reference signal acc accumulated (mean power fixtest_acc_ref_power). */
double fixtest_acc_ideal_snr_db(const fixtest_acc_t *acc, double lsb);

/* CMocka-friendly assertions with a readable message (they call fail_msg on violation). */
void fixtest_assert_lsb(double val, double ref, double lsb, double max_lsb, const char *what);
void fixtest_assert_snr(const fixtest_acc_t *acc, double min_db, const char *what);

/* The main() of every C unit test: runs the listed CMocka tests (cmocka_unit_test(...) entries)
 * as one group named `group`, with `setup` (or NULL) run once before them, and returns the
 * number of failures. Expand it after <cmocka.h>. */
#define UNIT_TEST_MAIN(group, setup, ...)                                                        \
    int main(void)                                                                               \
    {                                                                                            \
        const struct CMUnitTest tests[] = {__VA_ARGS__};                                         \
        return cmocka_run_group_tests_name(group, tests, setup, NULL);                           \
    }

/* ---- Added for the fixmath suite (host-only helpers) ------------------------------------- */

/* pi (M_PI is not C99). */
#define FIXTEST_PI 3.14159265358979323846

/* Seeded pseudo-random numbers (SplitMix64): every run tests the same "random" inputs, so a
 * failure is reproducible, and the sequence is the same on every host. */
typedef struct {
    uint64_t state;
} fixtest_rng_t;

void fixtest_rng_seed(fixtest_rng_t *rng, uint64_t seed);
uint64_t fixtest_rng_u64(fixtest_rng_t *rng);
/* Uniform over the whole int32 / int16 range. */
int32_t fixtest_rng_i32(fixtest_rng_t *rng);
int16_t fixtest_rng_i16(fixtest_rng_t *rng);
/* Uniform int32 with a uniformly chosen bit length 0..31 (log-uniform magnitude, random sign):
 * exercises tiny and huge values equally, which a plain uniform draw almost never does. */
int32_t fixtest_rng_i32_log(fixtest_rng_t *rng);
/* Uniform double in [0, 1). */
double fixtest_rng_unit(fixtest_rng_t *rng);

/* Worst-case error over a sweep, in LSB, with the inputs that produced it (for the message). */
typedef struct {
    double max_lsb;     /* worst |val - ref| / lsb */
    double sum_sq_lsb;  /* for the rms figure */
    double worst_val;   /* value and reference at the worst point */
    double worst_ref;
    int64_t worst_in1;  /* the caller's inputs at the worst point */
    int64_t worst_in2;
    size_t n;
} fixtest_lsb_t;

void fixtest_lsb_init(fixtest_lsb_t *t);
/* Adds one point; in1/in2 are recorded with the worst point so the report can name them. */
void fixtest_lsb_add(fixtest_lsb_t *t, double val, double ref, double lsb, int64_t in1,
                     int64_t in2);
/* Adds one point whose error is already in LSB (e.g. formed exactly in integers). */
void fixtest_lsb_add_err(fixtest_lsb_t *t, double err_lsb, double val, double ref, int64_t in1,
                         int64_t in2);
/* Prints "what: max X LSB (bound B), rms R LSB, N points" and fails when X > B. */
void fixtest_lsb_check(const fixtest_lsb_t *t, double max_lsb, const char *what);

/* Prints "what: SNR X dB (bound B), max error E" and fails when X < B. */
void fixtest_snr_check(const fixtest_acc_t *acc, double min_db, const char *what);

/* Error in LSB of a fixed-point result res against the exact real value num / 2^shift clamped to
 * [lo, hi] (the saturating reference). num is a full 64-bit product or sum, which a double
 * cannot hold exactly (53-bit mantissa), so the difference is formed exactly in 128-bit
 * integers and only then converted; shift <= 62. */
double fixtest_err_lsb_exact(int64_t res, int64_t num, uint16_t shift, int64_t lo, int64_t hi);

#endif /* FIXTEST_H */
