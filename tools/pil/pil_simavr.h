/*
 * pil_simavr.h - what the two modes of pil-simavr share (pil_simavr.c: the replay;
 * pil_simavr_console.c: the console on USART0).
 */
#ifndef PIL_SIMAVR_H
#define PIL_SIMAVR_H

#include <stdint.h>
#include <stdio.h>

#include <sim_avr.h>
#include <sim_elf.h>

/* An ATmega2560 at 16 MHz with the image at path loaded into it, the RAM above the image's static
 * data painted (*end: the first address after it, 0 if unknown). ramend 0 keeps the part's
 * RAMEND; another value gives the core that much data memory, for a probe image linked to a larger
 * data region (the RAM an image needs when it does not fit the part). NULL and a message on
 * stderr when the image or the core cannot be had. */
avr_t *pil_simavr_load(const char *path, elf_firmware_t *fw, uint16_t ramend, uint16_t *end);

/* The "ram: ..." line: static data, the stack's peak (the lowest byte changed since the paint)
 * and the bytes never used. */
void pil_simavr_ram_report(const avr_t *avr, uint16_t end);

/* Everything simavr allocated for avr and fw (the sanitizer build's leak check runs this program). */
void pil_simavr_release(avr_t *avr, elf_firmware_t *fw);

/* The ISR timing of the markers (pil_avr_channel.h): PIL_AVR_ISR_BEGIN keeps simavr's cycle
 * count in *start and returns 0; PIL_AVR_ISR_END returns the cycles since; any other marker 0. */
uint64_t pil_simavr_isr_cycles(const avr_t *avr, uint8_t marker, uint64_t *start);

/* One ISR's cycle count c into a CYCLES file: u32 little-endian. */
void pil_simavr_put_cycles(FILE *f, uint32_t c);

/* pil-simavr --console IMAGE.elf LINK [--cycles FILE] [--ram-end ADDR] (argv[0] is "--console"). */
int pil_simavr_console(int argc, char **argv);

#endif /* PIL_SIMAVR_H */
