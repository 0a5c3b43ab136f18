/*
 * capture.h - triggered capture of firmware quantities at the control rate (as TI's DLOG on this
 * DSP family): up to CAPTURE_CHANNELS channels of int32, every ISR period or one in `decim`,
 * with a pre-trigger history, triggered by a level or an edge of a channel, by a fault, or at
 * once.
 *
 * Who does what.
 *   - The application binds each quantity it can offer to the variable that holds it
 *     (capture_bind / capture_bind_u16, at init): the capture reads through those pointers, so
 *     the ISR passes nothing per quantity.
 *   - The background loop sets a capture up (capture_setup: channels, length, pre-trigger,
 *     decimation, trigger; it arms it), polls capture_state() and reads the samples out
 *     (capture_read) once the capture is CAPTURE_DONE. It writes the state last, and the ISR
 *     preempts the background, never the reverse: the ISR sees a set-up either whole or not at all.
 *   - The ISR calls capture_isr() once per period after the control step. Off or done, that is
 *     one load and one compare (an inline test of `state`); armed, one sample of `count` values
 *     per `decim` periods into a ring, and a trigger test.
 *
 * Buffer. CAPTURE_BUF_WORDS32 int32 values shared by the channels: count * samples <= it. The
 * default, 512 values, is 1024 16-bit words of C28x RAM (2 KiB): 4 channels x 128 samples (6.4 ms
 * at the 50 us ISR rate, decim 1; decimate for longer windows), or 1 channel x 512. Why 512: on
 * the F2812 the only zero-wait RAM left beside the PM image is the part of H0 that the fixed-point
 * core and the application leave free, about 1800 words by the pessimistic size estimate
 * (hal/f2812/budget.sh prints it), and the frame decoder (about 390 words) and the fault log
 * (about 230) need a place there too; .ebss (1K words) is half full with the controller state.
 * Override with -DCAPTURE_BUF_WORDS32=N (at most 16384: indices are 16 bits).
 *
 * Formats. A channel holds its quantity's raw firmware value: per-unit IQ (int32, FIX_IQ_Q = 24,
 * fixmath.h) for currents, fluxes, torques, speeds and voltages; a plain integer for the sector
 * and the vector. Copied, never scaled: the host converts with the configuration's bases.
 */
#ifndef CAPTURE_H
#define CAPTURE_H

#include <stdint.h>

#define CAPTURE_CHANNELS 4u
#ifndef CAPTURE_BUF_WORDS32
#define CAPTURE_BUF_WORDS32 512u
#endif
#if CAPTURE_BUF_WORDS32 < CAPTURE_CHANNELS || CAPTURE_BUF_WORDS32 > 16384u
#error "CAPTURE_BUF_WORDS32 must be in 4..16384"
#endif

/* The quantities a channel can capture. The name after each is the column of the SIL trace (and
 * of the console's capture.csv) with the same quantity, in SI there, per-unit here. */
enum capture_quantity {
    CAPTURE_Q_I_A = 0,           /* i_a_a: phase A current, iq pu */
    CAPTURE_Q_I_B = 1,           /* i_b_a */
    CAPTURE_Q_I_C = 2,           /* i_c_a */
    CAPTURE_Q_PSI_ALPHA_EST = 3, /* psi_alpha_est_wb: estimated stator flux, alpha */
    CAPTURE_Q_PSI_BETA_EST = 4,  /* psi_beta_est_wb */
    CAPTURE_Q_TORQUE_EST = 5,    /* torque_est_nm: estimated torque */
    CAPTURE_Q_SPEED = 6,         /* speed_rpm: measured speed */
    CAPTURE_Q_SPEED_REF = 7,     /* speed_ref_rpm */
    CAPTURE_Q_TORQUE_REF = 8,    /* torque_ref_nm: torque reference in force */
    CAPTURE_Q_PSI_REF = 9,       /* psi_ref_wb: flux reference in force */
    CAPTURE_Q_VDC = 10,          /* vdc_v: DC-link voltage */
    CAPTURE_Q_VMID = 11,         /* vmid_v: FSTP mid-point voltage */
    CAPTURE_Q_SECTOR = 12,       /* sector: flux sector (integer) */
    CAPTURE_Q_VECTOR = 13,       /* vector: voltage vector applied (integer) */
    CAPTURE_Q_COUNT = 14
};

/* Trigger kinds; x = the trigger channel's sample, L = level. Level and edge triggers are tested
 * on the recorded (decimated) samples; a fault is caught in any period, recorded or not. */
enum capture_trigger {
    CAPTURE_TRIG_NOW = 0,     /* the first sample with the pre-trigger history full */
    CAPTURE_TRIG_ABOVE = 1,   /* level: x >= L */
    CAPTURE_TRIG_BELOW = 2,   /* level: x <= L */
    CAPTURE_TRIG_RISING = 3,  /* edge: previous sample < L and x >= L */
    CAPTURE_TRIG_FALLING = 4, /* edge: previous sample > L and x <= L */
    CAPTURE_TRIG_FAULT = 5,   /* a fault reported to capture_isr() */
    CAPTURE_TRIG_COUNT = 6
};

/* States. Active ones are >= CAPTURE_ARMED, so the ISR's test is one compare. */
enum capture_state {
    CAPTURE_OFF = 0,
    CAPTURE_DONE = 1,      /* samples ready for capture_read() */
    CAPTURE_ARMED = 2,     /* recording the pre-trigger history, testing the trigger */
    CAPTURE_TRIGGERED = 3  /* recording the samples after the trigger */
};

/* capture_setup results. */
enum capture_err {
    CAPTURE_OK = 0,
    CAPTURE_ERR_COUNT = 1,    /* count not in 1..CAPTURE_CHANNELS */
    CAPTURE_ERR_QUANTITY = 2, /* a quantity unknown or not bound */
    CAPTURE_ERR_SAMPLES = 3,  /* samples 0, or count * samples > CAPTURE_BUF_WORDS32 */
    CAPTURE_ERR_PRE = 4,      /* pre >= samples */
    CAPTURE_ERR_DECIM = 5,    /* decim 0 */
    CAPTURE_ERR_TRIGGER = 6   /* unknown trigger, or trigger channel >= count */
};

typedef struct {
    const volatile int32_t *p32;  /* the variable, if an int32 */
    const volatile uint16_t *p16; /* the variable, if a uint16 (sector, vector) */
} capture_src_t;

typedef struct {
    uint16_t count;                     /* channels, 1..CAPTURE_CHANNELS */
    uint16_t quantity[CAPTURE_CHANNELS]; /* enum capture_quantity of channel 0..count-1 */
    uint16_t samples;                   /* samples per channel, pre-trigger ones included */
    uint16_t pre;                       /* samples before the trigger sample, < samples */
    uint16_t decim;                     /* one sample every decim ISR periods, >= 1 */
    uint16_t trigger;                   /* enum capture_trigger */
    uint16_t trig_ch;                   /* channel the level/edge trigger watches, < count */
    int32_t level;                      /* trigger level, in the channel's format */
} capture_setup_t;

typedef struct {
    volatile uint16_t state;  /* enum capture_state */
    /* The ISR's fields first: near the structure's start, reached with short offsets (C28x
     * *+XARn[0..7] words, Thumb immediate offsets). */
    uint16_t w;               /* ring offset of the next sample */
    uint16_t span;            /* count * samples: ring length in values */
    uint16_t dec_cnt;         /* ISR periods until the next sample */
    uint16_t filled;          /* samples recorded since arming, saturating at cfg.pre */
    uint16_t post;            /* samples still to record after the trigger */
    uint16_t tch;             /* the channel the trigger reads (cfg.trig_ch, 0 if none) */
    uint16_t may_fire;        /* a hit of the next recorded sample fires: 1 for a level trigger;
                                 for an edge, the previous recorded sample missed; for a fault
                                 trigger, a fault was reported since the last recorded sample */
    uint16_t lvl;             /* 1: a level trigger (now, above, below): may_fire stays 1 */
    uint16_t on_fault;        /* 1: the fault trigger: a fault reported sets may_fire */
    int32_t tmask;            /* 0 (now, above, rising, fault) or -1 (below, falling) */
    int32_t tlevel;           /* the trigger level ^ tmask; INT32_MIN for now and fault */
    uint32_t trig_tick;       /* ISR tick of the trigger sample */
    capture_setup_t cfg;      /* the set-up in force */
    capture_src_t ch[CAPTURE_CHANNELS]; /* the selected channels' sources; the unused pointer of
                                 each points to a zero of its type, so that a sample is
                                 *p32 + *p16 without a test */
    capture_src_t src[CAPTURE_Q_COUNT]; /* bindings */
    int32_t buf[CAPTURE_BUF_WORDS32];
} capture_t;

/* Init: off, nothing bound. */
void capture_init(capture_t *c);

/* Binds quantity q to an int32 (IQ) or a uint16 variable of the application. Returns 0, or 1 for
 * an unknown q. Init time. */
uint16_t capture_bind(capture_t *c, uint16_t q, const volatile int32_t *p);
uint16_t capture_bind_u16(capture_t *c, uint16_t q, const volatile uint16_t *p);

/* Background: validates and arms a capture (discarding any other). Returns enum capture_err;
 * on an error the capture is off. */
uint16_t capture_setup(capture_t *c, const capture_setup_t *s);

/* Background: back to off. */
void capture_stop(capture_t *c);

/* Background: enum capture_state. */
uint16_t capture_state(const capture_t *c);

/* Background, CAPTURE_DONE only: value of channel ch in sample k (0 = the oldest; the trigger
 * sample is k = pre). 0 when not done or out of range. */
int32_t capture_read(const capture_t *c, uint16_t k, uint16_t ch);

/* Background, CAPTURE_DONE only: ISR tick of sample 0 (trigger tick - pre * decim, modulo 2^32);
 * sample k was taken at that + k * decim. */
uint32_t capture_first_tick(const capture_t *c);

/* ISR, armed: records and tests the trigger (capture_isr's slow path). */
void capture_isr_run(capture_t *c, uint32_t tick, uint16_t fault);

/* ISR, once per period after the control step. tick: the period's ISR tick; fault: non-zero if a
 * fault latched (or is latched) in this period. */
static inline void capture_isr(capture_t *c, uint32_t tick, uint16_t fault)
{
    if (c->state >= (uint16_t)CAPTURE_ARMED) {
        capture_isr_run(c, tick, fault);
    }
}

#endif /* CAPTURE_H */
