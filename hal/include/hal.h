/*
 * hal.h - the seam between the firmware and whatever it runs on.
 *
 * Bound at link time: hal/f2812 (the DSP's EV-A/ADC/QEP/PIE registers), hal/host (the C++ plant
 * model for software-in-the-loop) and test fakes each implement every function here; an
 * executable links exactly one. No function pointers, no target #ifdef in firmware/.
 *
 * The ISR exchanges data, not many small calls: once per 50 us control period the application
 * (firmware/app) calls hal_read() for one measurement struct, runs the pure control step, and
 * calls hal_write() with one command struct. The command written in period k takes effect at the
 * start of period k+1 (shadowed action/compare registers on the DSP; the host HAL emulates it).
 *
 * Units here are raw hardware units (ADC counts, encoder counts); firmware/app converts them to
 * per-unit with the calibrated offsets and gains of its configuration.
 */
#ifndef HAL_H
#define HAL_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ADC channels sampled every period (12-bit results, right-justified, 0..4095). */
enum hal_adc_channel {
    HAL_ADC_IA = 0,   /* phase A current sensor (if fitted; see the configuration) */
    HAL_ADC_IB = 1,   /* phase B current sensor */
    HAL_ADC_IC = 2,   /* phase C current sensor */
    HAL_ADC_VDC = 3,  /* DC-link voltage, negative rail to positive rail */
    HAL_ADC_VMID = 4, /* FSTP: mid-point (capacitor junction) to negative rail; 0 if not fitted */
    HAL_ADC_COUNT = 5
};

typedef struct {
    uint16_t adc[HAL_ADC_COUNT]; /* 12-bit counts, 0..4095, indexed by enum hal_adc_channel */
    uint16_t qep_count;          /* quadrature counter, 0 .. 4*lines-1, counts up for positive speed */
    uint16_t qep_index_seen;     /* 1 if the index pulse was seen since the previous read */
    uint16_t qep_index_count;    /* counter value latched by the index pulse (capture unit);
                                  * valid when qep_index_seen = 1 */
    uint16_t trip;               /* 1 if the hardware protection input (PDPINTA) has tripped */
    uint32_t tick;               /* control periods since start (wraps after 2^32 periods) */
} hal_meas_t;

typedef struct {
    uint16_t sa, sb, sc; /* leg states: 1 = upper switch on, 0 = lower switch on. The FSTP has no
                          * leg A (phase A is tied to the capacitor mid-point): sa is ignored. */
    uint16_t enable;     /* 0 = every gate off (outputs high-impedance), whatever sa/sb/sc say */
} hal_cmd_t;

/* Board bring-up (clocks, ADC, PWM, encoder, protection). The ISR is not running yet. */
void hal_init(void);

/* Latest sampled measurements of this control period. */
void hal_read(hal_meas_t *meas);

/* Switching command for the NEXT control period (applied at its boundary). */
void hal_write(const hal_cmd_t *cmd);

/* Turn every gate off now (not at the next boundary): the fault path. */
void hal_gates_off(void);

/* Clear a latched hardware trip (the application decides when that is allowed). */
void hal_trip_clear(void);

/* Service the watchdog (called from the background loop). */
void hal_watchdog_service(void);

/* Critical sections for the background loop's shadow-parameter hand-over. */
uint16_t hal_irq_save(void);
void hal_irq_restore(uint16_t state);

#ifdef __cplusplus
}
#endif

#endif /* HAL_H */
