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
    int64_t xs = (int64_t)x * 64;
    int64_t ys = (int64_t)y * 64;
    uint32_t turn = 0U;
    uint16_t i;

    if (x == 0 && y == 0) {
        *angle = 0U;
        *mag = 0;
        return;
    }
    if (xs < 0) { /* half turn: (x, y) -> (-x, -y) */
        xs = -xs;
        ys = -ys;
        turn = 0x80000000UL;
    }
    for (i = 0U; i < 16U; ++i) {
        const int64_t dx = ys >> i; /* arithmetic shifts of signed values: allowed in fixmath */
        const int64_t dy = xs >> i;
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
    *mag = fix_rshift_rnd64_sat32(xs * inv_gain_q24, 30U);
}
