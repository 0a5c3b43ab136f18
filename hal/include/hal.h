/*
 * hal.h - the seam between the firmware and whatever it runs on.
 *
 * Bound at link time: hal/f2812 (the DSP's EV-A/ADC/QEP/PIE registers), hal/host (the C++ plant
 * model for software-in-the-loop) and test fakes each implement every function here; an
 * executable links exactly one. No function pointers, no target #ifdef in firmware/.
 *
 * The ISR exchanges data, not many small calls: once per 50 us control period the application
 * (firmware/app) calls hal_read() for one measurement struct, runs the pure control step, and
 * calls hal_write() with one command struct. The command written in period k governs period k+1
 * (shadowed action/compare registers on the DSP; the host HAL emulates it). The command holds
 * either leg states for the whole period or, in the EV-A's terms, one pulse per leg (hal_cmd_t).
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
    uint16_t desat;              /* gate-driver desaturation (shoot-through / shorted device) outputs,
                                  * bit x = leg x (0 = A); the drivers also pull PDPINTA, so a
                                  * desaturation sets trip as well: desat says which leg and why */
    uint32_t tick;               /* control periods since start (wraps after 2^32 periods) */
} hal_meas_t;

/* The two forms of a switching command (hal_cmd_t.form). One struct, one hal_write() per period
 * and one enable/fault path for both: the leg-state form is the PWM form's 0 % / 100 % case
 * (the F2812 binding writes it as CMPRx = T1PR + 1 / 0), and form = 0 is the zero-initialised
 * default, so code that fills only sa/sb/sc/enable keeps meaning leg states. */
enum hal_cmd_form {
    HAL_CMD_LEGS = 0, /* sa, sb, sc: each leg held in one state for the whole period */
    HAL_CMD_PWM = 1   /* cmpr_up / cmpr_dn / act: one pulse per leg, from the EV-A compare units */
};

/* Output polarity of a leg's pair in the PWM form (the EV-A's ACTRA pair: upper output, lower
 * output; the dead-band unit delays the rising edge of each). */
enum hal_pwm_act {
    HAL_PWM_UPPER_ACTIVE_HIGH = 0, /* upper on from the up-count match to the down-count match */
    HAL_PWM_UPPER_ACTIVE_LOW = 1   /* upper off from the up-count match to the down-count match */
};

/*
 * PWM form, in the EV-A's own terms. Timer 1 counts continuously up and down: 0 at the start of
 * the control period (underflow), T1PR (hal_pwm_period()) at its middle (period match), 0 again
 * at its end; one count lasts ts / (2 T1PR). For leg x (CMPR1..3 = legs A, B, C):
 *   - the compare output is active while T1CNT >= the compare value in force: in the up-count
 *     half from T1CNT = cmpr_up[x] to the period match, in the down-count half from the period
 *     match to T1CNT = cmpr_dn[x]. So it is active from t_on = cmpr_up ts / (2 T1PR) to
 *     t_off = ts - cmpr_dn ts / (2 T1PR); a value 0 makes its half wholly active, a value above
 *     T1PR (never matched) wholly inactive. At most one active interval per period: one pulse.
 *   - act[x] (enum hal_pwm_act) says whether the active interval turns the upper or the lower
 *     device on; the other device is on outside it. cmpr_up = cmpr_dn: centred pulse; unequal:
 *     asymmetric pulse (DSVM's sub-intervals). Duty 0 / 1 of the upper device: cmpr = T1PR + 1
 *     / 0 with HAL_PWM_UPPER_ACTIVE_HIGH.
 *   - Hardware note (f2812-facts.md 7, ~): that a half with a value above T1PR has no compare
 *     edge in it, and the exact output at CMPR = 0, is the fact sheet's reading, not checked on a
 *     scope; the host binding implements the rule above exactly.
 * When each value takes effect (shadow registers, COMCONA.CLD / ACTRLD):
 *   - Every value of the command written in period k governs period k+1 as a whole (the same
 *     one-period delay as the leg-state form): cmpr_up and act from the underflow that starts
 *     k+1, cmpr_dn from the period match in the middle of k+1.
 *   - Centred pulses (cmpr_up = cmpr_dn on every leg) reload at underflow only (CLD = 00).
 *     Asymmetric ones reload at underflow and period match (CLD = 01): the binding writes
 *     cmpr_up to the shadows after the period match of k (f2812_t1pint(), the period-match
 *     interrupt) and cmpr_dn early in period k+1, from hal_write() of period k+1, which must
 *     therefore run before that period's match (the 50 us ISR ends within its first half).
 *   - While the period-match reload is in use, a command with enable = 0 (and a trip) is
 *     loaded at the next period match: the pulse of the period under way ends at its middle,
 *     half a period sooner than the one-period delay.
 * The FSTP has no leg A: its cmpr_up[0], cmpr_dn[0] and act[0] are ignored.
 */
typedef struct {
    uint16_t sa, sb, sc; /* leg states: 1 = upper switch on, 0 = lower switch on. The FSTP has no
                          * leg A (phase A is tied to the capacitor mid-point): sa is ignored. */
    uint16_t enable;     /* 0 = every gate off (outputs high-impedance), whatever the rest says */
    uint16_t form;       /* enum hal_cmd_form */
    uint16_t cmpr_up[3]; /* HAL_CMD_PWM: compare value in force while T1 counts up (counts) */
    uint16_t cmpr_dn[3]; /* HAL_CMD_PWM: compare value in force while T1 counts down (counts) */
    uint16_t act[3];     /* HAL_CMD_PWM: enum hal_pwm_act per leg */
    uint16_t relay;      /* fault-tolerant reconfiguration (enum hal_relay): which phase the
                          * reconfiguration relay ties to the capacitor mid-point. The relay
                          * closes after its own delay; while it is commanded the HAL holds
                          * both devices of that phase's leg off, whatever sa/sb/sc say (as the
                          * FSTP's leg A: a switching leg would short a capacitor through the
                          * relay); hal_gates_off() leaves it as it is (a closed relay with every
                          * gate off is safe). 0 = all open */
} hal_cmd_t;

/* hal_cmd_t.relay: the phase a failed leg left, tied to the mid-point (Hoang sec. I, ref. [9]:
 * the FSTP as the post-fault topology of the SSTP). */
enum hal_relay {
    HAL_RELAY_OPEN = 0,
    HAL_RELAY_A = 1,
    HAL_RELAY_B = 2,
    HAL_RELAY_C = 3
};

/* Board bring-up (clocks, ADC, PWM, encoder, protection). The ISR is not running yet. */
void hal_init(void);

/* Latest sampled measurements of this control period. */
void hal_read(hal_meas_t *meas);

/* Switching command for the NEXT control period (applied at its boundary; see hal_cmd_t). */
void hal_write(const hal_cmd_t *cmd);

/* Timer 1 period register T1PR of the PWM form: half the control period in counts. */
uint16_t hal_pwm_period(void);

/* Turn every gate off now (not at the next boundary): the fault path. */
void hal_gates_off(void);

/* Clear a latched hardware trip (the application decides when that is allowed). */
void hal_trip_clear(void);

/* Service the watchdog (called from the background loop). */
void hal_watchdog_service(void);

/* Critical sections for the background loop's shadow-parameter hand-over. */
uint16_t hal_irq_save(void);
void hal_irq_restore(uint16_t state);

/*
 * Serial line (background loop only; never called from the ISR). A non-blocking byte stream,
 * 8 data bits, no parity, one stop bit, at the binding's baud rate (F2812: SCI-A; host: the SIL's
 * line; PIL: the emulator's UART). One octet per uint16_t, in bits 7:0 (the C28x has no 8-bit
 * type); bits 15:8 of what is written are ignored, of what is read are 0. Neither call waits:
 * each moves what the line's buffers hold or accept now, and returns the count.
 */
/* Octets received since the last call, at most max, into buf. Returns how many (0..max). */
uint16_t hal_serial_read(uint16_t *buf, uint16_t max);
/* Queues up to n octets of buf for sending. Returns how many were accepted (0..n); the caller
 * keeps the rest and offers them again. */
uint16_t hal_serial_write(const uint16_t *buf, uint16_t n);

/*
 * Parameter storage medium (background loop only, drive disarmed: a write or an erase may take
 * milliseconds (F2812: an SPI EEPROM; host: a file or RAM). The bindings service the watchdog
 * while they wait). hal_store_words() 16-bit words, addressed 0..words-1.
 *   erase: prepares [addr, addr + n) for writing; what those words read afterwards is undefined
 *          until written (a flash binding erases its sectors to 0xFFFF; an EEPROM binding, whose
 *          words can be rewritten in place, need do nothing). addr and n are multiples of
 *          hal_store_erase_words().
 *   write: programs words; any word may be written with 0x0000 at any time (a flash binding
 *          can always clear bits), any other value only once after an erase.
 *   read:  reads words back.
 * A power cut during a write or an erase leaves the words of that call undefined, and only
 * those: the stored-parameter layer (firmware/comm/store.h) is built on exactly that.
 */
enum hal_store_status {
    HAL_STORE_OK = 0,
    HAL_STORE_ERR_RANGE = 1,  /* outside 0..words-1, or erase not on erase-unit boundaries */
    HAL_STORE_ERR_DEVICE = 2, /* the medium did not answer or reported a failure */
    HAL_STORE_ERR_NONE = 3    /* no medium fitted */
};
/* Size of the medium in 16-bit words (0: no medium). */
uint16_t hal_store_words(void);
/* Erase unit in words (a power of two that divides hal_store_words()). */
uint16_t hal_store_erase_words(void);
uint16_t hal_store_read(uint16_t addr, uint16_t *buf, uint16_t n);
uint16_t hal_store_write(uint16_t addr, const uint16_t *buf, uint16_t n);
uint16_t hal_store_erase(uint16_t addr, uint16_t n);

#ifdef __cplusplus
}
#endif

#endif /* HAL_H */
