#include "fixtest.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <cmocka.h>

static int64_t round_sat(double x, double lo, double hi)
{
    double r = nearbyint(x);
    if (r > hi) {
        r = hi;
    }
    if (r < lo) {
        r = lo;
    }
    return (int64_t)r;
}

q15_t fixtest_d_to_q15(double x) { return (q15_t)round_sat(x * 32768.0, -32768.0, 32767.0); }
q31_t fixtest_d_to_q31(double x)
{
    return (q31_t)round_sat(x * 2147483648.0, -2147483648.0, 2147483647.0);
}
iq_t fixtest_d_to_iq(double x)
{
    return (iq_t)round_sat(x * (double)(1L << FIX_IQ_Q), -2147483648.0, 2147483647.0);
}

void fixtest_acc_init(fixtest_acc_t *acc)
{
    const fixtest_acc_t empty = {0.0, 0.0, 0.0, 0U};
    *acc = empty;
}

void fixtest_acc_add(fixtest_acc_t *acc, double val, double ref)
{
    double e = val - ref;
    acc->sig_energy += ref * ref;
    acc->err_energy += e * e;
    if (fabs(e) > acc->max_abs_err) {
        acc->max_abs_err = fabs(e);
    }
    acc->n++;
}

double fixtest_acc_ref_power(const fixtest_acc_t *acc)
{
    return acc->n > 0U ? acc->sig_energy / (double)acc->n : 0.0;
}

double fixtest_ideal_rounding_snr_db(double p, double lsb)
{
    return 10.0 * log10(p / (lsb * lsb / 12.0));
}

double fixtest_acc_ideal_snr_db(const fixtest_acc_t *acc, double lsb)
{
    return fixtest_ideal_rounding_snr_db(fixtest_acc_ref_power(acc), lsb);
}

double fixtest_acc_snr_db(const fixtest_acc_t *acc)
{
    if (acc->err_energy <= 0.0) {
        return 200.0;
    }
    return 10.0 * log10(acc->sig_energy / acc->err_energy);
}

void fixtest_assert_lsb(double val, double ref, double lsb, double max_lsb, const char *what)
{
    double err_lsb = fabs(val - ref) / lsb;
    if (!(err_lsb <= max_lsb)) {
        fail_msg("%s: value %.9g vs reference %.9g, error %.3f LSB > %.3f LSB", what, val, ref,
                 err_lsb, max_lsb);
    }
}

void fixtest_assert_snr(const fixtest_acc_t *acc, double min_db, const char *what)
{
    double snr = fixtest_acc_snr_db(acc);
    if (!(snr >= min_db)) {
        fail_msg("%s: SNR %.2f dB < %.2f dB over %zu samples (max error %.3g)", what, snr, min_db,
                 acc->n, acc->max_abs_err);
    }
}

/* ---- Added for the fixmath suite --------------------------------------------------------- */

void fixtest_rng_seed(fixtest_rng_t *rng, uint64_t seed) { rng->state = seed; }

uint64_t fixtest_rng_u64(fixtest_rng_t *rng)
{
    uint64_t z = (rng->state += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

int32_t fixtest_rng_i32(fixtest_rng_t *rng)
{
    return (int32_t)(int64_t)((int64_t)(fixtest_rng_u64(rng) >> 32) - 2147483648LL);
}

int16_t fixtest_rng_i16(fixtest_rng_t *rng)
{
    return (int16_t)((int32_t)(fixtest_rng_u64(rng) >> 48) - 32768);
}

int32_t fixtest_rng_i32_log(fixtest_rng_t *rng)
{
    uint64_t u = fixtest_rng_u64(rng);
    unsigned bits = (unsigned)(u % 32U);          /* magnitude below 2^bits */
    int64_t mag = (int64_t)((u >> 32) & ((1ULL << bits) - 1U));
    if (bits == 31U && (u & 32U)) {
        return INT32_MIN; /* the one value a sign flip cannot reach */
    }
    return (int32_t)((u & 64U) ? -mag : mag);
}

double fixtest_rng_unit(fixtest_rng_t *rng)
{
    return (double)(fixtest_rng_u64(rng) >> 11) * (1.0 / 9007199254740992.0);
}

void fixtest_lsb_init(fixtest_lsb_t *t)
{
    const fixtest_lsb_t empty = {0.0, 0.0, 0.0, 0.0, 0, 0, 0U};
    *t = empty;
}

void fixtest_lsb_add_err(fixtest_lsb_t *t, double err_lsb, double val, double ref, int64_t in1,
                         int64_t in2)
{
    double e = fabs(err_lsb);
    if (!(e <= t->max_lsb)) { /* also catches NaN */
        t->max_lsb = e;
        t->worst_val = val;
        t->worst_ref = ref;
        t->worst_in1 = in1;
        t->worst_in2 = in2;
    }
    t->sum_sq_lsb += e * e;
    t->n++;
}

void fixtest_lsb_add(fixtest_lsb_t *t, double val, double ref, double lsb, int64_t in1,
                     int64_t in2)
{
    fixtest_lsb_add_err(t, (val - ref) / lsb, val, ref, in1, in2);
}

void fixtest_lsb_check(const fixtest_lsb_t *t, double max_lsb, const char *what)
{
    double rms = t->n > 0U ? sqrt(t->sum_sq_lsb / (double)t->n) : 0.0;
    print_message("[ MEASURE  ] %s: max %.6f LSB (bound %.6f), rms %.4f LSB, %zu points\n", what,
                  t->max_lsb, max_lsb, rms, t->n);
    if (t->n == 0U) {
        fail_msg("%s: no points were checked", what);
    }
    if (!(t->max_lsb <= max_lsb)) {
        fail_msg("%s: error %.6f LSB > bound %.6f LSB at inputs (%lld, %lld): value %.12g vs "
                 "reference %.12g",
                 what, t->max_lsb, max_lsb, (long long)t->worst_in1, (long long)t->worst_in2,
                 t->worst_val, t->worst_ref);
    }
}

void fixtest_snr_check(const fixtest_acc_t *acc, double min_db, const char *what)
{
    print_message("[ MEASURE  ] %s: SNR %.2f dB (bound >= %.2f dB), max error %.4g, %zu samples\n",
                  what, fixtest_acc_snr_db(acc), min_db, acc->max_abs_err, acc->n);
    if (acc->n == 0U) {
        fail_msg("%s: no samples were checked", what);
    }
    fixtest_assert_snr(acc, min_db, what);
}

double fixtest_err_lsb_exact(int64_t res, int64_t num, uint16_t shift, int64_t lo, int64_t hi)
{
    __extension__ typedef __int128 i128;
    i128 scale = (i128)1 << shift;
    i128 ref = (i128)num;
    i128 d;
    if (ref > (i128)hi * scale) {
        ref = (i128)hi * scale;
    }
    if (ref < (i128)lo * scale) {
        ref = (i128)lo * scale;
    }
    d = (i128)res * scale - ref;
    return fabs((double)d) / ldexp(1.0, (int)shift);
}
