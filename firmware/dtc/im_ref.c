#include "im_ref.h"

void im_speed_reset(im_speed_t *s)
{
    s->theta_prev = 0U;
    s->primed = 0U;
    s->w_psi_iq = 0;
    s->te_filt_iq = 0;
    s->speed_iq = 0;
}
