#include "dsvm.h"

#include "swtab.h"

/* The seven switching tables for a flux in sector 1 (dsvm.h), derived in docs/firmware-core.md
 * ("DSVM") from Casadei eq. 15 and recomputed by tests/unit/test_dsvm.c: [range][flux_up][level
 * + 2], levels -2, -1, 0, +1, +2. Codes: 0 null, 1 + 3 (k - 1) + j (dsvm.h). */
static const uint16_t dsvm_tab[DSVM_NRANGE][2][5] = {
    /*            flux down                flux up */
    /* LOW    */ {{13U, 11U, 0U, 9U, 7U}, {16U, 18U, 0U, 2U, 4U}},
    /* MED +  */ {{13U, 9U, 9U, 8U, 7U}, {16U, 2U, 2U, 3U, 4U}},
    /* MED -  */ {{13U, 12U, 11U, 11U, 7U}, {16U, 17U, 18U, 18U, 4U}},
    /* HIGH+1-*/ {{13U, 8U, 7U, 7U, 6U}, {15U, 2U, 3U, 3U, 4U}},
    /* HIGH+1+*/ {{14U, 9U, 8U, 8U, 7U}, {16U, 3U, 4U, 4U, 5U}},
    /* HIGH-1-*/ {{13U, 12U, 12U, 11U, 6U}, {15U, 16U, 16U, 17U, 4U}},
    /* HIGH-1+*/ {{14U, 13U, 13U, 12U, 7U}, {16U, 17U, 17U, 18U, 5U}},
};

uint16_t dsvm_table(uint16_t range, uint16_t flux_up, int16_t level)
{
    if (range >= (uint16_t)DSVM_NRANGE || level < -2 || level > 2) {
        return 0U;
    }
    return dsvm_tab[range][flux_up != 0U ? 1U : 0U][(uint16_t)(level + 2)];
}

void dsvm_vectors(uint16_t code, uint16_t null_vec, uint16_t v[3])
{
    uint16_t k = 1U, kn, j;
    if (code == 0U || code > 18U) {
        v[0] = v[1] = v[2] = null_vec;
        return;
    }
    j = (uint16_t)(code - 1U);
    while (j >= 3U) { /* k = 1 + (code - 1) div 3, j = (code - 1) mod 3, without a division */
        j = (uint16_t)(j - 3U);
        k++;
    }
    kn = (uint16_t)(k == 6U ? 1U : k + 1U);
    v[0] = j == 2U ? kn : k;
    v[1] = j == 2U ? kn : k;
    v[2] = j == 0U ? k : (j == 1U ? kn : k);
}

uint16_t dsvm_half(uint16_t sector, iq_t psi_alpha_iq, iq_t psi_beta_iq)
{
    /* cos, sin of (k - 1) 60 deg in Q30 */
    static const int32_t cs[6][2] = {
        {1073741824, 0},          {536870912, 929887697},   {-536870912, 929887697},
        {-1073741824, 0},         {-536870912, -929887697}, {536870912, -929887697},
    };
    const uint16_t i = (uint16_t)((sector >= 1U && sector <= 6U) ? sector - 1U : 0U);
    const int64_t cross = (int64_t)cs[i][0] * (int64_t)psi_beta_iq - (int64_t)cs[i][1] * (int64_t)psi_alpha_iq;
    return (uint16_t)(cross >= 0 ? 1U : 0U);
}

uint16_t dsvm_range(iq_t speed_iq, iq_t psi_ref_iq, iq_t vdc_iq, uint16_t half_plus)
{
    const iq_t e = iq_mpy(speed_iq, psi_ref_iq);
    const iq_t ea = fix_abs32(e);
    if (ea < iq_mpy(DSVM_E1_23_IQ, vdc_iq)) {
        return (uint16_t)DSVM_LOW;
    }
    if (ea < iq_mpy(DSVM_E2_23_IQ, vdc_iq)) {
        return (uint16_t)(e > 0 ? DSVM_MED_CCW : DSVM_MED_CW);
    }
    if (e > 0) {
        return (uint16_t)(half_plus != 0U ? DSVM_HIGH_CCW_P : DSVM_HIGH_CCW_M);
    }
    return (uint16_t)(half_plus != 0U ? DSVM_HIGH_CW_P : DSVM_HIGH_CW_M);
}

void dsvm_patterns(const uint16_t v[3], uint16_t pat[3])
{
    uint16_t n;
    pat[0] = pat[1] = pat[2] = 0U;
    for (n = 0U; n < 3U; n++) {
        const swtab_legs_t l = swtab_sstp_legs(v[n]);
        pat[0] = (uint16_t)((pat[0] << 1) | l.sa);
        pat[1] = (uint16_t)((pat[1] << 1) | l.sb);
        pat[2] = (uint16_t)((pat[2] << 1) | l.sc);
    }
}
