/* fix_polar.c - CORDIC angle and magnitude (fixmath.h). Its own translation unit, so that an image
 * whose control law does not call it does not link it (a linker pulls archive members, not
 * functions: the F2812 budget, hal/f2812/budget.sh, counts the members an image links). */
#include "fixmath.h"

/* atan(2^-i) / (2 pi) * 2^32, rounded (i = 0 .. 15). */
static const uint32_t fix_atan_q32[16] = {
    536870912UL, 316933406UL, 167458907UL, 85004756UL, 42667331UL, 21354465UL, 10679838UL,
    5340245UL,   2670163UL,   1335087UL,   667544UL,  333772UL,   166886UL,   83443UL,
    41722UL,     20861UL};

/* CORDIC micro-rotations i0 .. i1 - 1 on the state (fixmath.h fix_polar). */
static void fix_polar_iter(fix_polar_t *s, uint16_t i0, uint16_t i1)
{
    int32_t xs = s->xs, ys = s->ys;
    uint32_t turn = s->turn;
    uint16_t i;
    for (i = i0; i < i1; ++i) {
        const int32_t dx = ys >> i; /* arithmetic shifts of signed values: allowed in fixmath */
        const int32_t dy = xs >> i;
        if (ys > 0) {
            xs += dx;
            ys -= dy;
            turn += fix_atan_q32[i];
        } else {
            xs -= dx;
            ys += dy;
            turn -= fix_atan_q32[i];
        }
    }
    s->xs = xs;
    s->ys = ys;
    s->turn = turn;
}

void fix_polar_begin(iq_t x, iq_t y, fix_polar_t *s)
{
    /* |x|, |y| as unsigned: exact for INT32_MIN too */
    uint32_t ax = x < 0 ? 0U - (uint32_t)x : (uint32_t)x;
    uint32_t ay = y < 0 ? 0U - (uint32_t)y : (uint32_t)y;
    uint32_t b = ax | ay; /* its top bit is the larger magnitude's */
    uint16_t up = 0U, down = 0U;

    if (b == 0U) {
        s->xs = 0;
        s->ys = 0;
        s->turn = 0U;
        s->shift = 0U; /* (0, 0): fix_polar_end gives angle 0, magnitude 0 */
        return;
    }
    /* Scale by 2^(up - down) so that the top bit of max(|x|, |y|) is bit 28 (fixmath.h). On a
     * 64-bit GCC/Clang host the compiler's count of leading zeros gives the same shift (b != 0);
     * the portable search below is what the targets run (no count-leading-zeros in C99). */
#if FIX_WORD64 && defined(__GNUC__)
    {
        const int lz = __builtin_clz(b);
        if (lz >= 3) {
            up = (uint16_t)(lz - 3);
        } else {
            down = (uint16_t)(3 - lz);
        }
    }
#else
    while (b >= ((uint32_t)1U << 29)) { /* at most three times */
        b >>= 1;
        ++down;
    }
    if (b < ((uint32_t)1U << 13)) {
        b <<= 16;
        up = (uint16_t)(up + 16U);
    }
    if (b < ((uint32_t)1U << 21)) {
        b <<= 8;
        up = (uint16_t)(up + 8U);
    }
    if (b < ((uint32_t)1U << 25)) {
        b <<= 4;
        up = (uint16_t)(up + 4U);
    }
    if (b < ((uint32_t)1U << 27)) {
        b <<= 2;
        up = (uint16_t)(up + 2U);
    }
    if (b < ((uint32_t)1U << 28)) {
        up = (uint16_t)(up + 1U);
    }
#endif
    ax = (ax >> down) << up;
    ay = (ay >> down) << up;
    /* half turn for x < 0: (x, y) -> (-x, -y), so xs >= 0; both below 2^29 */
    s->xs = (int32_t)ax;
    s->ys = (y < 0) != (x < 0) ? -(int32_t)ay : (int32_t)ay;
    s->turn = x < 0 ? 0x80000000UL : 0U;
    s->shift = (uint16_t)(24U + up - down);
    fix_polar_iter(s, 0U, 8U);
}

void fix_polar_end(fix_polar_t *s, angle_t *angle, iq_t *mag)
{
    const int64_t inv_gain_q24 = 10188014; /* 1/K = 0.60725293510314, K = prod sqrt(1 + 4^-i), i < 16 */
    if (s->shift == 0U) {
        *angle = 0U;
        *mag = 0;
        return;
    }
    fix_polar_iter(s, 8U, 16U);
    *angle = (angle_t)((s->turn + 0x8000UL) >> 16);
    /* xs = K |v| 2^(up - down); times 1/K in Q24, back by 24 + up - down (21 .. 52) */
    *mag = fix_rshift_rnd64_sat32((int64_t)s->xs * inv_gain_q24, s->shift);
}

void fix_polar(iq_t x, iq_t y, angle_t *angle, iq_t *mag)
{
    fix_polar_t s;
    fix_polar_begin(x, y, &s);
    fix_polar_end(&s, angle, mag);
}
