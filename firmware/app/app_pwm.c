/*
 * app_pwm.c - the PWM form of the leg command (see app_pwm.h).
 */
#include "app_pwm.h"

int16_t app_pwm_period_check(uint16_t form, uint16_t t1pr)
{
    if (form != (uint16_t)LAW_OUT_LEGS && (t1pr == 0U || t1pr == 0xFFFFU)) {
        return DTC_ERR_SVM;
    }
    return 0;
}

void app_pwm_encode(uint16_t form, const dtc_out_t *o, uint16_t t1pr, hal_cmd_t *cmd)
{
    if (form != (uint16_t)LAW_OUT_LEGS) {
        cmd->form = (uint16_t)HAL_CMD_PWM;
        law_pwm(form, o, t1pr, cmd->cmpr_up, cmd->cmpr_dn, cmd->act);
    }
}
