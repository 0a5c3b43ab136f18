/*
 * app_pwm.c - the PWM form of the leg command (see app_pwm.h).
 */
#include "app_pwm.h"

#include "dsvm.h"
#include "svm.h"

int16_t app_pwm_period_check(const dtc_config_t *cfg, uint16_t t1pr)
{
    if (cfg->law == (uint16_t)DTC_LAW_IM_DTC &&
        (cfg->sw.scheme == (uint16_t)DTC_SCHEME_SFVC || cfg->sw.scheme == (uint16_t)DTC_SCHEME_DFOC ||
         cfg->sw.scheme == (uint16_t)DTC_SCHEME_DSVM) && (t1pr == 0U || t1pr == 0xFFFFU)) {
        return DTC_ERR_SVM;
    }
    return 0;
}

void app_pwm_encode(const dtc_out_t *o, uint16_t t1pr, hal_cmd_t *cmd)
{
    uint16_t x;
    if (o->pwm == 2U) {
        /* DSVM: one pulse per leg holding the three sub-interval states (dsvm.h, hal.h) */
        const uint16_t c23 = dsvm_c23(t1pr);
        cmd->form = (uint16_t)HAL_CMD_PWM;
        for (x = 0U; x < 3U; x++) {
            dsvm_pwm(o->thirds[x], t1pr, c23, &cmd->cmpr_up[x], &cmd->cmpr_dn[x], &cmd->act[x]);
        }
    } else if (o->pwm != 0U) {
        /* one centred pulse per leg (hal.h): compare values of the law's duties */
        cmd->form = (uint16_t)HAL_CMD_PWM;
        for (x = 0U; x < 3U; x++) {
            const uint16_t c = svm_cmpr(o->duty_iq[x], t1pr);
            cmd->cmpr_up[x] = c;
            cmd->cmpr_dn[x] = c;
            cmd->act[x] = (uint16_t)HAL_PWM_UPPER_ACTIVE_HIGH;
        }
    }
}
