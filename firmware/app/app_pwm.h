/*
 * app_pwm.h - the PWM form of the leg command (hal.h HAL_CMD_PWM): the compare values of a law
 * that commands duties (dtc_out_t.pwm = 1: one centred pulse per leg, svm.h) or DSVM's three
 * sub-interval states (dtc_out_t.pwm = 2: one pulse per leg, dsvm.h), at the HAL's timer period
 * T1PR (hal_pwm_period(), counts). Stateless.
 */
#ifndef APP_PWM_H
#define APP_PWM_H

#include <stdint.h>

#include "dtc.h"
#include "hal.h"

/* 0 when cfg's law can run at the timer period t1pr, else DTC_ERR_SVM: a law that commands the
 * PWM form (IM schemes SFVC, DFOC, DSVM) cannot with t1pr = 0 (the control period is not a whole
 * number of timer counts) or t1pr = 0xFFFF (no 16-bit compare value above it, so a duty of 0 or
 * 1 cannot be written: hal.h, T1PR + 1). */
int16_t app_pwm_period_check(const dtc_config_t *cfg, uint16_t t1pr);

/* The law's output o in the PWM form of cmd (form, cmpr_up, cmpr_dn, act of each leg) when it
 * commands one (o->pwm != 0); cmd is left as it is for a leg-state law (o->pwm = 0).
 * Scaling: svm_cmpr and dsvm_pwm (svm.h, dsvm.h): compare values in 0 .. t1pr + 1. */
void app_pwm_encode(const dtc_out_t *o, uint16_t t1pr, hal_cmd_t *cmd);

#endif /* APP_PWM_H */
