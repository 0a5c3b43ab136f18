#include "dtc_ref.h"

#include <math.h>

void dtc_ref_clarke3(double a, double b, double c, double *alpha, double *beta)
{
    *alpha = (2.0 * a - b - c) / 3.0;
    *beta = (b - c) / sqrt(3.0);
}

void dtc_ref_table_i(int vec, double out[5])
{
    /* v_an, v_bn, v_cn, v_alpha, v_beta (x V_dc), Hoang Table I. */
    static const double t[4][5] = {
        {1.0 / 3.0, -1.0 / 6.0, -1.0 / 6.0, 1.0 / 3.0, 0.0},
        {0.0, 0.5, -0.5, 0.0, 0.57735026918962576},
        {-1.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0, -1.0 / 3.0, 0.0},
        {0.0, -0.5, 0.5, 0.0, -0.57735026918962576},
    };
    for (int k = 0; k < 5; k++) {
        out[k] = t[vec - 1][k];
    }
}

void dtc_ref_table_v(int sgn_b, int sgn_c, double vf, double *va, double *vb)
{
    const double s3 = sqrt(3.0);
    if (sgn_b < 0 && sgn_c < 0) { *va = -2.0 * vf / 3.0; *vb = 0.0; }
    else if (sgn_b < 0 && sgn_c > 0) { *va = 0.0; *vb = 2.0 * vf / s3; }
    else if (sgn_b > 0 && sgn_c < 0) { *va = 0.0; *vb = -2.0 * vf / s3; }
    else { *va = 2.0 * vf / 3.0; *vb = 0.0; }
}

void dtc_ref_table_vi(int sb, int sc, int sgn_b, int sgn_c, double vce, double vd, double *va,
                      double *vb)
{
    const double s3 = sqrt(3.0);
    /* Rows in the paper's order: signs (-,-), (-,+), (+,-), (+,+); states 00, 01, 10, 11. */
    struct row { double a, b; } r[4][4];
    r[0][0] = (struct row){-2.0 * vce / 3.0, 0.0};
    r[0][1] = (struct row){-(vd + vce) / 3.0, -(vd - vce) / s3};
    r[0][2] = (struct row){-(vd + vce) / 3.0, (vd - vce) / s3};
    r[0][3] = (struct row){-2.0 * vd / 3.0, 0.0};
    r[1][0] = (struct row){(vd - vce) / 3.0, (vd + vce) / s3};
    r[1][1] = (struct row){0.0, 2.0 * vce / s3};
    r[1][2] = (struct row){0.0, 2.0 * vd / s3};
    r[1][3] = (struct row){-(vd - vce) / 3.0, (vd + vce) / s3};
    r[2][0] = (struct row){(vd - vce) / 3.0, -(vd + vce) / s3};
    r[2][1] = (struct row){0.0, -2.0 * vd / s3};
    r[2][2] = (struct row){0.0, -2.0 * vce / s3};
    r[2][3] = (struct row){-(vd - vce) / 3.0, -(vd + vce) / s3};
    r[3][0] = (struct row){2.0 * vd / 3.0, 0.0};
    r[3][1] = (struct row){(vd + vce) / 3.0, -(vd - vce) / s3};
    r[3][2] = (struct row){(vd + vce) / 3.0, (vd - vce) / s3};
    r[3][3] = (struct row){2.0 * vce / 3.0, 0.0};
    int sg = (sgn_b > 0 ? 2 : 0) + (sgn_c > 0 ? 1 : 0);
    int st = sb * 2 + sc;
    *va = r[sg][st].a;
    *vb = r[sg][st].b;
}

void dtc_ref_pm_init(dtc_ref_pm_t *m, double rs, double ls, double psi_m, double w, double theta,
                     double ia, double ib)
{
    m->rs = rs;
    m->ls = ls;
    m->psi_m = psi_m;
    m->w = w;
    m->theta = theta;
    m->psi_a = ls * ia + psi_m * cos(theta);
    m->psi_b = ls * ib + psi_m * sin(theta);
}

void dtc_ref_pm_currents(const dtc_ref_pm_t *m, double *ia, double *ib)
{
    *ia = (m->psi_a - m->psi_m * cos(m->theta)) / m->ls;
    *ib = (m->psi_b - m->psi_m * sin(m->theta)) / m->ls;
}

double dtc_ref_pm_torque(const dtc_ref_pm_t *m)
{
    double ia, ib;
    dtc_ref_pm_currents(m, &ia, &ib);
    return m->psi_a * ib - m->psi_b * ia; /* Hoang eq. 10 in pu */
}

static void deriv(const dtc_ref_pm_t *m, double pa, double pb, double th, double va, double vb,
                  double *da, double *db)
{
    double ia = (pa - m->psi_m * cos(th)) / m->ls;
    double ib = (pb - m->psi_m * sin(th)) / m->ls;
    *da = va - m->rs * ia;
    *db = vb - m->rs * ib;
}

void dtc_ref_pm_step(dtc_ref_pm_t *m, double va, double vb, double dt, int n_sub)
{
    double h = dt / n_sub;
    for (int k = 0; k < n_sub; k++) {
        double a1, b1, a2, b2, a3, b3, a4, b4;
        double pa = m->psi_a, pb = m->psi_b, th = m->theta;
        deriv(m, pa, pb, th, va, vb, &a1, &b1);
        deriv(m, pa + 0.5 * h * a1, pb + 0.5 * h * b1, th + 0.5 * h * m->w, va, vb, &a2, &b2);
        deriv(m, pa + 0.5 * h * a2, pb + 0.5 * h * b2, th + 0.5 * h * m->w, va, vb, &a3, &b3);
        deriv(m, pa + h * a3, pb + h * b3, th + h * m->w, va, vb, &a4, &b4);
        m->psi_a = pa + h * (a1 + 2.0 * a2 + 2.0 * a3 + a4) / 6.0;
        m->psi_b = pb + h * (b1 + 2.0 * b2 + 2.0 * b3 + b4) / 6.0;
        m->theta = th + h * m->w;
    }
}

static double leg_drop(int state, double i, double vce, double vd, double ron)
{
    double vf = state == 0 ? (i >= 0 ? vd : -vce) : (i >= 0 ? vce : -vd); /* Hoang Table III */
    return vf + ron * i;                                                  /* Hoang eq. 20 */
}

void dtc_ref_fstp_inverter(int sb, int sc, double vdc, double ib, double ic, double vce,
                           double vd, double ron, double *va, double *vb)
{
    double va0 = 0.5 * vdc;
    double vb0 = sb * vdc - leg_drop(sb, ib, vce, vd, ron);
    double vc0 = sc * vdc - leg_drop(sc, ic, vce, vd, ron);
    *va = (2.0 * va0 - vb0 - vc0) / 3.0; /* Hoang eqs. 1-5: v_n0 cancels */
    *vb = (vb0 - vc0) / sqrt(3.0);
}

void dtc_ref_im_init(dtc_ref_im_t *x, double rs, double rr, double ls, double lr, double m, double w)
{
    x->rs = rs;
    x->rr = rr;
    x->ls = ls;
    x->lr = lr;
    x->m = m;
    x->w = w;
    x->psa = x->psb = x->pra = x->prb = 0.0;
}

static void im_cur(const dtc_ref_im_t *x, double psa, double psb, double pra, double prb,
                   double *isa, double *isb, double *ira, double *irb)
{
    const double d = x->ls * x->lr - x->m * x->m;
    *isa = (x->lr * psa - x->m * pra) / d;
    *isb = (x->lr * psb - x->m * prb) / d;
    *ira = (x->ls * pra - x->m * psa) / d;
    *irb = (x->ls * prb - x->m * psb) / d;
}

void dtc_ref_im_currents(const dtc_ref_im_t *x, double *ia, double *ib)
{
    double ra, rb;
    im_cur(x, x->psa, x->psb, x->pra, x->prb, ia, ib, &ra, &rb);
}

double dtc_ref_im_torque(const dtc_ref_im_t *x)
{
    double ia, ib;
    dtc_ref_im_currents(x, &ia, &ib);
    return x->psa * ib - x->psb * ia;
}

static void im_deriv(const dtc_ref_im_t *x, const double s[4], double va, double vb, double d[4])
{
    double isa, isb, ira, irb;
    im_cur(x, s[0], s[1], s[2], s[3], &isa, &isb, &ira, &irb);
    d[0] = va - x->rs * isa;
    d[1] = vb - x->rs * isb;
    d[2] = -x->rr * ira - x->w * s[3];
    d[3] = -x->rr * irb + x->w * s[2];
}

void dtc_ref_im_step(dtc_ref_im_t *x, double va, double vb, double dt, int n_sub)
{
    const double h = dt / n_sub;
    for (int k = 0; k < n_sub; k++) {
        double s0[4] = {x->psa, x->psb, x->pra, x->prb}, s1[4], k1[4], k2[4], k3[4], k4[4];
        im_deriv(x, s0, va, vb, k1);
        for (int j = 0; j < 4; j++) s1[j] = s0[j] + 0.5 * h * k1[j];
        im_deriv(x, s1, va, vb, k2);
        for (int j = 0; j < 4; j++) s1[j] = s0[j] + 0.5 * h * k2[j];
        im_deriv(x, s1, va, vb, k3);
        for (int j = 0; j < 4; j++) s1[j] = s0[j] + h * k3[j];
        im_deriv(x, s1, va, vb, k4);
        x->psa = s0[0] + h * (k1[0] + 2.0 * k2[0] + 2.0 * k3[0] + k4[0]) / 6.0;
        x->psb = s0[1] + h * (k1[1] + 2.0 * k2[1] + 2.0 * k3[1] + k4[1]) / 6.0;
        x->pra = s0[2] + h * (k1[2] + 2.0 * k2[2] + 2.0 * k3[2] + k4[2]) / 6.0;
        x->prb = s0[3] + h * (k1[3] + 2.0 * k2[3] + 2.0 * k3[3] + k4[3]) / 6.0;
    }
}

void dtc_ref_sstp_ideal(int sa, int sb, int sc, double vdc, double *va, double *vb)
{
    *va = vdc * (2.0 * sa - sb - sc) / 3.0;
    *vb = vdc * (sb - sc) / sqrt(3.0);
}
