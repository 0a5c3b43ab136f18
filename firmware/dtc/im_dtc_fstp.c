/*
 * im_dtc_fstp.c - the IM switching-table DTC (DTC_LAW_IM_DTC) on the four-switch inverter (FSTP,
 * board.topology = DTC_TOPO_FSTP): Hoang Table II's four-sector table on Casadei's estimator,
 * speed loop, start-up and references (Hoang sec. I and its refs. [12], [13]: the four-switch DTC
 * of an induction machine). law.c calls im_dtc_step_fstp instead of im_dtc_step for such a
 * configuration, a choice made at init (law_init) or at a live reconfiguration
 * (law_reconfigure), so the six-switch step carries no test of the topology.
 *
 * What differs from im_dtc_step (im_dtc.c), and why:
 *   currents: Clarke of the two switched phases i_b, i_c (clarke_fstp, Hoang eqs. 4-5 with the
 *     zero sum): phase A's current returns through the capacitors' mid-point;
 *   voltage: the phase voltages of the FSTP, leg A on the mid-point (vrec_fstp, Hoang eqs. 1-5 with
 *     v_a0 = V_mid): the measured lower capacitor voltage when board.fstp_vmid_measured (phase A's
 *     current moves the mid-point; Hoang eqs. 17-19 assume V_dc/2), with the FSTP's device drops
 *     (Hoang Table V = eqs. 35-36 or Table VI with eqs. 37-38, vcomp.h) and the dead time of legs
 *     B and C only (vrec.h deadtime_error, fstp);
 *   vectors: the four active vectors of Hoang Table I (V_1..V_4 = S_B S_C 00, 10, 11, 01), no
 *     null vector; the sector is the flux's quadrant (sector.h sector_fstp, derived there from
 *     Hoang Tables I-II); the torque comparator two-level (Table II has no zero-torque row);
 *   start-up: phase A's current is the split capacitors' only path, d(v_hi - v_lo)/dt = i_a / C
 *     (docs/plant.md "DC link"), so a flux built at DC with an alpha part charges the mid-point
 *     without limit (SIL, 4 kW IM, 2 x 4.7 mF: the lower capacitor from 155 V to 0 V within 0.1 s
 *     of the magnetisation). With the encoder reading a rotor at rest the flux is built along
 *     +beta, where i_alpha = i_a = 0: V_2 (S_B S_C = 10, pure +beta with leg A at the mid-point,
 *     Hoang Table I) while the flux comparator asks for more flux or the flux has crossed to
 *     -beta, V_4 (01, -beta) while it asks for less (a fixed half-axis: a choice by the flux's
 *     sign alone limit-cycles about zero with the period's actuation delay, where the flux
 *     starts; V_4 for less flux at any sign takes a flux that crossed zero away without
 *     limit, SIL), so i_b = -i_c carries the DC magnetising current and
 *     the mid-point stays where it is. Otherwise (a turning rotor, or no encoder) the same table
 *     at T* = 0: the comparator alternates the two vectors of the quadrant that raise (or lower)
 *     the flux and turn it either way, zero mean torque, so the flux builds at the rotor's own
 *     speed, as ST-D's vectors do on the SSTP (im_dtc_internal.h im_magn_vector); at rest without
 *     an encoder that flux is DC with an alpha part and moves the mid-point (not solved:
 *     docs/firmware-core.md);
 *   current limit: ilim_select over the four vectors (ilim.h, fstp);
 *   after a live reconfiguration (im_dtc_reconfigure), until the relay has tied the failed phase
 *     A' to the mid-point: phase A' is open, i_alpha = i_a' = 0, and its terminal floats at the
 *     machine's voltage, which no sensor reads. The machine then runs on the line B'-C' alone (a single-phase machine): its alpha stator flux
 *     is the rotor's, phi_s,alpha = sigma l_s i_alpha + x_alpha = x_alpha (Casadei eq. 21 over
 *     k_r, x = (m/l_r) phi_r), so the estimator takes the alpha voltage of the rotor equation
 *     (Casadei eqs. A7-A9 in the stator frame, dx/dt = (r_r/l_r)((m^2/l_r) i - x) + j w x, with
 *     i_alpha = 0): v_alpha = -(r_r/l_r) x_alpha - w x_beta, w the speed in use; the beta voltage
 *     is the legs' (v_beta = (v_b'0 - v_c'0)/sqrt3, Hoang eq. 5, whatever A' does). The torque is
 *     then phi_s,alpha i_beta (Hoang eq. 10 with i_alpha = 0), which only the beta voltage moves:
 *     the torque comparator's demand takes V_2 (+beta) where phi_s,alpha >= 0 and V_4 (-beta)
 *     where it is negative, and V_1 (S_B' = S_C' = 0: no line voltage, the beta current
 *     free-wheels) when the torque is to fall, the beta current turned back before phi_s,alpha
 *     crosses zero (im_open_vector); the flux is the rotor's and is not regulated.
 *     Hoang Table II in that interval chooses the vectors for a phase A' on the mid-point and
 *     gives half of them no beta voltage (SIL: the mean torque near zero for the 15 ms, a speed
 *     dip twice as deep). The interval ends when phase A' carries current, |i_alpha| beyond the
 *     open-phase check's zero band prot.leg_i_min_iq / 4 (app_fault.h APP_LEG_ZERO_LOG2): the
 *     relay has closed; or after prot.relay_periods, the relay's closing time with the host's
 *     margin (1.5 times, tools/config), which the app waits too. The margin's periods on the
 *     interval's vectors with phase A' on the mid-point drove 40 A of DC into it and the current
 *     limit braked the machine (SIL, 4 kW IM at 1000 rpm: 7.6 ms past the closure, a 41 % dip).
 * The FSTP's voltage is half the SSTP's on the same link (the largest circle inside Hoang Table
 * I's rhombus has the radius V_dc / (2 sqrt3), against V_dc / sqrt3): the flux the speed allows is
 * the host's to derive (docs/firmware-core.md).
 */
#include "im_dtc_internal.h"

#include "clarke.h"
#include "sector.h"
#include "vrec.h"

/* The estimator's input on the FSTP: the voltage of the period that ends now (legs_2: S_B, S_C;
 * S_A is reported 0 and not read) on the measured link and mid-point, the FSTP's drop and
 * dead-time compensations, the currents (im_dtc_ein_common). Formats IQ pu, saturating sums. */
void im_dtc_estimate_fstp(im_dtc_t *c, const dtc_meas_t *m)
{
    const dtc_config_t *cfg = c->cfg;
    im_est_in_t *in = &c->ein;

    vrec_fstp(c->legs_2.sb, c->legs_2.sc, m->vdc_iq, m->vmid_iq, cfg->board.fstp_vmid_measured, &in->v_alpha_iq,
              &in->v_beta_iq);
    if (c->open_wait != 0U) {
        /* phase A' open (file comment): v_alpha = -(r_r/l_r) x_alpha - w x_beta; rounded IQ
         * products, saturating sums */
        in->v_alpha_iq =
            fix_neg32(fix_add32(iq_mpy(c->rr_lr_iq, c->est.x_alpha_iq), iq_mpy(c->speed_iq, c->est.x_beta_iq)));
        {
            /* Hoang Table I with v_a0 = V_mid: V_2, V_4 = +-V_dc/sqrt3 along beta, V_1 = (2/3) V_mid
             * and V_3 = -(2/3)(V_dc - V_mid) along alpha, V_mid the measured lower capacitor
             * (V_dc/2 when it is not measured); 1/sqrt3 and 2/3 in Q31 */
            const iq_t lo = cfg->board.fstp_vmid_measured != 0U ? m->vmid_iq : fix_rshift_rnd32(m->vdc_iq, 1U);
            const iq_t hi = iq_sub(m->vdc_iq, lo);
            c->vb_max_iq = q31_mul(FIX_Q31_INV_SQRT3, m->vdc_iq);
            c->va_min_iq = q31_mul((q31_t)1431655765L, lo < hi ? lo : hi);
        }
    }
    im_vcomp(c, 0U, c->legs_2.sb, c->legs_2.sc, 1U);
    in->v_alpha_iq = fix_add32(in->v_alpha_iq, c->dva_iq);
    in->v_beta_iq = fix_add32(in->v_beta_iq, c->dvb_iq);
    if (cfg->est.deadtime_comp != 0U && (c->legs_3.sb != c->legs_2.sb || c->legs_3.sc != c->legs_2.sc)) {
        /* the currents' signs at the switching instant: the previous step's sample (im_dtc_estimate) */
        deadtime_error(&c->dt_p, m->vdc_iq, &c->i_prev, &c->legs_3, &c->legs_2, &c->dva_iq, &c->dvb_iq);
        in->v_alpha_iq = fix_add32(in->v_alpha_iq, c->dva_iq);
        in->v_beta_iq = fix_add32(in->v_beta_iq, c->dvb_iq);
    }
    c->i_prev = c->i;
    im_dtc_ein_common(c, m);
}

/* From the live reconfiguration (im_dtc_reconfigure) until the machine's rotor flux has fallen
 * to the FSTP's reference: the estimator's rotor-flux reference (Casadei eq. 20) follows the
 * machine's rotor flux instead of holding the six-switch drive's or stepping to the FSTP's. The
 * machine's rotor flux follows the T model's rotor equation in rotor-flux coordinates,
 * tau_r d|phi_r|/dt = m i_d - |phi_r| (Casadei eqs. A7, A9 in the frame of phi_r, as the start-up's
 * current model, im_dtc_refs), i_d the current along the estimated rotor-flux direction (Casadei
 * eq. 22), from the reference in force at the reconfiguration (magn_psir_iq). While phase A' is
 * open the single-phase machine's beta current takes the rotor flux down within the relay's time
 * (SIL, 4 kW IM at 1000 rpm: 0.53 to 0.45 Wb in 15 ms), and a reference held at 0.53 Wb pulls the
 * estimate above the machine's flux (the estimated torque 33 N*m against the machine's 26); after
 * the closing a reference stepped below the machine's flux pulls the estimate below it (the
 * estimated |phi_s| 0.06 Wb low for 8 ms), and the table then turns a flux larger than the one it
 * sees, beyond what the FSTP's voltage turns at that speed. Once the current model's flux reaches
 * the FSTP's reference (im_dtc_psir_ref of the set in force) that reference holds.
 * Formats: IQ pu, Ts/tau_r Q31 (u.im.ref.magn_k_q31); rounded products, saturating sums.
 * External linkage on purpose (im_dtc_internal.h): inlined, its temporaries would sit in
 * im_dtc_select_fstp's frame on the four-switch step's deepest stack path. */
void im_fstp_psir_fall(im_dtc_t *c)
{
    const dtc_im_machine_cfg_t *im = &c->cfg->u.im.machine;
    const iq_t i_d = iq_add(iq_mpy(c->i.i_alpha_iq, c->est.u_alpha_iq), iq_mpy(c->i.i_beta_iq, c->est.u_beta_iq));
    c->magn_psir_iq = iq_add(c->magn_psir_iq,
                             q31_mul(c->cfg->u.im.ref.magn_k_q31, iq_sub(iq_mpy(im->m_iq, i_d), c->magn_psir_iq)));
    im_dtc_psir_ref(c, c->act.flux_ref_iq);
    if (c->magn_psir_iq > c->psir_ref_iq) {
        c->psir_ref_iq = c->magn_psir_iq;
    } else {
        c->psir_fall = 0U;
    }
}

/* Phase A' open, before the relay's closing: the stator flux that the FSTP turns at the speed.
 * Once A' is tied to the mid-point the flux turns near the beta axis by the alpha vectors alone
 * (Hoang Table I: V_1, V_3 along alpha, V_a the shorter, va_min_iq), at most at |V_a| / |phi_s|: a flux with
 * |phi_s| w > |V_a| falls behind the rotor's there, and Hoang Table II's flux-lowering vector at a
 * quadrant's start is radial, which stops it while the rotor's turns (SIL, 4 kW IM at 1000 rpm,
 * leg B: |phi_s| 0.61 Wb at the closing, 0.47 Wb turned, the torque -18 to -26 N*m for 2 ms). The
 * excess is sigma l_s i_beta of the interval's current (Casadei eq. 21, phi_s = sigma l_s i + x,
 * phi_s,alpha = x_alpha while i_alpha = 0), which the beta vector against the current takes down
 * at V_dc/sqrt3 / (sigma l_s) (vb_max_iq): the largest current the limit allows within
 * t_w = sigma l_s I_lim / (V_dc/sqrt3). So from t_w before the relay's nominal closing (its time
 * is relay_periods / 1.5, the host's margin: im_dtc_reconfigure; 3 open_wait - relay_periods is
 * three times the periods left to it) a flux with |phi_s w|^2 > V_a^2 takes that vector. w is
 * the rotor's electrical speed in use (the slip left out: the bound is a little above the
 * stator flux's). Formats: IQ pu; the window as the exact 64-bit product of the periods (< 2^18)
 * and Ts V_dc/sqrt3 / (sigma l_s) (ip_a_iq vb_max_iq, < 2^31) against 3 I_lim; the flux as Q48
 * sums of squares of rounded IQ products. Returns 2 or 4, or 0 when the flux is within it. */
static uint16_t im_open_turnable(const im_dtc_t *c, iq_t psi_a)
{
    if (((int64_t)c->open_wait * 3 - (int64_t)c->cfg->prot.relay_periods) * (int64_t)iq_mpy(c->ip_a_iq, c->vb_max_iq) <=
            3 * (int64_t)c->il_p.i_lim_iq &&
        iq_sumsq_q48(iq_mpy(psi_a, c->speed_iq), iq_mpy(c->est.psi_beta_iq, c->speed_iq)) >
            iq_sumsq_q48(c->va_min_iq, 0)) {
        return c->i.i_beta_iq >= 0 ? 4U : 2U;
    }
    return 0U;
}

/* Phase A' open (file comment): the vector of the torque by the beta voltage alone, V_2 (+beta)
 * where phi_s,alpha >= 0 and V_4 (-beta) where it is negative while the torque is to rise (up),
 * V_1 when it is to fall; but the beta current brought back towards zero, by the beta vector
 * against it, near the relay's closing while the flux is beyond what the FSTP turns
 * (im_open_turnable), and once it cannot be reversed before phi_s,alpha crosses zero. The torque is
 * phi_s,alpha i_beta (Hoang eq. 10 with i_alpha = 0): the current that the comparator builds
 * while phi_s,alpha is small gives little torque, and the same current after phi_s,alpha has
 * changed sign gives the opposite torque (SIL, 4 kW IM at 1000 rpm, leg C: the beta current at
 * the current limit, -6.6 N*m over 2 ms, 45 rpm lost within the relay's time). phi_s,alpha
 * approaches zero when it and its rate have opposite signs, its rate the estimator's alpha voltage
 * of this interval (v_alpha = d phi_s,alpha / dt, i_alpha = 0: im_dtc_estimate_fstp); it reaches
 * zero within |phi_s,alpha| / |v_alpha|. The beta vector against the current takes it to zero
 * within sigma l_s |i_beta| / (V_dc / sqrt3) (Casadei eq. 21: phi_s = sigma l_s i + x, the rotor's
 * x_beta near its peak, and so nearly at rest, where x_alpha crosses zero; Hoang Table I: V_2, V_4
 * = +-V_dc/sqrt3 along beta, V_dc the measured link, vb_max_iq). The current is reversed when the
 * second time is not shorter than the first:
 *   sigma l_s |i_beta| |v_alpha| >= |phi_s,alpha| V_dc / sqrt3,
 * compared as exact 64-bit products of IQ values (each < 2^31: no overflow). External linkage on
 * purpose, as im_fstp_psir_fall. */
uint16_t im_open_vector(const im_dtc_t *c, iq_t psi_a, uint16_t up)
{
    const iq_t ib = c->i.i_beta_iq, va = c->ein.v_alpha_iq;
    const uint16_t down = im_open_turnable(c, psi_a);
    if (down != 0U) {
        return down;
    }
    if ((psi_a >= 0) != (va >= 0) &&
        (int64_t)iq_mpy(c->cfg->u.im.machine.sigma_ls_iq, fix_abs32(ib)) * (int64_t)fix_abs32(va) >=
            (int64_t)fix_abs32(psi_a) * (int64_t)c->vb_max_iq) {
        return ib >= 0 ? 4U : 2U;
    }
    return up == 0U ? 1U : (psi_a >= 0 ? 2U : 4U);
}

/* From the reconfiguration until the machine's rotor flux has fallen to the FSTP's reference
 * (psir_fall), with the torque to rise and T* > 0: of Hoang Table II's two torque-raising vectors
 * of the quadrant (the rows (1,1) and (0,1)), the one that turns the stator flux forward faster,
 * while the torque's relative error exceeds the flux's. The flux turns at (phi_s x V) / |phi_s|^2
 * (Hoang eq. 10's cross product, d phi_s / dt = V), so the larger phi_s x V advances it more:
 * V_1: -phi_b V_dc/3; V_2: phi_a V_dc/sqrt3; V_3: phi_b V_dc/3; V_4: -phi_a V_dc/sqrt3 (Hoang
 * Table I on the measured V_dc; with the measured mid-point's alpha lengths, (2/3) V_mid and
 * (2/3)(V_dc - V_mid), the 4 kW IM's leg B dipped 10.9 % instead of 9.4 % in SIL: the choice near
 * the beta axis is sensitive to them, and the mid-point swings within the half-period the choice
 * acts over, docs/reliability.md). The table's choice by the flux comparator alone takes the weaker of
 * the two where the flux is at the FSTP's voltage limit: an alpha vector (V_dc/3, less 2/3 of the
 * mid-point's swing) turns a flux of |phi_s| at most at |V_a| / |phi_s|, and where it is the
 * flux-raising row's vector the flux holds its magnitude and lags the rotor's (SIL, 4 kW IM at
 * 1000 rpm, leg A: 13-17 N*m against the load's 26.5 for 13 ms after the relay's closing, the
 * flux on its reference; leg B: the flux-lowering row's V_4 radial at a quadrant's start, the
 * flux stopped while the rotor's turns, -18 to -26 N*m). The relative errors:
 *   | |phi_s|^2 - phi*^2 | / (2 phi*^2) < (T* - T) / T*
 * (|phi_s|^2 - phi*^2 = (|phi_s| - phi*)(|phi_s| + phi*), about 2 phi* (|phi_s| - phi*)), compared
 * as products of Q24 squares (the Q48 sums of squares >> 24, < 2^27) and IQ torques (< 2^31):
 * below 2^59, exact. Once the flux's error is the larger the table's row by the flux comparator
 * holds the flux. Returns that vector, or Hoang Table II's (swtab_fstp) otherwise; the common
 * factor V_dc/sqrt3 left out (the comparison does not depend on it), fix_neg32 saturating. */
uint16_t im_dtc_fstp_advance(const im_dtc_t *c, uint16_t sector, uint16_t flux_up, uint16_t up, iq_t te)
{
    const iq_t pa = c->est.psi_alpha_iq, pb = c->est.psi_beta_iq, dt = iq_sub(c->te_ref_iq, te);
    const int64_t e2 = (int64_t)(iq_sumsq_q48(pa, pb) >> 24);
    const int64_t r2 = (int64_t)(iq_sumsq_q48(c->psi_ref_iq, 0) >> 24);
    /* phi_s x V over V_dc/sqrt3: the alpha vectors' 1/sqrt3 (Q31), the beta vectors' 1 */
    const iq_t xa = q31_mul(FIX_Q31_INV_SQRT3, pb);
    iq_t x[5];
    uint16_t v11, v01;
    if (up == 0U || c->te_ref_iq <= 0 || dt <= 0 ||
        (e2 > r2 ? e2 - r2 : r2 - e2) * (int64_t)c->te_ref_iq >= 2 * r2 * (int64_t)dt) {
        return swtab_fstp(sector, flux_up, up);
    }
    x[0] = 0;
    x[1] = fix_neg32(xa);
    x[2] = pa;
    x[3] = xa;
    x[4] = fix_neg32(pa);
    v11 = swtab_fstp(sector, 1U, 1U);
    v01 = swtab_fstp(sector, 0U, 1U);
    return x[v11] >= x[v01] ? v11 : v01;
}

/* The flux comparator on |phi_s|^2, the two-level torque comparator, Hoang Table II on the
 * flux's quadrant, then the current limit over the four vectors (im_ilim). Returns V_1..V_4. */
uint16_t im_dtc_select_fstp(im_dtc_t *c, iq_t te, dtc_out_t *o)
{
    const iq_t psi_a = c->est.psi_alpha_iq, psi_b = c->est.psi_beta_iq;
    const uint16_t flux_up = hyst2_sq_step(&c->h_flux, c->psi_ref_iq, iq_sumsq_q48(psi_a, psi_b));
    const uint16_t sector = sector_fstp(psi_a, psi_b);
    const uint16_t up = hyst2_step(&c->h_torque2, iq_sub(c->te_ref_iq, te));

    o->sector = sector;
    o->flux_up = flux_up;
    o->torque_dem = up != 0U ? 1 : -1;
    if (c->psir_fall != 0U) {
        im_fstp_psir_fall(c);
    }
    if (c->open_wait != 0U) {
        /* phase A' open (file comment) until it carries current, |i_alpha| > h (the unsigned
         * box test of im_ilim), or the relay's periods have run out; then Hoang Table II drives */
        const uint32_t h = (uint32_t)fix_rshift_rnd32(c->cfg->prot.leg_i_min_iq, 2U);
        c->open_wait = (uint16_t)((uint32_t)c->i.i_alpha_iq + h > h + h ? 0U : c->open_wait - 1U);
        if (c->open_wait != 0U) {
            /* the torque by the beta voltage alone */
            return im_ilim(c, im_open_vector(c, psi_a, up));
        }
    }
    if (c->magnetised == 0U && c->cfg->speed.sensor == DTC_SPEED_ENCODER && c->speed_iq == 0) {
        /* at rest: the flux along +beta (file comment), V_2 = +beta, V_4 = -beta */
        o->torque_dem = 0;
        return im_ilim(c, flux_up != 0U || psi_b < 0 ? 2U : 4U);
    }
    return im_ilim(c, c->psir_fall != 0U ? im_dtc_fstp_advance(c, sector, flux_up, up, te) : swtab_fstp(sector, flux_up, up));
}

void im_dtc_step_fstp(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o)
{
    im_dtc_table_step(c, m, o, 1U);
}
