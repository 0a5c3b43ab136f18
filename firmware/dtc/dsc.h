/*
 * dsc.h - Direct Self Control flux comparators (Casadei et al. 2006, section 9, Figs. 11-12).
 *
 * DSC drives the stator flux along a hexagon with one commutation per leg every half supply period
 * (six per turn), and holds the torque by inserting null vectors (a torque hysteresis comparator,
 * as in DTC; the caller does that). Section 9: each switch state follows a comparison of a flux
 * component with the reference: "when a phase flux exceeds the lower limit the corresponding
 * switch state S is set to 1; when it exceeds the upper limit S is set to 0". The paper does not
 * print which flux component commands which leg. Derivation (checked by the
 * kinematic test in test_dsc.c): the flux must run along a hexagon whose sides are parallel to the
 * active vectors (0, 60, ..., 300 degrees), so the sides' normals lie on 30 + 60 k degrees, and
 * the flux must leave a side at the vertex where the component on the next side's normal reaches
 * phi*. For counter-clockwise rotation leg x therefore follows the flux component on the axis
 * 30 degrees AHEAD of phase x's axis, and 30 degrees BEHIND it for clockwise rotation:
 *     counter-clockwise: c_a on 30, c_b on 150, c_c on 270 degrees;
 *     clockwise:         c_a on 330, c_b on 90, c_c on 210 degrees;
 *     c_x > +phi*  ->  S_x = 0,    c_x < -phi*  ->  S_x = 1,    otherwise S_x keeps its state.
 * The flux then runs along the hexagon whose sides lie at distance phi* from the origin (vertices
 * at phi* / cos 30 deg = 1.155 phi* on 0, 60, ..., 300 degrees), one leg commutating at each
 * vertex: six commutations per turn, the fewest a six-switch inverter can make. Counter-clockwise,
 * the flux between the vertices at (k-1) 60 and k 60 degrees is driven by V_{k+2} (V_3 between 0
 * and 60 degrees, V_4 between 60 and 120: the paper's "V_3 before point A, V_4 after it").
 * At a reset each leg takes the state it has on the hexagon at the flux's angle theta. Leg x
 * (comparator axis a_x) is set to 1 at the vertex where c_x reaches -phi* and to 0 at the one
 * where it reaches +phi*. Counter-clockwise those vertices are a_x + 150 and a_x + 330 degrees,
 * so S_x = 1 on the half turn centred on a_x + 240 degrees, the axis of the previous leg's
 * comparator: S_A = [c_c > 0], S_B = [c_a > 0], S_C = [c_b > 0]. Clockwise they are a_x + 210 and
 * a_x + 30 degrees, the half turn centred on a_x + 120 degrees, the next leg's axis:
 * S_A = [c_b > 0], S_B = [c_c > 0], S_C = [c_a > 0]. (The signs of the components themselves are
 * not the states: between 0 and 60 degrees counter-clockwise c_c < 0 while S_C = 0, and setting
 * S_C = 1 there gives V_4, against the flux.) At a vertex one comparand is 0 and either neighbour
 * side's vector results, both of which turn the flux forward. The machine must be magnetised
 * first (at zero flux every state is 0 and the vector is V_0).
 *
 * Formats: psi and phi* IQ pu. Scaling and overflow: each component is +-(sqrt(3)/2) psi_alpha +-
 * psi_beta/2 (or +-psi_beta) with the constants in Q31, formed in 64 bits (< 2^63) and rounded once
 * (<= 0.5 LSB + 2e-10 relative), saturated.
 */
#ifndef DSC_H
#define DSC_H

#include <stdint.h>

#include "fixmath.h"

typedef struct {
    uint16_t s[3]; /* switch states S_A, S_B, S_C (1 = upper device on) */
    uint16_t ccw;  /* 1: counter-clockwise (positive speed), 0: clockwise */
} dsc_t;

/* The three comparator components c_a, c_b, c_c of the stator flux for the rotation sense. */
void dsc_components(iq_t psi_alpha_iq, iq_t psi_beta_iq, uint16_t ccw, iq_t c[3]);
/* Sets the rotation sense and the states from the flux (see above). */
void dsc_reset(dsc_t *s, uint16_t ccw, iq_t psi_alpha_iq, iq_t psi_beta_iq);
/* One period: updates the switch states; returns the SSTP vector number 0..7 (swtab.h) they make. */
uint16_t dsc_step(dsc_t *s, iq_t psi_alpha_iq, iq_t psi_beta_iq, iq_t psi_ref_iq);

#endif /* DSC_H */
