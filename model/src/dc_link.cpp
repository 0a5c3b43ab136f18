// dc_link.cpp - DC-link constants and parameter checks (dc_link.h).
#include "dc_link.h"

#include <cmath>

namespace dclink {

void setup(const plant_params_t &p, DcLink &k) {
    if (p.inverter == PLANT_INVERTER_SSTP && !split_link(p)) {
        k.c_lo = k.c_hi = 2.0 * p.c_dc_f;
    } else {
        k.c_lo = k.c_hi = p.c_dc_f;
    }
    k.inv_c_lo = (k.c_lo > 0.0) ? 1.0 / k.c_lo : 0.0;
    k.inv_c_hi = (k.c_hi > 0.0) ? 1.0 / k.c_hi : 0.0;
    const double inv_rdc = (p.r_dc_ohm > 0.0) ? 1.0 / p.r_dc_ohm : 0.0;
    LinkRC &lk = k.rc;
    lk = LinkRC{};
    lk.on = p.finite_dc_link && p.inverter != PLANT_INVERTER_IDEAL && (p.r_bal_ohm > 0.0 || p.esr_ohm > 0.0);
    lk.fstp = split_link(p);
    lk.esr = p.esr_ohm > 0.0;
    lk.esr_ohm = p.esr_ohm;
    lk.vdc = p.vdc_v;
    lk.inv_c_lo = k.inv_c_lo;
    lk.inv_c_hi = k.inv_c_hi;
    lk.g_s = inv_rdc;
    lk.g_e = lk.esr ? 1.0 / p.esr_ohm : 0.0;
    lk.g_b = (p.r_bal_ohm > 0.0) ? 1.0 / p.r_bal_ohm : 0.0;
    if (lk.on && lk.esr) {
        const double a = lk.g_s + lk.g_e + lk.g_b, c = lk.g_e + lk.g_b;
        const double det = c * (c - 2.0 * a);  // det [[a, -c], [c, -2c]] = -2ac + c^2
        lk.m11 = -2.0 * c / det;
        lk.m12 = c / det;
        lk.m21 = -c / det;
        lk.m22 = a / det;
        lk.inv_gsum = 1.0 / a;
    }
    LinearLink &q = k.lin;
    q.is_g = q.hi_s = q.hi_p = q.lo_s = q.lo_p = q.lo_m = 0.0;
    q.pdc_s = q.pdc_st = q.pdc_src = q.r_dc = 0.0;
    if (p.inverter == PLANT_INVERTER_IDEAL) {
        q.pdc_src = 1.0;
    } else if (!p.finite_dc_link) {
        q.pdc_st = 1.0;
    } else {
        q.is_g = inv_rdc;
        q.pdc_s = p.vdc_v;
        q.r_dc = p.r_dc_ohm;
        if (split_link(p)) {
            q.hi_s = q.hi_p = k.inv_c_hi;
            q.lo_s = q.lo_p = q.lo_m = k.inv_c_lo;
        } else {
            // SSTP: one capacitor of 2*c_dc_f (c_lo holds that value), reported as two equal halves.
            q.hi_s = q.hi_p = q.lo_s = q.lo_p = 0.5 * k.inv_c_lo;
        }
    }
}

const char *check_elements(const plant_params_t &p) {
    auto bad = [](double v) { return !std::isfinite(v); };
    if (bad(p.r_bal_ohm) || p.r_bal_ohm < 0.0) return "r_bal_ohm must be finite and >= 0 (0 = not fitted)";
    if (bad(p.esr_ohm) || p.esr_ohm < 0.0) return "esr_ohm must be finite and >= 0";
    return nullptr;
}

const char *check_finite(const plant_params_t &p) {
    auto bad = [](double v) { return !std::isfinite(v); };
    if (p.finite_dc_link && p.inverter != PLANT_INVERTER_IDEAL) {
        if (bad(p.c_dc_f) || p.c_dc_f <= 0.0) return "c_dc_f must be > 0 with finite_dc_link";
        if (bad(p.r_dc_ohm) || p.r_dc_ohm <= 0.0) return "r_dc_ohm must be > 0 with finite_dc_link";
        // RK4 accuracy/stability on the source-capacitor mode: lambda * h <= 1.
        const double c_eff = split_link(p) ? 0.5 * p.c_dc_f : 2.0 * p.c_dc_f;
        if (p.max_step_s > p.r_dc_ohm * c_eff)
            return "max_step_s exceeds r_dc_ohm * C_link (DC source/capacitor time constant): "
                   "reduce max_step_s or raise r_dc_ohm / c_dc_f";
    }
    return nullptr;
}

}  // namespace dclink
