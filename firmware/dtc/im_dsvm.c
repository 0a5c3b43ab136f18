/*
 * im_dsvm.c - DTC with Discrete Space Vector Modulation (Casadei et al. 2006 section 11): the
 * law DTC_LAW_IM_DSVM of the IM module (im_dtc.h), one im_dsvm_step() per control period, the
 * period split into three equal sub-intervals (dsvm.h).
 *
 *   estimator, speed loop, start-up and references as the IM law (im_dtc_front, im_dtc_refs)
 *   -> flux comparator on |phi_s|^2 (hyst2_sq_step), five-level torque comparator (hyst5_step)
 *   -> sector (sector.h) and, at high speed, its half (dsvm_half: twelve sectors, Casadei Fig. 28)
 *   -> speed range from the dynamic EMF w phi_s* against E1, E2 times |V_k| = 2/3 v_dc
 *      (dsvm_range; Casadei Fig. 27, eq. 15's w_k phi_s,k)
 *   -> the tables' vector for sector 1 turned to the flux's sector (dsvm_table, dsvm_rotate),
 *      its three basic vectors (dsvm_vectors; the null as V_0 or V_7, whichever the last
 *      sub-interval's legs reach with the fewer commutations, as swtab_null_choice)
 *   -> each leg's three states (dsvm_patterns, by the look-up dsvm_code_patterns): the command
 *      (LAW_OUT_THIRDS, thirds)
 *   -> the mean voltage they will apply, kept for the estimator (as the SVM schemes' v1/v2,
 *      im_pwm_out): d_x = n_x/3 (n_x the leg's "on" thirds) minus the dead time's loss, Casadei
 *      eq. 2 / Hoang eqs. 1-5 on the link measured now plus the duty's share of the per-leg drops
 *      (pwm_dv_iq, im_dtc.h) (vrec_from_legs, rounded IQ products).
 * Start-up (im_dtc.h): the radial vector V_k of the flux's sector over the whole period while the
 * flux comparator asks for more flux, the null otherwise.
 * Current limit (im_ilim, ilim.h): when the sampled current passes prot.i_lim_iq, the vector that
 * reduces |i| fastest over the whole period in place of the tables' three.
 * Mean ripple current: the estimator's resistive drop takes the current sampled at the period's
 * end (im_est.h), the mean over the period in the long run for a vector held over a period. The
 * three thirds' vectors v_1, v_2, v_3 (mean v) move the current off the straight line between the
 * samples by rho(t) = (1/(sigma L_s)) int_0^t (v - v_mean) (Casadei eq. A6 over one period: the rotor
 * flux and the back-EMF constant, the current's fast part driven through the transient inductance
 * sigma L_s), zero at both ends, rho_1 = (v_1 - v) Ts/(3 sigma L_s) and rho_2 = -(v_3 - v) Ts/(3 sigma L_s)
 * after the first and second thirds, so its mean over the period is (rho_1 + rho_2)/3 =
 * (v_1 - v_3) Ts/(9 sigma L_s). The order of the thirds is fixed (the nulls first, dsvm.h), so this
 * mean does not average out: measured, the second machine at 72 rpm and 10 % torque, ideal
 * inverter, the estimate's stator flux 7.1 mrad ahead of the machine's and the plant's torque
 * +5.9 % of T* (the resistive drop of 0.146 A per third of a whole vector, 0.43 V, against 15 V of
 * back-EMF). The voltage kept for the estimator is the mean voltage less R_s times that current,
 * per leg by linearity of Casadei eq. 2: d_x - k (s1_x - s3_x), k = r_s Ts/(9 sigma l_s).
 * Dead time (the sign rule of svm.h / vrec.h deadtime_error): a rising edge of the upper command loses T_d
 * when the phase current leaves the leg (i > 0), a falling edge gains T_d when it enters (i < 0);
 * the edges counted are those inside the period and the one at its start (the previous period's
 * last state against this one's first); the current's sign is that sampled now.
 *
 * Formats: IQ pu (dtc_base.h), duties IQ in [0, 1] before the dead-time terms (each at most
 * 3 T_d/T_s, T_d/T_s < 1/2: the sums stay within (-3/2, 5/2)), T_d/T_s IQ (svm_p.td_iq).
 * Scaling and overflow: comparisons and table look-ups; the sums above without saturation; the
 * voltage as rounded IQ products (vrec_from_legs saturates).
 */
#include "im_dtc_internal.h"

#include "sector.h"
#include "vrec.h"

/* n/3 in IQ, n = 0..3 */
static const iq_t dsvm_thirds_iq[4] = {0, IQ_FRAC(1, 3), IQ_FRAC(2, 3), IQ(1.0)};

/* The duty a leg pattern applies (file comment), from its dsvm_edges() over the leg's state in
 * the last third of the previous period and its pattern; a rising edge loses T_d with the current leaving the leg, a falling edge
 * gains T_d with the current entering it (at most two of either). */
static inline iq_t dsvm_leg_duty(uint16_t e, iq_t i_iq, iq_t td_iq)
{
    const iq_t d = dsvm_thirds_iq[e & 3U];
    if (i_iq > 0) {
        const uint16_t n = (uint16_t)((e >> 2) & 3U);
        return n == 0U ? d : (n == 1U ? d - td_iq : d - td_iq - td_iq);
    }
    if (i_iq < 0) {
        const uint16_t n = (uint16_t)((e >> 4) & 3U);
        return n == 0U ? d : (n == 1U ? d + td_iq : d + td_iq + td_iq);
    }
    return d;
}

void im_dsvm_select(im_dtc_t *c, const dtc_meas_t *m, iq_t te, uint16_t lim_vec, dtc_out_t *o)
{
    const iq_t psi_a = c->est.psi_alpha_iq, psi_b = c->est.psi_beta_iq;
    const uint16_t flux_up = hyst2_sq_step(&c->h_flux, c->psi_ref_iq, iq_sumsq_q48(psi_a, psi_b));
    const uint16_t sector = sector_sstp(psi_a, psi_b);
    /* the null the previous period's last third reaches with the fewer commutations (swtab.h:
     * V_7 from two or three upper devices on) */
    const uint16_t null_vec = (uint16_t)((uint16_t)(c->legs_1.sa + c->legs_1.sb + c->legs_1.sc) >= 2U ? 7U : 0U);
    uint16_t code, pat[3];
    int16_t level;

    if (c->magnetised == 0U) {
        /* the start-up's vector in all three thirds (code 6 of sector m: V_m V_m V_m), or the null */
        const uint16_t v = im_magn_vector(c, sector, flux_up, iq_sub(c->te_ref_iq, te), &level);
        code = v == SWTAB_NULL ? 0U : dsvm_rotate(6U, v);
    } else {
        uint16_t range = dsvm_range(c->speed_iq, c->psi_ref_iq, m->vdc_iq, 0U);
        /* the half sector (a cross product) only where the range uses it, the high speeds: there
         * dsvm_range with half_plus = 0 returns DSVM_HIGH_*_M, and its 1+ half is the next range
         * (enum dsvm_range) */
        if ((range == (uint16_t)DSVM_HIGH_CCW_M || range == (uint16_t)DSVM_HIGH_CW_M) &&
            dsvm_half(sector, psi_a, psi_b) != 0U) {
            range = (uint16_t)(range + 1U);
        }
        level = hyst5_step(&c->h_torque5, iq_sub(c->te_ref_iq, te));
        code = dsvm_rotate(dsvm_table(range, flux_up, level), sector);
    }
    if (c->i_limited != 0U) {
        /* the current limit (im_ilim, im_dsvm_step): its vector over the whole period (code 6 of
         * sector v: V_v V_v V_v) */
        code = dsvm_rotate(6U, lim_vec);
    }
    dsvm_code_patterns(code, null_vec, pat);
    {
        /* the mean voltage of the three thirds (file comment), for the estimator */
        const iq_t td = c->svm_p.td_iq;
        const uint16_t ea = dsvm_edges(c->legs_1.sa, pat[0]);
        const uint16_t eb = dsvm_edges(c->legs_1.sb, pat[1]);
        const uint16_t ec = dsvm_edges(c->legs_1.sc, pat[2]);
        /* less the resistive drop of the mean ripple current (file comment), by the leg's pattern */
        const iq_t da = dsvm_leg_duty(ea, c->i.ia_iq, td) - c->dsvm_rip_iq[pat[0] & 7U];
        const iq_t db = dsvm_leg_duty(eb, c->i.ib_iq, td) - c->dsvm_rip_iq[pat[1] & 7U];
        const iq_t dc = dsvm_leg_duty(ec, c->i.ic_iq, td) - c->dsvm_rip_iq[pat[2] & 7U];
        const iq_t vdc = fix_add32(m->vdc_iq, c->pwm_dv_iq); /* the duty's share of the drops (im_dtc.h) */
        iq_t a, b;
        o->duty_iq[0] = dsvm_thirds_iq[ea & 3U];
        o->duty_iq[1] = dsvm_thirds_iq[eb & 3U];
        o->duty_iq[2] = dsvm_thirds_iq[ec & 3U];
        vrec_from_legs(da, db, dc, &a, &b);
        c->v2_alpha_iq = c->v1_alpha_iq;
        c->v2_beta_iq = c->v1_beta_iq;
        c->v1_alpha_iq = iq_mpy(a, vdc);
        c->v1_beta_iq = iq_mpy(b, vdc);
    }
    /* the leg states of the last third, for the next period's edges and null choice (legs_2 and
     * legs_3 are the table scheme's, im_dtc_estimate) */
    c->legs_1.sa = (uint16_t)(pat[0] & 1U);
    c->legs_1.sb = (uint16_t)(pat[1] & 1U);
    c->legs_1.sc = (uint16_t)(pat[2] & 1U);
    o->thirds[0] = pat[0];
    o->thirds[1] = pat[1];
    o->thirds[2] = pat[2];
    o->vector = code;
    o->sector = sector;
    o->flux_up = flux_up;
    o->torque_dem = level;
}

void im_dsvm_step(im_dtc_t *c, const dtc_meas_t *m, dtc_out_t *o)
{
    /* 1-5. Shadow set, Clarke, stator and rotor flux from the mean voltage of the period that
     *      ends now (v2), torque, speed and speed loop (shared with im_dtc_step). */
    const iq_t te = im_dtc_front(c, m, o, IM_FRONT_PWM);
    /* 6. References: start-up, Casadei eq. 19. */
    im_dtc_refs_step(c);
    /* 7. The current limit (im_ilim: sets c->i_limited; here, not in im_dsvm_select, so that its
     *    chain and the tables' are not on one stack path), comparators, tables, the three
     *    sub-interval vectors, the voltage they apply. */
    const uint16_t lim_vec = im_ilim(c, 0U);
    im_dsvm_select(c, m, te, lim_vec, o);
    /* 8. Outputs. */
    o->sa = 0U; /* the PWM form carries the command (thirds) */
    o->sb = 0U;
    o->sc = 0U;
    im_out_report(c, o, te);
}
