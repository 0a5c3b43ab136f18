/*
 * hal_replay.c - the replay binding of hal.h (hal_replay.h).
 */
#include "hal_replay.h"

static hal_meas_t g_meas;
static pil_hal_obs_t g_obs;
static uint16_t g_t1pr;
static uint16_t g_irq_enabled = 1U;

void hal_replay_set_pwm_period(uint16_t t1pr)
{
    g_t1pr = t1pr;
}

void hal_replay_begin_isr(const hal_meas_t *m)
{
    static const pil_hal_obs_t zero;
    g_meas = *m;
    g_obs = zero;
}

const pil_hal_obs_t *hal_replay_obs(void)
{
    return &g_obs;
}

void hal_init(void)
{
    g_irq_enabled = 1U;
}

void hal_read(hal_meas_t *meas)
{
    if (meas != 0) {
        *meas = g_meas;
    }
}

void hal_write(const hal_cmd_t *cmd)
{
    if (cmd != 0) {
        g_obs.written = *cmd;
        if (g_obs.writes < 0xFFFFU) {
            g_obs.writes++;
        }
    }
}

uint16_t hal_pwm_period(void)
{
    return g_t1pr;
}

void hal_gates_off(void)
{
    if (g_obs.gates_off < 0xFFFFU) {
        g_obs.gates_off++;
    }
}

void hal_trip_clear(void)
{
    if (g_obs.trip_clear < 0xFFFFU) {
        g_obs.trip_clear++;
    }
}

void hal_watchdog_service(void)
{
}

uint16_t hal_irq_save(void)
{
    const uint16_t s = g_irq_enabled;
    g_irq_enabled = 0U;
    return s;
}

void hal_irq_restore(uint16_t state)
{
    g_irq_enabled = state;
}

/* The replay images have no serial line and no storage medium: a replayed ISR never reaches the
 * background loop's protocol. The line is unplugged (nothing read, every octet dropped). */
uint16_t hal_serial_read(uint16_t *buf, uint16_t max)
{
    (void)buf;
    (void)max;
    return 0U;
}

uint16_t hal_serial_write(const uint16_t *buf, uint16_t n)
{
    (void)buf;
    return n;
}

uint16_t hal_store_words(void)
{
    return 0U;
}

uint16_t hal_store_erase_words(void)
{
    return 1U;
}

uint16_t hal_store_read(uint16_t addr, uint16_t *buf, uint16_t n)
{
    (void)addr;
    (void)buf;
    (void)n;
    return HAL_STORE_ERR_NONE;
}

uint16_t hal_store_write(uint16_t addr, const uint16_t *buf, uint16_t n)
{
    (void)addr;
    (void)buf;
    (void)n;
    return HAL_STORE_ERR_NONE;
}

uint16_t hal_store_erase(uint16_t addr, uint16_t n)
{
    (void)addr;
    (void)n;
    return HAL_STORE_ERR_NONE;
}
