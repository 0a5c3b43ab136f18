/*
 * pil_simavr_console.c - pil-simavr --console: the AVR console image (target/pil/pil_console_avr.c)
 * in simavr, its USART0 on a pseudo-terminal (docs/pil.md, "Console on the emulated target").
 *
 *   pil-simavr --console IMAGE.elf LINK [--cycles FILE] [--ram-end ADDR]
 *
 * The pseudo-terminal is raw, 8 bit, its slave device linked at LINK (as pil-console-host and
 * `dtc-sil serve --serial` make it). Runs until SIGINT or SIGTERM, then prints the RAM line
 * (pil_simavr.h), the ISR's cycles and the line's counts on stdout.
 *
 * The bridge is simavr's UART IRQs (avr_uart.h):
 *   UART_IRQ_OUTPUT    every octet the image writes to UDR0: to the pseudo-terminal;
 *   UART_IRQ_INPUT     octets from the pseudo-terminal, one per octet time of the line as the image
 *                      set it (simavr's cycles_per_byte from UBRR0 and U2X0): the host's octets
 *                      arrive at the line's rate in simulated time, once the image has enabled
 *                      its receiver (before, they wait in the pseudo-terminal);
 *   UART_IRQ_OUT_XON / _XOFF  simavr's receive FIFO (64 octets) has room / is full: no octet is
 *                      raised while it is full, none is lost in simulation.
 * The ATmega2560 itself holds two received octets and a third in the shift register (datasheet
 * 22.7.4: Data OverRun). An octet that arrives while three are unread would be lost on the part;
 * simavr's deeper FIFO keeps it, so this program counts them ("would overrun"): a session in which
 * that count is not zero runs in simavr and not on the part.
 *
 * ISR cycles: the image writes PIL_AVR_ISR_BEGIN / _END to GPIOR2 around the control ISR
 * (pil_avr_channel.h); the cycles between them are the ISR's (with --cycles FILE, each as u32
 * little-endian); an ISR longer than Timer1's period (OCR1A + 1) is counted as late.
 *
 * --ram-end ADDR gives the core data memory up to ADDR (hex): external SRAM on the part's XMEM
 * interface, for an image linked with a larger data region (the console image: 7fff, 32 KB).
 * simavr maps it as internal SRAM: no XMCRA check, no extra access cycle.
 */
#define _DEFAULT_SOURCE /* posix_openpt, ptsname, cfmakeraw, symlink */
#define _XOPEN_SOURCE 600
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <termios.h>
#include <unistd.h>

#include <avr_uart.h>
#include <sim_io.h>
#include <sim_irq.h>
#include <sim_regbit.h>

#include "pil_avr_channel.h"
#include "pil_simavr.h"

#define OCR1A_ADDR 0x88u /* OCR1AL; OCR1AH at 0x89 (ATmega2560 register summary) */
#define RX_HELD 3u       /* octets the part holds unread: the two-level buffer and the shift register */

static volatile sig_atomic_t g_stop;
static int g_master = -1;
static avr_uart_t *g_uart;
static avr_irq_t *g_irq_in;
static int g_xoff;
static uint8_t g_in[4096];
static size_t g_in_len, g_in_pos;
static uint8_t g_out[4096];
static size_t g_out_len;
static unsigned long g_rx, g_tx, g_overrun;
static uint64_t g_isr_start, g_isr_sum, g_isr_max, g_isrs, g_isr_late;
static FILE *g_cyc;

static void on_signal(int sig)
{
    (void)sig;
    g_stop = 1;
}

static void flush_out(void)
{
    while (g_out_len > 0u) {
        const ssize_t w = write(g_master, g_out, g_out_len);
        if (w <= 0) {
            return; /* the client is not reading: kept for the next octet time */
        }
        memmove(g_out, g_out + w, g_out_len - (size_t)w);
        g_out_len -= (size_t)w;
    }
}

static void on_output(avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    (void)param;
    ++g_tx;
    if (g_out_len == sizeof g_out) {
        flush_out();
    }
    if (g_out_len < sizeof g_out) {
        g_out[g_out_len++] = (uint8_t)value;
    }
    flush_out();
}

static void on_xon(avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    (void)param;
    if (value != 0u) {
        g_xoff = 0;
    }
}

static void on_xoff(avr_irq_t *irq, uint32_t value, void *param)
{
    (void)irq;
    (void)param;
    g_xoff = value != 0u;
}

/* One octet time of the line: an octet from the pseudo-terminal into the USART, the output
 * flushed. Re-armed every cycles_per_byte (at least 1). */
static avr_cycle_count_t on_octet_time(avr_t *avr, avr_cycle_count_t when, void *param)
{
    (void)param;
    if (g_in_pos == g_in_len) {
        const ssize_t r = read(g_master, g_in, sizeof g_in);
        g_in_pos = 0u;
        g_in_len = r > 0 ? (size_t)r : 0u;
    }
    if (g_in_pos < g_in_len && !g_xoff && avr_regbit_get(avr, g_uart->rxen)) {
        const unsigned unread =
            ((unsigned)g_uart->input.write + uart_fifo_fifo_size - g_uart->input.read) & (uart_fifo_fifo_size - 1u);
        if (unread >= RX_HELD) {
            ++g_overrun;
        }
        avr_raise_irq(g_irq_in, g_in[g_in_pos++]);
        ++g_rx;
    }
    flush_out();
    if (g_stop) {
        avr->state = cpu_Done;
    }
    return when + (g_uart->cycles_per_byte > 0u ? g_uart->cycles_per_byte : 1u);
}

static void on_marker(avr_t *avr, avr_io_addr_t addr, uint8_t v, void *param)
{
    const uint64_t c = pil_simavr_isr_cycles(avr, v, &g_isr_start);
    (void)addr;
    (void)param;
    if (v == PIL_AVR_ISR_END) {
        const uint32_t period = ((uint32_t)avr->data[OCR1A_ADDR + 1u] << 8 | avr->data[OCR1A_ADDR]) + 1u;
        ++g_isrs;
        g_isr_sum += c;
        g_isr_max = c > g_isr_max ? c : g_isr_max;
        g_isr_late += c > period ? 1u : 0u;
        if (g_cyc != NULL) {
            pil_simavr_put_cycles(g_cyc, (uint32_t)c);
        }
    }
}

/* The first avr_uart_t named '0' among the core's I/O modules. */
static avr_uart_t *uart0(avr_t *avr)
{
    avr_io_t *io;
    for (io = avr->io_port; io != NULL; io = io->next) {
        if (io->kind != NULL && strcmp(io->kind, "uart") == 0 && ((avr_uart_t *)io)->name == '0') {
            return (avr_uart_t *)io;
        }
    }
    return NULL;
}

/* A raw pseudo-terminal, its slave linked at link; the master (non-blocking), or -1. */
static int open_pty(const char *link, int *slave_keep)
{
    struct termios t;
    const char *name;
    const int m = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (m < 0 || grantpt(m) != 0 || unlockpt(m) != 0 || (name = ptsname(m)) == NULL) {
        return -1;
    }
    *slave_keep = open(name, O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (*slave_keep < 0 || tcgetattr(*slave_keep, &t) != 0) {
        return -1;
    }
    cfmakeraw(&t);
    if (tcsetattr(*slave_keep, TCSANOW, &t) != 0) {
        return -1;
    }
    (void)unlink(link); /* a stale link from an earlier run */
    if (symlink(name, link) != 0) {
        return -1;
    }
    return m;
}

int pil_simavr_console(int argc, char **argv)
{
    elf_firmware_t fw;
    avr_t *avr;
    uint16_t end, ramend = 0u;
    uint32_t flags = 0u;
    int k, state, slave_keep = -1;

    if (argc < 3) {
        fprintf(stderr, "usage: pil-simavr --console IMAGE.elf LINK [--cycles FILE] [--ram-end ADDR]\n");
        return 1;
    }
    for (k = 3; k < argc; ++k) {
        if (strcmp(argv[k], "--cycles") == 0 && k + 1 < argc) {
            g_cyc = fopen(argv[++k], "wb");
            if (g_cyc == NULL) {
                fprintf(stderr, "pil-simavr: %s: cannot open for writing\n", argv[k]);
                return 1;
            }
        } else if (strcmp(argv[k], "--ram-end") == 0 && k + 1 < argc) {
            ramend = (uint16_t)strtoul(argv[++k], NULL, 16);
        } else {
            fprintf(stderr, "pil-simavr: --console: unknown option %s\n", argv[k]);
            return 1;
        }
    }
    avr = pil_simavr_load(argv[1], &fw, ramend, &end);
    if (avr == NULL) {
        return 1;
    }
    g_uart = uart0(avr);
    if (g_uart == NULL) {
        fprintf(stderr, "pil-simavr: simavr's atmega2560 has no USART0\n");
        return 1;
    }
    /* no line printing, no sleep while the image polls UCSR0A: the image polls on every pass */
    avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS('0'), &flags);
    g_irq_in = avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_INPUT);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUTPUT), on_output, NULL);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XON), on_xon, NULL);
    avr_irq_register_notify(avr_io_getirq(avr, AVR_IOCTL_UART_GETIRQ('0'), UART_IRQ_OUT_XOFF), on_xoff, NULL);
    avr_register_io_write(avr, PIL_AVR_ADDR_MARKER, on_marker, NULL);
    g_master = open_pty(argv[2], &slave_keep);
    if (g_master < 0) {
        fprintf(stderr, "pil-simavr: %s: cannot make a pseudo-terminal there (%s)\n", argv[2], strerror(errno));
        return 1;
    }
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    avr_cycle_timer_register(avr, 1u, on_octet_time, NULL);
    do {
        state = avr_run(avr);
    } while (state != cpu_Done && state != cpu_Crashed && !g_stop);
    (void)unlink(argv[2]);
    pil_simavr_ram_report(avr, end);
    printf("isr: %llu calls, mean %.0f cycles, worst %llu cycles, %llu longer than the period\n",
           (unsigned long long)g_isrs, g_isrs > 0u ? (double)g_isr_sum / (double)g_isrs : 0.0,
           (unsigned long long)g_isr_max, (unsigned long long)g_isr_late);
    printf("line: %lu octets in, %lu out, %lu would overrun the part's receive buffer; an octet %llu cycles\n", g_rx,
           g_tx, g_overrun, (unsigned long long)g_uart->cycles_per_byte);
    printf("simulated: %.3f s\n", (double)avr->cycle / (double)avr->frequency);
    fflush(stdout);
    if (state == cpu_Crashed) {
        fprintf(stderr, "pil-simavr: the image crashed (pc 0x%05x)\n", (unsigned)avr->pc);
    }
    pil_simavr_release(avr, &fw);
    close(slave_keep);
    close(g_master);
    if (g_cyc != NULL && fclose(g_cyc) != 0) {
        fprintf(stderr, "pil-simavr: write failed\n");
        return 1;
    }
    return state == cpu_Crashed ? 2 : 0;
}
