// pil_console_host.cpp - the host binding of the console image (target/pil/pil_console.h): the
// same drive and bench as pil_cm_console.elf in qemu, its line hal/host's SerialLine at
// PROTO_BAUD in simulated time on a pseudo-terminal linked at LINK (as `dtc-sil serve --serial`
// makes it), the ISR and a background pass once per period, paced at real time. The storage
// medium is RAM of the same geometry. Runs until SIGINT or SIGTERM.
//
//   pil-console-host LINK
#include <chrono>
#include <csignal>
#include <cstdio>
#include <exception>
#include <thread>

#include "hal_host_line.hpp"
#include "pil_console.h"
#include "proto.h"

namespace {
volatile std::sig_atomic_t g_stop = 0;
void on_signal(int) { g_stop = 1; }
constexpr double kTs = 50e-6;           // APP_ISR_PERIOD_NS
constexpr unsigned kPump = 8;           // periods between exchanges with the pseudo-terminal
} // namespace

extern "C" uint16_t hal_irq_save(void) { return 0U; } // the ISR and the background alternate here
extern "C" void hal_irq_restore(uint16_t state) { (void)state; }

int main(int argc, char** argv)
{
    if (argc != 2) {
        std::fprintf(stderr, "usage: pil-console-host LINK\n");
        return 2;
    }
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    try {
        hal_host::SerialLine line(static_cast<double>(PROTO_BAUD), kTs);
        hal_host::StoreMedium medium(PIL_CONSOLE_STORE_WORDS, PIL_CONSOLE_STORE_ERASE,
                                     hal_host::StoreMedium::Kind::eeprom);
        hal_host::PtyLink pty(argv[1]);
        line.activate();
        medium.activate();
        if (pil_console_init() != 0) {
            std::fprintf(stderr, "pil-console-host: app_init refused the board configuration\n");
        }
        const auto t0 = std::chrono::steady_clock::now();
        for (std::uint64_t k = 0; g_stop == 0; ++k) {
            if (k % kPump == 0u) {
                pty.pump(line);
                const auto due = t0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                          std::chrono::duration<double>(static_cast<double>(k) * kTs));
                if (due > std::chrono::steady_clock::now() + std::chrono::microseconds(200)) {
                    std::this_thread::sleep_until(due);
                }
            }
            pil_console_isr();
            pil_console_background();
            line.advance_period();
        }
        line.deactivate();
        medium.deactivate();
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pil-console-host: %s\n", e.what());
        return 1;
    }
    return 0;
}
