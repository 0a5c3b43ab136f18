/*
 * app_params.c - the dispatcher's parameter commands (app_proto_param.h).
 */
#include "app_proto_param.h"

#include "proto.h"

uint16_t app_param_count(void)
{
    return 0U;
}

uint32_t app_param_table_hash(void)
{
    return 0U;
}

void app_proto_param(app_proto_t *p, const frame_t *rq, frame_t *rs)
{
    (void)p;
    rs->cmd = PROTO_ERROR;
    rs->len = 6U;
    frame_put_u16(&rs->payload[0], rq->cmd);
    frame_put_u16(&rs->payload[2], PROTO_ERR_UNKNOWN_CMD);
    frame_put_u16(&rs->payload[4], 0U);
}
