/*
 * f2812_hal.c - hal/include/hal.h for the TMS320F2812: start-up, EV-A PWM/ISR timing, ADC, QEP,
 * protection, watchdog. Register facts: ../shared/reference/f2812-facts.md (section numbers).
 *
 * Timing of one control period k (T1 counting up/down, 50 us, f2812_board.h):
 *
 *   T1CNT = 0 (underflow) --+-- shadow CMPR1-3 and ACTRA load: the state computed in period k-1
 *                           |   becomes active (COMCONA.CLD = ACTRLD = 00, fact sheet 2.4)
 *                           +-- GPTCONA.T1TOADC = 01 starts ADC SEQ1 (fact sheet 2.10)
 *   ~1.3 us                 SEQ1 end of sequence -> ADCINT (PIE 1.6) -> f2812_adcint_isr:
 *                             app_isr(): hal_read (ia, ib, ic, Vdc, Vmid, QEP, trip)
 *                                        -> control step -> hal_write (to the shadows)
 *                             f2812_adcint_done(): SEQ1 reset, flag clear, PIE ack
 *   next T1CNT = 0          the shadows written in period k load: applied in period k+1.
 *
 * How legs are driven (fact sheet 7 step 7, item 8.4). The EV's output logic (ACTRA polarity and
 * force) sits after the dead-band unit: the TI F2812 Event Manager workshop block diagram shows
 * each compare unit feeding "PWM circuits" (which hold the dead-band unit) and then "Output
 * logic" before the PWMx pins. Forcing a pin high/low through ACTRA therefore bypasses the dead
 * band, and switching a leg from lower-on to upper-on with forced levels could shoot through.
 * So ACTRA is left at active-high (upper, odd PWM) / active-low (lower, even PWM) on every leg in
 * use, the complementary pair TI's own DMC PWM driver uses (DMC ✔), and the leg state is commanded
 * as 0 % or 100 % duty through the shadowed CMPRx (F2812_CMPR_UPPER_ON / _OFF): every transition
 * of a leg then passes through the dead-band unit (DBTCONA.EDBT1-3 all set). ACTRA 'forced low'
 * is used only to turn BOTH switches of a leg off (disabled drive, absent FSTP leg A), where no
 * dead band is needed because nothing turns on.
 *
 * Protection. PDPINTA (GPIOD0, PIE 1.1) low: the EV clears COMCONA.FCOMPOE in hardware and PWM1-6
 * go high-impedance without software (fact sheet 2.11, ~); EVAIFRA.PDPINTA latches the fault. The
 * board's gate-drive pull resistors must hold every switch off while the pins float. The binding
 * reports trip = 1 while that flag is latched or the pin is still low, and refuses to re-enable
 * the outputs until hal_trip_clear(). Over-current from the ADC samples is detected by firmware/app
 * in the same ISR, which calls hal_gates_off().
 */
#include "hal.h"

#include "f2812_board.h"
#include "f2812_hal.h"
#include "f2812_regs.h"

/* Binding state (a singleton, like the registers it shadows). */
static struct {
    uint32_t tick;  /* completed control periods */
    uint16_t isr_ticks_max; /* longest ISR end time after the period start, in HSPCLK periods */
    uint16_t fstp;  /* 1: leg A absent (four-switch board) */
    uint16_t rearm; /* 1: outputs are Hi-Z and the all-off state has been written to the shadows */
    uint32_t rearm_tick; /* the period in which it was written */
    /* PWM form with asymmetric pulses (hal.h): CMPRx also reload at the period match. */
    uint16_t split;      /* 1: COMCONA.CLD = 01 in force (reload at underflow and period match) */
    uint16_t next_split; /* what f2812_t1pint() sets CLD to for the next period */
    uint16_t hook_write; /* 1: f2812_t1pint() writes up[]/actra to the shadows */
    uint16_t up[3], dn[3]; /* compare values of the last command (CMPR1..3) */
    uint16_t actra;      /* its ACTRA */
    uint16_t relay;      /* enum hal_relay in force on GPIOB0..2 */
} s_hal;

/* ------------------------------------------------------------------------- helpers -------- */
static inline uint16_t bits_set(uint16_t reg, uint16_t mask) { return (uint16_t)(reg | mask); }
static inline uint16_t bits_clear(uint16_t reg, uint16_t mask)
{
    return (uint16_t)(reg & (uint16_t)~mask);
}

static void f2812_delay_us(uint32_t us)
{
    f2812_delay_cycles(us * (uint32_t)(F2812_SYSCLK_HZ / 1000000L));
}

void f2812_memcopy(uint16_t *dst, const uint16_t *begin, const uint16_t *end)
{
    while (begin < end) {
        *dst++ = *begin++;
    }
}

/* Register values derived in f2812_board.h, named once so init and tests agree on them. */
#define ACTRA_ALL_OFF ((uint16_t)0x0000u) /* every output forced low: every switch off */
#define ACTRA_LEG_PAIR(leg)                                                                        \
    ((uint16_t)(F2812_ACTRA_FIELD(2u * (leg) + 1u, F2812_ACT_ACTIVE_HIGH) |                       \
                F2812_ACTRA_FIELD(2u * (leg) + 2u, F2812_ACT_ACTIVE_LOW)))
/* PWM form, HAL_PWM_UPPER_ACTIVE_LOW: the pair's polarities swapped (upper off between matches). */
#define ACTRA_LEG_PAIR_INV(leg)                                                                    \
    ((uint16_t)(F2812_ACTRA_FIELD(2u * (leg) + 1u, F2812_ACT_ACTIVE_LOW) |                        \
                F2812_ACTRA_FIELD(2u * (leg) + 2u, F2812_ACT_ACTIVE_HIGH)))
#define COMCONA_RUN_NO_OUTPUTS                                                                     \
    ((uint16_t)(F2812_COMCONA_CENABLE | F2812_COMCONA_CLD_UF | F2812_COMCONA_ACTRLD_UF))
#define ADCTRL2_RUN ((uint16_t)(F2812_ADCTRL2_EVA_SOC_SEQ1 | F2812_ADCTRL2_INT_ENA_SEQ1))
#define T1CON_STOPPED                                                                              \
    ((uint16_t)(F2812_TXCON_FREE_SOFT | F2812_TXCON_TMODE_UPDOWN | F2812_TXCON_TPS(0u)))

/* ------------------------------------------------------------------ start-up steps -------- */
/* Watchdog off (again: the codestart stub already did it, fact sheet 1.4), PLL, clock dividers,
 * peripheral clocks. Fact sheet 4.3/4.4, 7 step 2. */
static void init_sysctrl(void)
{
    f2812_eallow();
    f2812_wr_protected(&f2812_sysctrl.WDCR, (uint16_t)(F2812_WDCR_WDCHK | F2812_WDCR_WDDIS));
    if ((f2812_sysctrl.PLLCR & 0x000Fu) != (uint16_t)F2812_PLLCR_DIV) {
        f2812_wr_protected(&f2812_sysctrl.PLLCR, (uint16_t)F2812_PLLCR_DIV);
        f2812_edis();
        f2812_delay_us((uint32_t)F2812_PLL_LOCK_US); /* 131072 OSCCLK cycles */
        f2812_eallow();
    }
    f2812_wr_protected(&f2812_sysctrl.HISPCP, (uint16_t)F2812_HISPCP);
    f2812_wr_protected(&f2812_sysctrl.LOSPCP, (uint16_t)F2812_LOSPCP);
    f2812_wr_protected(&f2812_sysctrl.PCLKCR,
                       (uint16_t)(F2812_PCLKCR_EVAENCLK | F2812_PCLKCR_ADCENCLK));
    f2812_edis();
}

/* Flash wait states for 150 MHz: PAGEWAIT = RANDWAIT = 5, OTPWAIT = 8, pipeline on (fact sheet 4.7,
 * WS ✔). Runs from RAM: the flash must not be read while its timing changes. */
F2812_RAMFUNC(init_flash)
static void init_flash(void)
{
    f2812_eallow();
    f2812_wr_protected(&f2812_flash.FOPT, F2812_FOPT_ENPIPE);
    f2812_wr_protected(&f2812_flash.FBANKWAIT, F2812_FBANKWAIT(5u, 5u));
    f2812_wr_protected(&f2812_flash.FOTPWAIT, (uint16_t)8u);
    f2812_edis();
    f2812_pipeline_flush();
}

/* PIE off, all enables and flags cleared, every vector to the catch-all, then the two real ISRs,
 * PIE on. TI's order (fact sheet 4.1 "TI PIE init order"). Interrupts stay globally disabled. */
static void init_pie(void)
{
    uint16_t g;
    uint16_t v;
    f2812_int_global_disable();
    f2812_piectrl.PIECTRL = 0x0000u;
    for (g = 0u; g < 12u; g++) {
        f2812_piectrl.grp[g].IER = 0x0000u;
        f2812_piectrl.grp[g].IFR = 0x0000u;
    }
    f2812_ier_ifr_clear();
    f2812_eallow();
    for (v = 0u; v < F2812_PIE_VECTORS; v++) {
        f2812_wr_protected_vec(&f2812_pievect.vec[v], f2812_unexpected_isr);
    }
    f2812_wr_protected_vec(&f2812_pievect.vec[F2812_PIE_INDEX_PDPINTA], f2812_pdpint_isr);
    f2812_wr_protected_vec(&f2812_pievect.vec[F2812_PIE_INDEX_ADCINT], f2812_adcint_isr);
    f2812_wr_protected_vec(&f2812_pievect.vec[F2812_PIE_INDEX_T1PINT], f2812_t1pint_isr);
    f2812_edis();
    f2812_piectrl.PIECTRL = F2812_PIECTRL_ENPIE;
    f2812_piectrl.PIEACK = F2812_PIEACK_ALL;
}

/* ADC: power-up sequence (DS ✔), clock, cascaded SEQ1 with five conversions in hal.h order,
 * started by EV-A, interrupt at every end of sequence (fact sheet 3.2, 3.3). */
static void init_adc(void)
{
    f2812_adc.ADCTRL3 = F2812_ADCTRL3_ADCBGRFDN;
    f2812_delay_us((uint32_t)F2812_ADC_BGR_DELAY_US);
    f2812_adc.ADCTRL3 = (uint16_t)(F2812_ADCTRL3_ADCBGRFDN | F2812_ADCTRL3_ADCPWDN |
                                   F2812_ADCTRL3_ADCCLKPS(F2812_ADCCLKPS));
    f2812_delay_us((uint32_t)F2812_ADC_PWD_DELAY_US);
    f2812_adc.ADCTRL1 = (uint16_t)(F2812_ADCTRL1_ACQ_PS(F2812_ADC_ACQ_PS) |
                                   (F2812_ADC_CPS != 0u ? F2812_ADCTRL1_CPS : 0u) |
                                   F2812_ADCTRL1_SEQ_CASC);
    f2812_adc.ADCMAXCONV = (uint16_t)(HAL_ADC_COUNT - 1);
    f2812_adc.ADCCHSELSEQ[0] = (uint16_t)((F2812_ADCIN_IA & 15u) | ((F2812_ADCIN_IB & 15u) << 4) |
                                          ((F2812_ADCIN_IC & 15u) << 8) |
                                          ((F2812_ADCIN_VDC & 15u) << 12));
    f2812_adc.ADCCHSELSEQ[1] = (uint16_t)(F2812_ADCIN_VMID & 15u);
    f2812_adc.ADCCHSELSEQ[2] = 0x0000u;
    f2812_adc.ADCCHSELSEQ[3] = 0x0000u;
    f2812_adc.ADCTRL2 = F2812_ADCTRL2_RST_SEQ1;
    f2812_adc.ADCTRL2 = ADCTRL2_RUN;
    f2812_adc.ADCST = F2812_ADCST_INT_SEQ1_CLR;
}

/* EV-A timer 1, compare units, dead band, PDPINTA. Outputs stay high-impedance (FCOMPOE = 0) with
 * every switch commanded off until the application enables them through hal_write(). */
static void init_eva_pwm(void)
{
    f2812_eva.T1CON = 0x0000u; /* stopped while configured */
    f2812_eva.EXTCONA = 0x0000u; /* INDCOE = 0: FCOMPOE/PDPINTA act on all six; QEPIE = 0 */
    f2812_eva.ACTRA = ACTRA_ALL_OFF;
    f2812_eva.CMPR1 = F2812_CMPR_UPPER_OFF;
    f2812_eva.CMPR2 = F2812_CMPR_UPPER_OFF;
    f2812_eva.CMPR3 = F2812_CMPR_UPPER_OFF;
    f2812_eva.COMCONA = COMCONA_RUN_NO_OUTPUTS;
    f2812_eva.DBTCONA = (uint16_t)(F2812_DBTCONA_DBT(F2812_DBT) | F2812_DBTCONA_DBTPS(F2812_DBTPS) |
                                   F2812_DBTCONA_EDBT1 | F2812_DBTCONA_EDBT2 | F2812_DBTCONA_EDBT3);
    f2812_eva.T1PR = F2812_T1PR;
    f2812_eva.T1CNT = 0x0000u;
    f2812_eva.GPTCONA = F2812_GPTCONA_T1TOADC_UF;
    f2812_eva.EVAIFRA = 0xFFFFu; /* write-1-to-clear every stale flag */
    f2812_eva.EVAIFRB = 0xFFFFu;
    f2812_eva.EVAIMRA = F2812_EVA_INTA_PDPINTA; /* set whichever way item 8.6 resolves */
    f2812_eva.EVAIMRB = 0x0000u;
}

/* QEP on timer 2: directional up/down, clocked by the QEP circuit (4 counts per line), wrapping in
 * 0..T2PR = 7999; CAP3 catches the index pulse QEPI1 on its rising edge (flag polled by hal_read).
 * CAPCONA[14:13] = 11 enables the QEP circuit with CAP1/2 off: item 8.3 is unresolved in TI's own
 * code (DMC writes 00, community code 11 labelled "enable QEP"); 11 is the reading under which the
 * field's name (CAPQEPN in the older TI headers) and the EVG excerpt agree. Scope/board check #3
 * in docs/f2812.md. */
static void init_eva_qep(void)
{
    f2812_eva.T2CON = 0x0000u;
    f2812_eva.T2PR = F2812_T2PR;
    f2812_eva.T2CNT = 0x0000u;
    f2812_eva.CAPCONA = 0x0000u; /* CAPRES = 0: reset capture units and FIFOs */
    f2812_eva.CAPCONA = (uint16_t)(F2812_CAPCONA_CAPRES | F2812_CAPCONA_CAP12EN_QEP |
                                   F2812_CAPCONA_CAP3EN | F2812_CAPCONA_CAP3EDGE_RISE);
    f2812_eva.EVAIFRC = 0xFFFFu;
    f2812_eva.EVAIMRC = 0x0000u;
    f2812_eva.T2CON = (uint16_t)(F2812_TXCON_FREE_SOFT | F2812_TXCON_TMODE_DIRUPDOWN |
                                 F2812_TXCON_TPS(0u) | F2812_TXCON_TCLKS_QEP | F2812_TXCON_TENABLE);
}

/* Pins to their peripheral functions, after the EV has made PWM1-6 high-impedance. */
/* The relay outputs' latches are cleared (coils off) before the pins become outputs, so they
 * never drive a stale latch; the desaturation inputs stay inputs (f2812_board.h). */
static void init_gpio(void)
{
    f2812_gpiodata.B.CLEAR = F2812_RELAY_GPB_MASK;
    f2812_eallow();
    f2812_wr_protected(&f2812_gpiomux.GPAMUX,
                       bits_set(f2812_gpiomux.GPAMUX, (uint16_t)(F2812_GPAMUX_PWM1_6 | F2812_GPAMUX_QEP)));
    f2812_wr_protected(&f2812_gpiomux.GPDMUX, bits_set(f2812_gpiomux.GPDMUX, F2812_GPDMUX_PDPINTA));
    f2812_wr_protected(&f2812_gpiomux.GPBMUX,
                       bits_clear(f2812_gpiomux.GPBMUX, (uint16_t)(F2812_RELAY_GPB_MASK | F2812_DESAT_GPB_MASK)));
    f2812_wr_protected(&f2812_gpiomux.GPBDIR,
                       (uint16_t)((f2812_gpiomux.GPBDIR | F2812_RELAY_GPB_MASK) & (uint16_t)~F2812_DESAT_GPB_MASK));
    f2812_edis();
}

/* Relay coils for enum hal_relay r (1..3: that phase's coil alone; anything else: all off), then
 * the set one (a GPIO write acts at once, not at the period boundary). */
static inline void write_relay(uint16_t r)
{
    uint16_t on = 0u;
    if (r >= (uint16_t)HAL_RELAY_A && r <= (uint16_t)HAL_RELAY_C) {
        on = (uint16_t)(1u << (F2812_RELAY_GPB_SHIFT + r - 1u));
    }
    f2812_gpiodata.B.CLEAR = (uint16_t)(F2812_RELAY_GPB_MASK & (uint16_t)~on);
    f2812_gpiodata.B.SET = on;
    s_hal.relay = on != 0u ? r : (uint16_t)HAL_RELAY_OPEN;
}

/* ----------------------------------------------------------------------- hal.h ------------ */
void hal_init(void)
{
    s_hal.tick = 0u;
    s_hal.isr_ticks_max = 0u;
    s_hal.fstp = (uint16_t)F2812_BOARD_FSTP;
    s_hal.rearm = 0u;
    s_hal.rearm_tick = 0u;
    s_hal.split = 0u;
    s_hal.next_split = 0u;
    s_hal.hook_write = 0u;
    s_hal.relay = (uint16_t)HAL_RELAY_OPEN;

    init_sysctrl();
    f2812_ramfuncs_copy(); /* before the first call into RAM code (fact sheet 1.4) */
    init_flash();
    init_pie();
    init_adc();
    init_eva_pwm();
    init_eva_qep();
    init_gpio();
    f2812_sci_init();
    f2812_spi_init();

    /* Interrupt sources: PDPINTA (1.1) and ADCINT (1.6) in PIE group 1 -> CPU INT1. Timer 1 is
     * configured but not counting, and INTM stays set: no conversion is started and no ISR runs
     * until main() calls f2812_interrupts_enable() after app_init() (hal.h: "The ISR is not
     * running yet"). */
    f2812_piectrl.grp[0].IER = (uint16_t)(F2812_PIE_INTX(1u) | F2812_PIE_INTX(6u));
    /* T1PINT (2.4) -> CPU INT2: the period-match reload of the PWM form's asymmetric pulses; its
     * EV source (EVAIMRA.T1PINT) is enabled only while hal_write() has armed it. */
    f2812_piectrl.grp[1].IER = F2812_PIE_INTX(4u);
    f2812_ier_set((uint16_t)(F2812_IER_INT1 | F2812_IER_INT2));
    f2812_eva.T1CON = T1CON_STOPPED;
}

static inline uint16_t f2812_tripped(void)
{
    uint16_t latched = (uint16_t)(f2812_eva.EVAIFRA & F2812_EVA_INTA_PDPINTA);
    uint16_t pin_low = (uint16_t)((f2812_eva.COMCONA & F2812_COMCONA_PDPINTASTATUS) == 0u);
    return (uint16_t)((latched != 0u) || (pin_low != 0u));
}

F2812_RAMFUNC(hal_read)
void hal_read(hal_meas_t *meas)
{
    uint16_t n;
    uint16_t count;
    for (n = 0u; n < (uint16_t)HAL_ADC_COUNT; n++) {
        meas->adc[n] = (uint16_t)(f2812_adc.ADCRESULT[n] >> F2812_ADC_RESULT_SHIFT);
    }
    count = f2812_eva.T2CNT;
    if (count > F2812_T2PR) {
        count = F2812_T2PR; /* cannot happen in directional mode; never report out of range */
    }
#if F2812_QEP_REVERSED
    count = (uint16_t)(F2812_T2PR - count);
#endif
    meas->qep_count = count;
    if ((f2812_eva.EVAIFRC & F2812_EVA_INTC_CAP3) != 0u) {
        meas->qep_index_count = f2812_eva.CAP3FIFO; /* T2 (QEP counter) latched at the pulse */
        f2812_eva.EVAIFRC = F2812_EVA_INTC_CAP3; /* write-1-to-clear, this flag only */
        meas->qep_index_seen = 1u;
    } else {
        meas->qep_index_seen = 0u;
    }
    meas->trip = f2812_tripped();
    {
        const uint16_t pins = (uint16_t)(f2812_gpiodata.B.DAT & F2812_DESAT_GPB_MASK);
#if F2812_DESAT_ACTIVE_LOW
        meas->desat = (uint16_t)((uint16_t)(pins ^ F2812_DESAT_GPB_MASK) >> F2812_DESAT_GPB_SHIFT);
#else
        meas->desat = (uint16_t)(pins >> F2812_DESAT_GPB_SHIFT);
#endif
    }
    meas->tick = s_hal.tick;
}

/* Every switch off from the next period boundary: all outputs forced inactive, compares parked. */
static inline void write_all_off_shadows(void)
{
    f2812_eva.CMPR1 = F2812_CMPR_UPPER_OFF;
    f2812_eva.CMPR2 = F2812_CMPR_UPPER_OFF;
    f2812_eva.CMPR3 = F2812_CMPR_UPPER_OFF;
    f2812_eva.ACTRA = ACTRA_ALL_OFF;
}

static inline uint16_t leg_cmpr(uint16_t upper_on)
{
    return (upper_on != 0u) ? F2812_CMPR_UPPER_ON : F2812_CMPR_UPPER_OFF;
}

static inline void write_cmpr(const uint16_t v[3])
{
    f2812_eva.CMPR1 = v[0];
    f2812_eva.CMPR2 = v[1];
    f2812_eva.CMPR3 = v[2];
}

/* The period-match interrupt (EVAIMRA.T1PINT) is enabled only while f2812_t1pint() has work. */
static inline void t1pint_arm(uint16_t on)
{
    f2812_eva.EVAIMRA = on != 0u ? (uint16_t)(F2812_EVA_INTA_PDPINTA | F2812_EVA_INTA_T1PINT)
                                 : F2812_EVA_INTA_PDPINTA;
}

/* Leaves the period-match reload: nothing is written at the next match any more, and CLD goes
 * back to underflow-only at that match (so the all-off shadows written now load no later than
 * the next underflow, or at the match in between while CLD = 01 is still in force). */
static inline void split_cancel(void)
{
    s_hal.hook_write = 0u;
    s_hal.next_split = 0u;
    t1pint_arm((uint16_t)(s_hal.split != 0u));
}

/* Compare value of a half in the PWM form: anything above T1PR is "never matched" (T1PR + 1). */
static inline uint16_t pwm_cmpr(uint16_t v)
{
    return v > F2812_T1PR ? F2812_CMPR_UPPER_OFF : v;
}

/* The command of period k governs period k+1 (hal.h). Leg states and centred pulses: CMPRx and
 * ACTRA go to the shadows now and load at the underflow that starts k+1 (CLD = ACTRLD = 00).
 * Asymmetric pulses: CLD = 01, so a shadow loads at underflow and at period match. hal_write()
 * of period k first writes the down-count values of the command of period k-1 (they load at the
 * match in the middle of k, the pulse of k being that command's); the up-count values and ACTRA
 * of this command are written by f2812_t1pint() after that match (they load at the underflow
 * that starts k+1), which also sets CLD for k+1. Outputs that are high-impedance (after init,
 * hal_gates_off or a PDPINTA trip) are re-enabled in two steps so that they can never come back
 * driving a stale state: in period k the all-off state is written to the shadows; in a LATER
 * period (the tick has moved on, so a boundary has loaded it) FCOMPOE is set, the pins drive every
 * switch off, and the command is written, to be applied at the following boundary. A latched trip
 * blocks it all. */
F2812_RAMFUNC(hal_write)
void hal_write(const hal_cmd_t *cmd)
{
    uint16_t x;
    uint16_t asym = 0u;
    if (s_hal.split != 0u) {
        write_cmpr(s_hal.dn);
    }
    if (cmd->relay != s_hal.relay) {
        write_relay(cmd->relay); /* whatever the enable and trip: the relay is not a gate */
    }
    if ((cmd->enable == 0u) || (f2812_tripped() != 0u)) {
        write_all_off_shadows();
        s_hal.rearm = 0u;
        split_cancel();
        return;
    }
    if ((f2812_eva.COMCONA & F2812_COMCONA_FCOMPOE) == 0u) {
        if ((s_hal.rearm == 0u) || (s_hal.rearm_tick == s_hal.tick)) {
            write_all_off_shadows();
            s_hal.rearm = 1u;
            s_hal.rearm_tick = s_hal.tick;
            split_cancel();
            return;
        }
        f2812_eva.COMCONA = bits_set(f2812_eva.COMCONA, F2812_COMCONA_FCOMPOE);
        s_hal.rearm = 0u;
    }
    s_hal.actra = 0u;
    for (x = 0u; x < 3u; x++) {
        if (cmd->form == (uint16_t)HAL_CMD_PWM) {
            s_hal.up[x] = pwm_cmpr(cmd->cmpr_up[x]);
            s_hal.dn[x] = pwm_cmpr(cmd->cmpr_dn[x]);
        } else {
            const uint16_t s = x == 0u ? cmd->sa : (x == 1u ? cmd->sb : cmd->sc);
            s_hal.up[x] = leg_cmpr(s);
            s_hal.dn[x] = s_hal.up[x];
        }
        if (((x == 0u) && (s_hal.fstp != 0u)) || (s_hal.relay == (uint16_t)(x + 1u))) {
            /* Hoang et al. 2011, Fig. 1(b): phase A on the capacitor mid-point; leg A's
             * command is ignored and PWM1/PWM2 stay forced low. A phase the relay ties to the
             * mid-point after a reconfiguration: its leg likewise, both switches off. */
            s_hal.up[x] = F2812_CMPR_UPPER_OFF;
            s_hal.dn[x] = F2812_CMPR_UPPER_OFF;
            continue;
        }
        if ((cmd->form == (uint16_t)HAL_CMD_PWM) && (cmd->act[x] == (uint16_t)HAL_PWM_UPPER_ACTIVE_LOW)) {
            s_hal.actra = (uint16_t)(s_hal.actra | ACTRA_LEG_PAIR_INV(x));
        } else {
            s_hal.actra = (uint16_t)(s_hal.actra | ACTRA_LEG_PAIR(x));
        }
        if (s_hal.up[x] != s_hal.dn[x]) {
            asym = 1u;
        }
    }
    s_hal.next_split = asym;
    if (s_hal.split == 0u) {
        write_cmpr(s_hal.up);
        f2812_eva.ACTRA = s_hal.actra;
        s_hal.hook_write = 0u;
    } else {
        s_hal.hook_write = 1u;
    }
    t1pint_arm((uint16_t)((s_hal.split != 0u) || (asym != 0u)));
}

/* Period match (T1CNT = T1PR) of the PWM form's asymmetric pulses, called from f2812_t1pint_isr:
 * the up-count values and ACTRA of the command written in this period go to the shadows (they
 * load at the next underflow), and CLD is set for the next period. It must run after this
 * period's hal_write() and before the next underflow. */
void f2812_t1pint(void)
{
    if (s_hal.hook_write != 0u) {
        write_cmpr(s_hal.up);
        f2812_eva.ACTRA = s_hal.actra;
        s_hal.hook_write = 0u;
    }
    if (s_hal.next_split != s_hal.split) {
        s_hal.split = s_hal.next_split;
        f2812_eva.COMCONA = (uint16_t)((f2812_eva.COMCONA & (uint16_t)~F2812_COMCONA_CLD_MASK) |
                                       (s_hal.split != 0u ? F2812_COMCONA_CLD_UF_PR : F2812_COMCONA_CLD_UF));
    }
    t1pint_arm(s_hal.split);
}

/* In flash, not ramfuncs (the ISR path's zero-wait RAM is full): a few dozen instructions with
 * the flash wait states still end long before the next underflow, half a period away. */
F2812_INTERRUPT void f2812_t1pint_isr(void)
{
    f2812_t1pint();
    f2812_eva.EVAIFRA = F2812_EVA_INTA_T1PINT; /* write 1 to clear that flag only (2.8) */
    f2812_piectrl.PIEACK = F2812_PIEACK_GROUP2;
}

uint16_t hal_pwm_period(void) { return F2812_T1PR; }

/* Now, not at the boundary: FCOMPOE = 0 makes PWM1-6 high-impedance at once (the same mechanism
 * PDPINTA uses), then the all-off state goes to the shadows so nothing is on when outputs return. */
F2812_RAMFUNC(hal_gates_off)
void hal_gates_off(void)
{
    f2812_eva.COMCONA = bits_clear(f2812_eva.COMCONA, (uint16_t)(F2812_COMCONA_FCOMPOE | F2812_COMCONA_CLD_MASK));
    write_all_off_shadows();
    s_hal.rearm = 0u;
    s_hal.split = 0u;
    split_cancel();
}

/* Clears the latched PDPINTA flag (write 1 to that bit only, fact sheet 2.8). If the pin is still
 * low, trip stays 1 (hal_read) and the outputs stay off. */
void hal_trip_clear(void)
{
    f2812_eva.EVAIFRA = F2812_EVA_INTA_PDPINTA;
}

void hal_watchdog_service(void)
{
    f2812_eallow();
    f2812_wr_protected(&f2812_sysctrl.WDKEY, F2812_WDKEY_1);
    f2812_wr_protected(&f2812_sysctrl.WDKEY, F2812_WDKEY_2);
    f2812_edis();
}

uint16_t hal_irq_save(void) { return f2812_irq_save(); }

void hal_irq_restore(uint16_t state) { f2812_irq_restore(state); }

/* ------------------------------------------------------------------ F2812 extras ---------- */
/* Time since the period started (T1 underflow), in HSPCLK periods: T1 counts up 0..T1PR in the
 * first half of the period and down T1PR..0 in the second (GPTCONA.T1STAT, 1 = up, EVG ✔). */
static inline uint16_t period_elapsed_ticks(void)
{
    uint16_t cnt = f2812_eva.T1CNT;
    if ((f2812_eva.GPTCONA & F2812_GPTCONA_T1STAT) != 0u) {
        return cnt;
    }
    return (uint16_t)((uint16_t)(2u * F2812_T1PR) - cnt);
}

F2812_RAMFUNC(f2812_adcint_done)
void f2812_adcint_done(void)
{
    uint16_t elapsed = period_elapsed_ticks();
    if (elapsed > s_hal.isr_ticks_max) {
        s_hal.isr_ticks_max = elapsed;
    }
    s_hal.tick++;
    f2812_adc.ADCTRL2 = (uint16_t)(ADCTRL2_RUN | F2812_ADCTRL2_RST_SEQ1);
    f2812_adc.ADCST = F2812_ADCST_INT_SEQ1_CLR;
    f2812_piectrl.PIEACK = F2812_PIEACK_GROUP1;
}

/* PDPINTA: the hardware has already made the outputs high-impedance; make the software state agree
 * (shadows all-off, no re-arm) and re-arm PIE group 1 so ADCINT keeps running (the application
 * sees trip = 1 and goes to FAULT). The EV flag stays latched until hal_trip_clear(). */
F2812_RAMFUNC(f2812_pdpint_isr)
F2812_INTERRUPT void f2812_pdpint_isr(void)
{
    hal_gates_off();
    f2812_piectrl.PIEACK = F2812_PIEACK_GROUP1;
}

/* Any interrupt nobody asked for: gates off and stop; the watchdog (if started) resets the DSP. */
F2812_INTERRUPT void f2812_unexpected_isr(void)
{
    hal_gates_off();
    for (;;) {
    }
}

void f2812_set_fstp(uint16_t fstp) { s_hal.fstp = (uint16_t)(fstp != 0u); }

int16_t f2812_qep_direction(void)
{
    uint16_t up = (uint16_t)((f2812_eva.GPTCONA & F2812_GPTCONA_T2STAT) != 0u);
#if F2812_QEP_REVERSED
    up = (uint16_t)(up == 0u);
#endif
    return (up != 0u) ? (int16_t)1 : (int16_t)-1;
}

void f2812_watchdog_start(void)
{
    hal_watchdog_service();
    f2812_eallow();
    f2812_wr_protected(&f2812_sysctrl.WDCR, (uint16_t)(F2812_WDCR_WDCHK | F2812_WDCR_WDPS(F2812_WDPS)));
    f2812_edis();
}

uint16_t f2812_isr_ticks_max(void) { return s_hal.isr_ticks_max; }

/* Start of operation: SEQ1 back to CONV00 with its flag clear, timer 1 counting (its first
 * underflow starts the first conversion), then INTM = 0. */
void f2812_interrupts_enable(void)
{
    f2812_adc.ADCTRL2 = (uint16_t)(ADCTRL2_RUN | F2812_ADCTRL2_RST_SEQ1);
    f2812_adc.ADCST = F2812_ADCST_INT_SEQ1_CLR;
    f2812_eva.T1CON = (uint16_t)(T1CON_STOPPED | F2812_TXCON_TENABLE);
    f2812_int_global_enable();
}
