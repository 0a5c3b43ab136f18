/*
 * pil_replay.c - the replay loop (pil_replay.h).
 */
#include "pil_replay.h"

#include "app.h"
#include "hal_replay.h"

/* The application keeps a pointer to its configuration: it lives here for the whole replay. */
static dtc_config_t g_cfg;

void pil_replay_decode(const uint8_t *blob)
{
    pil_config_decode(blob, &g_cfg);
}

int16_t pil_replay_start(const pil_header_t *h)
{
    hal_replay_set_pwm_period(h->t1pr);
    hal_init();
    return app_init(&g_cfg);
}

int16_t pil_replay_init(const pil_header_t *h, const uint8_t *blob)
{
    pil_replay_decode(blob);
    return pil_replay_start(h);
}

void pil_replay_isr(const uint8_t *in, uint8_t *out)
{
    hal_meas_t m;
    app_status_t st;
    pil_out_t o;

    pil_in_decode(in, &m);
    hal_replay_begin_isr(&m);
    pil_target_isr_begin();
    app_isr();
    pil_target_isr_end();
    app_background();
    app_get_status(&st);
    pil_out_fill(&o, hal_replay_obs(), &st);
    pil_out_encode(&o, out);
}
