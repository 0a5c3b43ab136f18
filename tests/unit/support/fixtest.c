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
    acc->sig_energy = 0.0;
    acc->err_energy = 0.0;
    acc->max_abs_err = 0.0;
    acc->n = 0U;
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
