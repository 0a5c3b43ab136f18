/*
 * pil_avr_channel.h - the byte channel between the AVR replay image (pil_avr_main.c) and its
 * simavr host (tools/pil/pil_simavr.c): data-space addresses of the registers and the markers.
 */
#ifndef PIL_AVR_CHANNEL_H
#define PIL_AVR_CHANNEL_H

#define PIL_AVR_ADDR_OUT 0x3EU    /* GPIOR0: output byte */
#define PIL_AVR_ADDR_IN 0x4AU     /* GPIOR1: input byte */
#define PIL_AVR_ADDR_MARKER 0x4BU /* GPIOR2: marker */

#define PIL_AVR_ISR_BEGIN 1U
#define PIL_AVR_ISR_END 2U
#define PIL_AVR_DONE 0x55U
#define PIL_AVR_ERROR_HEADER 0xE1U /* not a recording this image can replay */
#define PIL_AVR_ERROR_INIT 0xE2U   /* app_init() refused the recorded configuration */

#endif /* PIL_AVR_CHANNEL_H */
