/*
 * pil_simavr.c - pil-simavr: runs an AVR image of processor-in-the-loop (docs/pil.md) in simavr,
 * linked as a library (libsimavr).
 *
 *   pil-simavr IMAGE.elf RECORDING OUTPUT [CYCLES]
 *   pil-simavr --console IMAGE.elf LINK [--cycles FILE] [--ram-end ADDR]
 *
 * Replay (the first form): the replay image (target/pil/pil_avr_main.c, cross-avr preset) streams
 * an ISR recording. The image reads the recording byte by byte from GPIOR1 and writes output
 * records to GPIOR0; this program serves and collects those bytes in the I/O callbacks, so there
 * is no UART timing and no limit from the AVR's memory. With CYCLES, it writes simavr's cycle
 * count of every app_isr() call (between the image's ISR_BEGIN and ISR_END markers) as u32
 * little-endian.
 *
 * Console (--console, pil_simavr_console.c): the console image (target/pil/pil_console_avr.c)
 * with USART0 on a pseudo-terminal linked at LINK, until SIGINT or SIGTERM.
 *
 * RAM: before the run, the RAM between the end of the image's static data (symbol _end) and RAMEND
 * is painted with PIL_SIMAVR_PAINT; after it, the lowest byte the stack changed gives the peak
 * stack depth, printed with the static size ("ram: ..." on stdout; docs/pil.md).
 *
 * Exit 0 when the image ran every ISR (console: when it was stopped by a signal); 1 usage or file
 * error; 2 the image reported an error or stopped early.
 */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sim_avr.h>
#include <sim_elf.h>
#include <sim_io.h>

#include "pil_avr_channel.h"
#include "pil_simavr.h"

static uint8_t *g_in;
static size_t g_in_len, g_in_pos;
static FILE *g_out, *g_cyc;
static int g_done, g_error, g_error_kind;
static uint64_t g_isr_start;
static unsigned long g_isrs;

static uint8_t on_read(avr_t *avr, avr_io_addr_t addr, void *param)
{
    (void)avr;
    (void)addr;
    (void)param;
    if (g_in_pos >= g_in_len) {
        g_error = 1000; /* read past the end of the recording */
        avr->state = cpu_Done;
        return 0;
    }
    return g_in[g_in_pos++];
}

static void on_write(avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param)
{
    (void)param;
    (void)addr;
    if (g_error < 0) {
        g_error = (int8_t)v; /* the error code follows the ERROR marker */
        avr->state = cpu_Done;
        return;
    }
    fputc(v, g_out);
}

static void on_marker(avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param)
{
    (void)addr;
    (void)param;
    const uint64_t c = pil_simavr_isr_cycles(avr, v, &g_isr_start);
    if (v == PIL_AVR_ISR_END) {
        ++g_isrs;
        if (g_cyc != NULL) {
            pil_simavr_put_cycles(g_cyc, (uint32_t)c);
        }
    } else if (v == PIL_AVR_DONE) {
        g_done = 1;
        avr->state = cpu_Done;
    } else if (v == PIL_AVR_ERROR_HEADER || v == PIL_AVR_ERROR_INIT) {
        g_error_kind = v;
        g_error = -1;
    }
}

uint64_t pil_simavr_isr_cycles(const avr_t *avr, uint8_t marker, uint64_t *start)
{
    if (marker == PIL_AVR_ISR_BEGIN) {
        *start = avr->cycle;
    } else if (marker == PIL_AVR_ISR_END) {
        return avr->cycle - *start;
    }
    return 0u;
}

void pil_simavr_put_cycles(FILE *f, uint32_t c)
{
    const uint8_t b[4] = {(uint8_t)c, (uint8_t)(c >> 8), (uint8_t)(c >> 16), (uint8_t)(c >> 24)};
    fwrite(b, 1, 4, f);
}

#define PIL_SIMAVR_PAINT 0xA5u

/* The first RAM address after the static data (the linker's _end), or 0 if the image has none. */
static uint16_t static_end(const elf_firmware_t *fw)
{
    uint32_t i;
    for (i = 0; i < fw->symbolcount; ++i) {
        if (strcmp(fw->symbol[i]->symbol, "_end") == 0) {
            return (uint16_t)(fw->symbol[i]->addr & 0xFFFFu); /* data addresses carry 0x800000 */
        }
    }
    return 0;
}

/* The sanitizer build's leak check: libsimavr 1.6 keeps some of its IRQ tables after
 * avr_terminate(); those are simavr's, not this program's (LeakSanitizer's suppression hook). */
const char *__lsan_default_suppressions(void);
const char *__lsan_default_suppressions(void)
{
    return "leak:libsimavr.so\n";
}

void pil_simavr_release(avr_t *avr, elf_firmware_t *fw)
{
    uint32_t i;
    avr_terminate(avr);
    free(avr);
    for (i = 0; i < fw->symbolcount; ++i) {
        free(fw->symbol[i]);
    }
    free(fw->symbol);
    free(fw->flash);
    free(fw->eeprom);
    free(fw->fuse);
    free(fw->lockbits);
}

avr_t *pil_simavr_load(const char *path, elf_firmware_t *fw, uint16_t ramend, uint16_t *end)
{
    avr_t *avr;
    memset(fw, 0, sizeof *fw);
    if (elf_read_firmware(path, fw) != 0) {
        fprintf(stderr, "pil-simavr: %s: not a readable AVR ELF image\n", path);
        return NULL;
    }
    avr = avr_make_mcu_by_name("atmega2560");
    if (avr == NULL) {
        fprintf(stderr, "pil-simavr: simavr has no atmega2560 core\n");
        return NULL;
    }
    if (ramend != 0u) {
        avr->ramend = ramend; /* a probe image linked for more RAM than the part has */
    }
    avr_init(avr);
    avr->frequency = 16000000u;
    avr->log = 0;
    fw->frequency = 16000000u;
    avr_load_firmware(avr, fw);
    *end = static_end(fw);
    if (*end != 0u && *end <= avr->ramend) {
        memset(avr->data + *end, (int)PIL_SIMAVR_PAINT, (size_t)(avr->ramend - *end + 1u));
    }
    return avr;
}

void pil_simavr_ram_report(const avr_t *avr, uint16_t end)
{
    if (end != 0u && end <= avr->ramend) {
        uint32_t low = end;
        while (low <= avr->ramend && avr->data[low] == PIL_SIMAVR_PAINT) {
            ++low;
        }
        printf("ram: static %u bytes (0x200..0x%04x), stack peak %u bytes, never used %u of %u bytes\n",
               (unsigned)(end - 0x200u), (unsigned)end, (unsigned)(avr->ramend + 1u - low),
               (unsigned)(low - end), (unsigned)(avr->ramend + 1u - 0x200u));
    }
}

int main(int argc, char **argv)
{
    elf_firmware_t fw;
    avr_t *avr;
    FILE *f;
    long n;
    int state;
    uint16_t end;

    if (argc >= 2 && strcmp(argv[1], "--console") == 0) {
        return pil_simavr_console(argc - 1, argv + 1);
    }
    if (argc != 4 && argc != 5) {
        fprintf(stderr, "usage: pil-simavr IMAGE.elf RECORDING OUTPUT [CYCLES]\n");
        return 1;
    }
    f = fopen(argv[2], "rb");
    if (f == NULL || fseek(f, 0, SEEK_END) != 0 || (n = ftell(f)) < 0) {
        fprintf(stderr, "pil-simavr: %s: cannot read\n", argv[2]);
        return 1;
    }
    rewind(f);
    g_in = malloc((size_t)n + 1u);
    g_in_len = (size_t)n;
    if (g_in == NULL || fread(g_in, 1, g_in_len, f) != g_in_len) {
        fprintf(stderr, "pil-simavr: %s: cannot read\n", argv[2]);
        return 1;
    }
    fclose(f);
    g_out = fopen(argv[3], "wb");
    if (g_out == NULL) {
        fprintf(stderr, "pil-simavr: %s: cannot open for writing\n", argv[3]);
        return 1;
    }
    if (argc == 5) {
        g_cyc = fopen(argv[4], "wb");
        if (g_cyc == NULL) {
            fprintf(stderr, "pil-simavr: %s: cannot open for writing\n", argv[4]);
            return 1;
        }
    }
    avr = pil_simavr_load(argv[1], &fw, 0u, &end);
    if (avr == NULL) {
        return 1;
    }
    avr_register_io_read(avr, PIL_AVR_ADDR_IN, on_read, NULL);
    avr_register_io_write(avr, PIL_AVR_ADDR_OUT, on_write, NULL);
    avr_register_io_write(avr, PIL_AVR_ADDR_MARKER, on_marker, NULL);
    do {
        state = avr_run(avr);
    } while (state != cpu_Done && state != cpu_Crashed);
    pil_simavr_ram_report(avr, end);
    pil_simavr_release(avr, &fw);
    free(g_in);
    if (fclose(g_out) != 0 || (g_cyc != NULL && fclose(g_cyc) != 0)) {
        fprintf(stderr, "pil-simavr: write failed\n");
        return 1;
    }
    if (!g_done) {
        if (g_error == 1000) {
            fprintf(stderr, "pil-simavr: the image read past the end of %s after %lu ISRs\n", argv[2], g_isrs);
        } else if (g_error_kind == PIL_AVR_ERROR_HEADER) {
            fprintf(stderr, "pil-simavr: %s: not a recording this image replays (pil_err %d)\n", argv[2], g_error);
        } else if (g_error_kind == PIL_AVR_ERROR_INIT) {
            fprintf(stderr, "pil-simavr: app_init() refused the recorded configuration (dtc_err %d)\n", g_error);
        } else {
            fprintf(stderr, "pil-simavr: the image stopped (state %d) after %lu ISRs\n", state, g_isrs);
        }
        return 2;
    }
    return 0;
}
