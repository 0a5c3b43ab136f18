#include "swtab.h"

#include "dtc_config.h"

/* k + n modulo 6 in 1..6, for n in -3..3 given as n + 6 >= 3 (no negative modulo). */
static uint16_t swtab_rot6(uint16_t k, uint16_t n_plus_6)
{
    uint16_t r = (uint16_t)(k - 1U + n_plus_6); /* 0 .. 5 + 9 */
    while (r >= 6U) {
        r = (uint16_t)(r - 6U);
    }
    return (uint16_t)(r + 1U);
}

uint16_t swtab_sstp_basic(uint16_t sector, uint16_t flux_up, int16_t c_t)
{
    if (c_t == 0) {
        return SWTAB_NULL;
    }
    if (flux_up != 0U) {
        return c_t > 0 ? swtab_rot6(sector, 7U) : swtab_rot6(sector, 5U);  /* k+1 | k-1 */
    }
    return c_t > 0 ? swtab_rot6(sector, 8U) : swtab_rot6(sector, 4U);      /* k+2 | k-2 */
}

uint16_t swtab_sstp_st(uint16_t strategy, uint16_t sector, uint16_t flux_up, uint16_t torque_up)
{
    if (torque_up != 0U) {
        return flux_up != 0U ? swtab_rot6(sector, 7U) : swtab_rot6(sector, 8U); /* k+1 | k+2 */
    }
    switch (strategy) {
    case DTC_ST_A:
        return SWTAB_NULL;
    case DTC_ST_B:
        return flux_up != 0U ? sector : SWTAB_NULL;                            /* k | null */
    case DTC_ST_C:
        return flux_up != 0U ? sector : swtab_rot6(sector, 9U);                /* k | k+3 */
    default: /* DTC_ST_D */
        return flux_up != 0U ? swtab_rot6(sector, 5U) : swtab_rot6(sector, 4U); /* k-1 | k-2 */
    }
}

/* Hoang Table II rows in the order (1,1), (1,0), (0,1), (0,0); columns sector I..IV (swtab.h
 * swtab_fstp). */
const uint16_t swtab_fstp_table[4][4] = {
    {2U, 3U, 4U, 1U},
    {1U, 2U, 3U, 4U},
    {3U, 4U, 1U, 2U},
    {4U, 1U, 2U, 3U},
};

uint16_t swtab_null_choice(uint16_t vec, uint16_t present_vec)
{
    if (vec != SWTAB_NULL) {
        return vec;
    }
    /* Vectors with two upper switches on (2, 4, 6) and V_7 are one or zero changes from V_7. */
    switch (present_vec) {
    case 2U:
    case 4U:
    case 6U:
    case 7U:
        return 7U;
    default:
        return 0U;
    }
}

swtab_legs_t swtab_sstp_legs(uint16_t vec)
{
    /* V_0 = 000, V_1 = 100, V_2 = 110, V_3 = 010, V_4 = 011, V_5 = 001, V_6 = 101, V_7 = 111 */
    static const uint16_t mask[8] = {0U, 4U, 6U, 2U, 3U, 1U, 5U, 7U};
    return swtab_legs_of_mask(mask[vec & 7U]);
}

/* Hoang Table I, S_B S_C: V_1 = 00, V_2 = 10, V_3 = 11, V_4 = 01 (index 0 unused: V_1) (swtab.h
 * swtab_fstp_legs). */
const uint16_t swtab_fstp_mask[5] = {0U, 0U, 2U, 3U, 1U};
