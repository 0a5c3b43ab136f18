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

/* CMocka-friendly assertions with a readable message (they call fail_msg on violation). */
void fixtest_assert_lsb(double val, double ref, double lsb, double max_lsb, const char *what);
void fixtest_assert_snr(const fixtest_acc_t *acc, double min_db, const char *what);

#endif /* FIXTEST_H */
