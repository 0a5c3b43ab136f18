// dc_link.h - the DC link (docs/plant.md, "DC link"): a DC source with internal resistance feeding
// the capacitor(s) (SSTP: one capacitor of 2 c_dc_f, reported as two equal halves; FSTP: two in
// series, phase A on their mid-point), optionally with capacitor ESR and balancing resistors; or a
// stiff link (capacitor voltages fixed at vdc/2); or, for the ideal inverter, none.
#ifndef DTC_MODEL_DC_LINK_H
#define DTC_MODEL_DC_LINK_H

#include "plant.h"

namespace dclink {

// Two capacitors in series with the mid-point brought out: the FSTP's link, and the SSTP's when
// the reconfiguration relay is fitted (it ties a phase to that mid-point); otherwise the SSTP has
// one capacitor of 2 c_dc_f.
inline bool split_link(const plant_params_t &p) {
    return p.inverter == PLANT_INVERTER_FSTP || (p.inverter == PLANT_INVERTER_SSTP && p.reconfig_relay);
}

// Finite DC link with capacitor ESR and/or balancing resistors (docs/plant.md, "DC link"): node
// analysis of the source, the capacitors (ideal C in series with ESR) and the resistors across
// them. Constants for dc_link_nodes(); used only when on (otherwise the linear forms of
// LinearLink).
struct LinkRC {
    bool on;        // finite link, switching inverter, r_bal_ohm > 0 or esr_ohm > 0
    bool fstp;      // two capacitors with the mid-point tied to phase A; else one capacitor
    bool esr;       // esr_ohm > 0
    double g_s;     // 1 / r_dc_ohm
    double g_e;     // 1 / esr_ohm (esr only)
    double g_b;     // 1 / r_bal_ohm, 0 when not fitted
    double esr_ohm;
    double vdc;            // DC source voltage
    double inv_c_lo, inv_c_hi;  // 1 / capacitance (SSTP: both 1 / (2 c_dc_f))
    // FSTP with ESR: [vP, vM] = inverse of [[a, -c], [c, -2c]] times the right-hand side,
    // a = g_s + g_e + g_b, c = g_e + g_b (KCL at the plus rail and at the mid-point).
    double m11, m12, m21, m22;
    // SSTP with ESR: vP = (g_s vdc - i_plus + g_e v_cap) * inv_gsum.
    double inv_gsum;
};

// Link node voltages and capacitor currents for one state.
struct LinkNodes {
    double tv_lo, tv_hi;  // terminal voltages across the lower / upper capacitor (SSTP: halves)
    double i_s;           // DC source current
    double dv_lo, dv_hi;  // capacitor voltage derivatives (internal, ideal-C voltages)
    double p_loss;        // ESR + balancing-resistor loss, W
};

// DC-link node analysis with ESR and balancing resistors (LinkRC): vc_lo / vc_hi are the ideal
// capacitor voltages (states), i_plus / i_mid the currents the inverter draws from the plus rail
// and from the mid-point. KCL at the plus rail P and the mid-point M (negative rail = 0):
//   g_s (vdc - vP) = i_plus + i_chi + g_b (vP - vM),   i_chi = g_e (vP - vM - vc_hi)
//   i_chi + g_b (vP - vM) = i_mid + i_clo + g_b vM,      i_clo = g_e (vM - vc_lo)
// with ESR = 0 the terminals are the capacitor voltages and the capacitor currents follow from
// the same two equations. SSTP: one capacitor (2 c_dc_f) from P to 0 with ESR and r_bal across it.
inline void dc_link_nodes(const LinkRC &k, double vlo, double vhi, double i_plus, double i_mid, LinkNodes &n) {
    const double vdc = k.vdc;
    if (k.fstp) {
        double i_chi, i_clo;
        if (k.esr) {
            const double r1 = k.g_s * vdc - i_plus + k.g_e * vhi;
            const double r2 = i_mid + k.g_e * (vhi - vlo);
            const double vp = k.m11 * r1 + k.m12 * r2;
            const double vm = k.m21 * r1 + k.m22 * r2;
            n.tv_lo = vm;
            n.tv_hi = vp - vm;
            n.i_s = k.g_s * (vdc - vp);
            i_chi = k.g_e * (n.tv_hi - vhi);
            i_clo = k.g_e * (n.tv_lo - vlo);
            n.p_loss = k.esr_ohm * (i_chi * i_chi + i_clo * i_clo);
        } else {
            n.tv_lo = vlo;
            n.tv_hi = vhi;
            n.i_s = k.g_s * (vdc - vlo - vhi);
            i_chi = n.i_s - i_plus - k.g_b * vhi;
            i_clo = n.i_s - i_plus - i_mid - k.g_b * vlo;
            n.p_loss = 0.0;
        }
        n.p_loss += k.g_b * (n.tv_lo * n.tv_lo + n.tv_hi * n.tv_hi);
        n.dv_hi = i_chi * k.inv_c_hi;
        n.dv_lo = i_clo * k.inv_c_lo;
    } else {
        const double vcap = vlo + vhi;
        double vp, i_cap;
        if (k.esr) {
            vp = (k.g_s * vdc - i_plus + k.g_e * vcap) * k.inv_gsum;
            i_cap = k.g_e * (vp - vcap);
            n.p_loss = k.esr_ohm * i_cap * i_cap;
        } else {
            vp = vcap;
            i_cap = k.g_s * (vdc - vp) - i_plus - k.g_b * vcap;
            n.p_loss = 0.0;
        }
        n.p_loss += k.g_b * vp * vp;
        n.i_s = k.g_s * (vdc - vp);
        n.tv_lo = n.tv_hi = 0.5 * vp;
        n.dv_lo = n.dv_hi = 0.5 * i_cap * k.inv_c_lo;  // SSTP: inv_c_lo = 1 / (2 c_dc_f)
    }
}

// The link without ESR or balancing resistors (and the energy drawn by the inverter for every
// kind) as linear forms of the rail currents, so the right-hand side has no branch on the
// inverter or link kind:
//   i_s = is_g (vdc - vc_lo - vc_hi)                                (DC source current)
//   dvc_hi/dt = hi_s i_s - hi_p i_plus;  dvc_lo/dt = lo_s i_s - lo_p i_plus - lo_m i_mid
//   p_dc = pdc_s i_s + pdc_st ((vc_lo + vc_hi) i_plus + vc_lo i_mid) + pdc_src p_src
//   p_rdc = r_dc i_s^2                                               (source resistance loss)
// i_plus / i_mid: currents the inverter draws from the plus rail / the mid-point; p_src: power of
// the ideal inverter's sources.
struct LinearLink {
    double is_g, hi_s, hi_p, lo_s, lo_p, lo_m;
    double pdc_s, pdc_st, pdc_src, r_dc;
};

// The whole link: capacitances and the two forms above.
struct DcLink {
    double c_lo, c_hi;          // capacitances (SSTP: one capacitor of 2 c_dc_f, split in the report)
    double inv_c_lo, inv_c_hi;  // their reciprocals (0 for no capacitor)
    LinkRC rc;                  // ESR / balancing resistors (rc.on)
    LinearLink lin;
};

// Link constants from the parameters.
void setup(const plant_params_t &p, DcLink &k);

// Capacitor energy 0.5 C v^2 at capacitor voltages (vlo, vhi).
inline double capacitor_energy(const plant_params_t &p, const DcLink &k, double vlo, double vhi) {
    if (p.inverter == PLANT_INVERTER_SSTP && !split_link(p)) {
        const double v = vlo + vhi;
        return 0.5 * k.c_lo * v * v;
    }
    if (split_link(p)) return 0.5 * k.c_lo * vlo * vlo + 0.5 * k.c_hi * vhi * vhi;
    return 0.0;
}

// Parameters of the link (nullptr: valid); the first part is checked before the inverter's,
// the second (finite link) after the step size, as plant_create reports them.
const char *check_elements(const plant_params_t &p);
const char *check_finite(const plant_params_t &p);

}  // namespace dclink

#endif  // DTC_MODEL_DC_LINK_H
