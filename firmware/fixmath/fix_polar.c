/* fix_polar.c - CORDIC angle and magnitude (fixmath.h). Its own translation unit, so that an image
 * whose control law does not call it does not link it (a linker pulls archive members, not
 * functions: the F2812 budget, hal/f2812/budget.sh, counts the members an image links). */
#include "fixmath.h"

void fix_polar(iq_t x, iq_t y, angle_t *angle, iq_t *mag)
{
    /* atan(2^-i) / (2 pi) * 2^32, rounded (i = 0 .. 15). */
    static const uint32_t atan_q32[16] = {
        536870912UL, 316933406UL, 167458907UL, 85004756UL, 42667331UL, 21354465UL, 10679838UL,
        5340245UL,   2670163UL,   1335087UL,   667544UL,  333772UL,   166886UL,   83443UL,
        41722UL,     20861UL};
    const int64_t inv_gain_q24 = 10188014; /* 1/K = 0.60725293510314, K = prod sqrt(1 + 4^-i), i < 16 */
    /* |x|, |y| as unsigned: exact for INT32_MIN too */
    uint32_t ax = x < 0 ? 0U - (uint32_t)x : (uint32_t)x;
    uint32_t ay = y < 0 ? 0U - (uint32_t)y : (uint32_t)y;
    uint32_t b = ax | ay; /* its top bit is the larger magnitude's */
    uint16_t up = 0U, down = 0U;
    int32_t xs, ys;
    uint32_t turn = 0U;
    uint16_t i;

    if (b == 0U) {
        *angle = 0U;
        *mag = 0;
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
    xs = (int32_t)ax;
    ys = (y < 0) != (x < 0) ? -(int32_t)ay : (int32_t)ay;
    if (x < 0) {
        turn = 0x80000000UL;
    }
    for (i = 0U; i < 16U; ++i) {
        const int32_t dx = ys >> i; /* arithmetic shifts of signed values: allowed in fixmath */
        const int32_t dy = xs >> i;
        if (ys > 0) {
            xs += dx;
            ys -= dy;
            turn += atan_q32[i];
        } else {
            xs -= dx;
            ys += dy;
            turn -= atan_q32[i];
        }
    }
    *angle = (angle_t)((turn + 0x8000UL) >> 16);
    /* xs = K |v| 2^(up - down); times 1/K in Q24, back by 24 + up - down (21 .. 52) */
    *mag = fix_rshift_rnd64_sat32((int64_t)xs * inv_gain_q24, (uint16_t)(24U + up - down));
}
