#include "dsvm.h"

#include "swtab.h"

/* The seven switching tables for a flux in sector 1 (dsvm.h), derived in docs/firmware-core.md
 * ("DSVM") from Casadei eq. 15 and recomputed by tests/unit/test_dsvm.c: [range][flux_up][level
 * + 2], levels -2, -1, 0, +1, +2. Codes: 0 null, 1 + 3 (k - 1) + j (dsvm.h). */
const uint16_t dsvm_tab[DSVM_NRANGE][2][5] = {
    /*              flux down                    flux up */
    /* LOW      */ {{30U, 25U, 0U, 13U, 18U}, {36U, 31U, 0U, 7U, 12U}},
    /* MED +    */ {{30U, 13U, 13U, 16U, 18U}, {36U, 7U, 7U, 10U, 12U}},
    /* MED -    */ {{30U, 28U, 25U, 25U, 18U}, {36U, 34U, 31U, 31U, 12U}},
    /* HIGH + 1-*/ {{30U, 8U, 18U, 18U, 9U}, {27U, 10U, 10U, 3U, 12U}},
    /* HIGH + 1+*/ {{29U, 16U, 16U, 17U, 18U}, {36U, 8U, 12U, 12U, 11U}},
    /* HIGH - 1-*/ {{30U, 21U, 28U, 28U, 9U}, {27U, 36U, 36U, 26U, 12U}},
    /* HIGH - 1+*/ {{29U, 30U, 30U, 26U, 18U}, {36U, 35U, 34U, 34U, 11U}},
};

/* dsvm_vectors then dsvm_patterns of every code, packed A << 6 | B << 3 | C (octal digits), for
 * the null V_0 (row 0) and V_7 (row 1): the control path's look-up (dsvm_code_patterns);
 * tests/unit/test_dsvm.c checks it against the two functions. */
const uint16_t dsvm_pat_tab[2][DSVM_NCODE] = {
    {00, 0100, 0310, 0760, 0300, 0710, 0700, 0110, 0130, 0170, 0330, 0670,
     0770, 010, 031, 076, 030, 071, 070, 011, 013, 017, 033, 067,
     077, 01, 0103, 0607, 03, 0107, 07, 0101, 0301, 0701, 0303, 0706,
     0707},
    {0777, 0766, 0764, 0760, 0744, 0710, 0700, 0776, 0674, 0170, 0774, 0670,
     0770, 0676, 0476, 076, 0474, 071, 070, 0677, 0467, 017, 0477, 067,
     077, 0667, 0647, 0607, 0447, 0107, 07, 0767, 0746, 0701, 0747, 0706,
     0707},
};

/* For a leg's previous state s0 and pattern p (index s0 << 3 | p): the "on" thirds n, the rising
 * edges r and the falling edges f of s0 s1 s2 s3, packed n | r << 2 | f << 4 (dsvm_edges). */
const uint16_t dsvm_edge_tab[16] = {0, 5, 21, 6, 21, 26, 22, 7, 16, 21, 37, 22, 17, 22, 18, 3};

/* cos, sin of (k - 1) 60 deg in Q30 (dsvm_half) */
const int32_t dsvm_cs_q30[6][2] = {
    {1073741824, 0},          {536870912, 929887697},   {-536870912, 929887697},
    {-1073741824, 0},         {-536870912, -929887697}, {536870912, -929887697},
};

void dsvm_vectors(uint16_t code, uint16_t null_vec, uint16_t v[3])
{
    /* (a, b) of the lattice index (dsvm.h) */
    static const uint16_t ab[6][2] = {{1U, 0U}, {1U, 1U}, {1U, 2U}, {2U, 0U}, {2U, 1U}, {3U, 0U}};
    uint16_t k = 1U, kn, i, a, b, n = 0U, first, second, nf, ns;
    if (code == 0U || code > DSVM_NCODE - 1U) {
        v[0] = v[1] = v[2] = null_vec;
        return;
    }
    i = (uint16_t)(code - 1U);
    while (i >= 6U) { /* k = 1 + (code - 1) div 6, i = (code - 1) mod 6, without a division */
        i = (uint16_t)(i - 6U);
        k++;
    }
    kn = (uint16_t)(k == 6U ? 1U : k + 1U);
    a = ab[i][0];
    b = ab[i][1];
    /* the nulls first (a + b < 3), then from the vector one commutation away from the null: the
     * odd vector (one upper device on) after V_0, the even one after V_7; without a null, the
     * majority vector first */
    if (a + b < 3U) {
        const uint16_t k_odd = (uint16_t)((k & 1U) != 0U ? 1U : 0U);
        const uint16_t k_first = null_vec == 7U ? (uint16_t)(1U - k_odd) : k_odd;
        while (n < 3U - a - b) {
            v[n++] = null_vec;
        }
        first = k_first != 0U ? k : kn;
        nf = k_first != 0U ? a : b;
    } else {
        first = a >= b ? k : kn;
        nf = a >= b ? a : b;
    }
    second = first == k ? kn : k;
    ns = first == k ? b : a;
    while (nf > 0U) {
        v[n++] = first;
        nf--;
    }
    while (ns > 0U) {
        v[n++] = second;
        ns--;
    }
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
