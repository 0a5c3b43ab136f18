/*
 * app_pwm.h - the PWM form of the leg command (hal.h HAL_CMD_PWM): the compare values of a law
 * whose command form (law.h law_out_form) is duties (LAW_OUT_DUTY: one centred pulse per leg) or
 * DSVM's three sub-interval states (LAW_OUT_THIRDS: one pulse per leg), at the HAL's timer period
 * T1PR (hal_pwm_period(), counts), by law.h law_pwm. Stateless.
 */
#ifndef APP_PWM_H
#define APP_PWM_H

#include <stdint.h>

#include "hal.h"
#include "law.h"

/* 0 when a law of command form `form` (enum law_out_form) can run at the timer period t1pr, else
 * DTC_ERR_SVM: a law that commands a PWM form (IM SFVC, DFOC, DSVM) cannot with t1pr = 0 (the control period is not a whole
 * number of timer counts) or t1pr = 0xFFFF (no 16-bit compare value above it, so a duty of 0 or
 * 1 cannot be written: hal.h, T1PR + 1). */
int16_t app_pwm_period_check(uint16_t form, uint16_t t1pr);

/* The law's output o in the PWM form of cmd (form, cmpr_up, cmpr_dn, act of each leg) when the
 * law's form is a PWM one; cmd is left as it is for a leg-state law (LAW_OUT_LEGS).
 * Scaling: law_pwm (svm_cmpr, dsvm_pwm): compare values in 0 .. t1pr + 1. */
void app_pwm_encode(uint16_t form, const dtc_out_t *o, uint16_t t1pr, hal_cmd_t *cmd);

#endif /* APP_PWM_H */
