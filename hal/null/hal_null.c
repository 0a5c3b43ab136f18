/* hal_null.c - the control half of hal.h with no hardware and no plant (hal_null.h). */
#include "hal_null.h"

hal_meas_t hal_null_meas;
uint32_t hal_null_tick;

void hal_init(void) {}
void hal_read(hal_meas_t *m)
{
    *m = hal_null_meas;
    m->tick = hal_null_tick;
}
void hal_write(const hal_cmd_t *cmd) { (void)cmd; }
uint16_t hal_pwm_period(void) { return HAL_NULL_T1PR; }
void hal_gates_off(void) {}
void hal_trip_clear(void) {}
void hal_watchdog_service(void) {}
uint16_t hal_irq_save(void) { return 0U; }
void hal_irq_restore(uint16_t state) { (void)state; }
